// Scheduler speed on a bunny-cover-sized synthetic stitch mesh (about 7,500
// stitches: a shaped body with short rows and two ears; see
// tests/planner/schedule_fixtures.hpp, cover_like).
//   schedule_bench [google-benchmark flags]
// BM_Schedule: grouping, needle assignment and 100 random orders on all
// cores (§7.1-7.3). BM_ScheduleAndWrite/plain|seed: the same plus knitout for
// every piece, written to files as `wearknit schedule` does.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "knitout/output_file.hpp"
#include "planner/schedule/knitout_emit.hpp"
#include "simulators/cloth/parallel.hpp"
#include "tests/planner/schedule_fixtures.hpp"

namespace {

const planner::StitchMesh& cover() {
  static const planner::StitchMesh mesh = planner::fixtures::cover_like();
  return mesh;
}

void bm_schedule(benchmark::State& state) {
  planner::ScheduleParams params;
  params.trials = 100;
  for (auto _ : state) {
    planner::Schedule s = planner::schedule(cover(), params);
    benchmark::DoNotOptimize(s.cuts);
  }
  state.counters["stitches"] = static_cast<double>(cover().faces.size());
  state.counters["threads"] = cloth::resolve_threads(params.threads);
}

void bm_schedule_and_write(benchmark::State& state, planner::StitchPattern pattern) {
  planner::ScheduleParams params;
  params.trials = 100;
  planner::EmitParams emit;
  emit.pattern = pattern;
  const auto dir = std::filesystem::temp_directory_path() / "wearknit-schedule-bench";
  std::filesystem::create_directories(dir);
  planner::PieceStats total;
  for (auto _ : state) {
    const planner::Schedule s = planner::schedule(cover(), params);
    total = {};
    for (std::size_t p = 0; p < s.pieces.size(); ++p) {
      const planner::EmittedPiece piece = planner::emit_piece(cover(), s, p, emit);
      const std::string failure =
          knitout::write_file_atomically((dir / ("piece-" + std::to_string(p + 1) + ".k")).string(),
                                         [&](std::ostream& out) { out << piece.knitout; });
      if (!failure.empty()) state.SkipWithError(failure.c_str());
      total.passes += piece.stats.passes;
      total.transfers += piece.stats.transfers;
      total.knit_time_s += piece.stats.knit_time_s;
    }
  }
  state.counters["passes"] = total.passes;
  state.counters["transfers"] = total.transfers;
  state.counters["knit_min"] = total.knit_time_s / 60;
}

}  // namespace

BENCHMARK(bm_schedule)->Name("Schedule")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bm_schedule_and_write, plain, planner::StitchPattern::Plain)
    ->Name("ScheduleAndWrite/plain")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(bm_schedule_and_write, seed, planner::StitchPattern::Seed)
    ->Name("ScheduleAndWrite/seed")
    ->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
