// Benchmarks of the DAT backend on generated sheets (no data files): pass
// formation from a knitout stream, and the whole knitout -> DAT bytes.
// The comparison with the reference backend is bench/dat_vs_reference.sh.
#include <benchmark/benchmark.h>

#include <sstream>

#include "backends/dat/passes.hpp"
#include "backends/dat/raster.hpp"
#include "knitout/generate.hpp"

namespace {

std::string sheet(int width, int rows, knitout::SheetPattern pattern) {
  knitout::SheetParams params;
  params.width_needles = width;
  params.rows = rows;
  params.pattern = pattern;
  return knitout::sheet_text(params);
}

void run(benchmark::State& state, knitout::SheetPattern pattern, bool write) {
  const std::string text =
      sheet(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)), pattern);
  std::int64_t lines = 0;
  for (char c : text) lines += c == '\n';
  for (auto _ : state) {
    std::istringstream in(text);
    knitout::DiagnosticSink sink;
    auto passes = dat::form_passes(in, "sheet.k", sink);
    if (!passes) state.SkipWithError("sheet rejected");
    if (write) {
      auto bytes = dat::write_dat(*passes, sink);
      benchmark::DoNotOptimize(bytes);
    }
    benchmark::DoNotOptimize(passes);
  }
  state.SetItemsProcessed(state.iterations() * lines);
  state.counters["lines"] = static_cast<double>(lines);
}

void BM_FormPassesPlain(benchmark::State& state) {
  run(state, knitout::SheetPattern::Plain, false);
}
void BM_KnitoutToDatPlain(benchmark::State& state) {
  run(state, knitout::SheetPattern::Plain, true);
}
void BM_KnitoutToDatSeed(benchmark::State& state) {
  run(state, knitout::SheetPattern::Seed, true);
}

// Width x rows; the widest cases show the per-pass cost does not grow
// with pass width.
BENCHMARK(BM_FormPassesPlain)->Args({50, 400})->Args({500, 400})->Args({1000, 200});
BENCHMARK(BM_KnitoutToDatPlain)->Args({50, 400})->Args({500, 400})->Args({1000, 200});
BENCHMARK(BM_KnitoutToDatSeed)->Args({200, 200});

}  // namespace

BENCHMARK_MAIN();
