// vm_bench: throughput of the needle-bed virtual machine.
//   BM_ValidateSheet      parse + validate (validate_stream) of a generated plain
//                         sheet held in memory: the `wearknit validate` path.
//   BM_ParseOnly          the knitout::Reader alone on the same text, to show
//                         what the machine adds.
//   BM_MachineOnly        bed::Machine::step over pre-parsed instructions.
// items_per_second = instructions per second. bench/vm_bench.sh runs this and
// the end-to-end comparison with knitout-to-dat.js (docs/vm.md).
#include <benchmark/benchmark.h>

#include <sstream>
#include <string>

#include "knitout/generate.hpp"
#include "knitout/parser.hpp"
#include "simulators/bed/machine.hpp"
#include "simulators/bed/profile.hpp"
#include "simulators/bed/validate.hpp"

namespace {

const std::string& sheet(int width, int rows) {
  static std::string text;
  static int cached_width = 0;
  static int cached_rows = 0;
  if (cached_width != width || cached_rows != rows) {
    knitout::SheetParams params;
    params.width_needles = width;
    params.rows = rows;
    text = knitout::sheet_text(params);
    cached_width = width;
    cached_rows = rows;
  }
  return text;
}

void BM_ValidateSheet(benchmark::State& state) {
  const std::string& text =
      sheet(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  std::uint64_t instructions = 0;
  for (auto _ : state) {
    std::istringstream in(text);
    knitout::DiagnosticSink sink;
    const bed::Stats stats = bed::validate_stream(in, "sheet.k", bed::default_profile(), sink);
    if (sink.has_errors()) state.SkipWithError("the sheet is invalid");
    instructions += stats.instructions;
    benchmark::DoNotOptimize(stats.loops_made);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(instructions));
  state.SetBytesProcessed(static_cast<std::int64_t>(text.size() * state.iterations()));
}
BENCHMARK(BM_ValidateSheet)->Args({500, 2000})->Args({50, 2000})->Unit(benchmark::kMillisecond);

void BM_ParseOnly(benchmark::State& state) {
  const std::string& text = sheet(500, 2000);
  std::uint64_t instructions = 0;
  for (auto _ : state) {
    std::istringstream in(text);
    knitout::DiagnosticSink sink;
    knitout::Reader reader(in, "sheet.k", sink);
    knitout::Instruction instruction;
    while (reader.next(instruction)) ++instructions;
    benchmark::DoNotOptimize(instruction);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(instructions));
}
BENCHMARK(BM_ParseOnly)->Unit(benchmark::kMillisecond);

void BM_MachineOnly(benchmark::State& state) {
  knitout::DiagnosticSink parse_sink;
  const knitout::Program program = knitout::parse_string(sheet(500, 2000), "sheet.k", parse_sink);
  std::uint64_t instructions = 0;
  for (auto _ : state) {
    knitout::DiagnosticSink sink;
    bed::Machine machine(bed::default_profile(), sink, "sheet.k", program.carriers, 10);
    for (const knitout::Instruction& instruction : program.instructions) machine.step(instruction);
    machine.finish(0);
    instructions += program.instructions.size();
    benchmark::DoNotOptimize(machine.stats().loops_made);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(instructions));
}
BENCHMARK(BM_MachineOnly)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
