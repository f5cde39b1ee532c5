// Stitch meshing speed (§6): make_stitch_mesh on a cut folder written by
// `wearknit cut` (bench/stitch_mesh.sh makes the 10 cm bunny cover).
//   stitch_mesh_bench CUT_DIR [benchmark options]
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>

#include "knitout/diagnostic.hpp"
#include "planner/pipeline.hpp"
#include "planner/stitch_mesh/stitch_mesher.hpp"

namespace {

planner::LabelledDisc g_disc;

void StitchMesh(benchmark::State& state) {
  const planner::StitchMeshParams params;
  std::size_t faces = 0;
  for (auto _ : state) {
    const planner::StitchMeshResult result = planner::make_stitch_mesh(g_disc, params);
    if (!result.problems.empty()) {
      state.SkipWithError(("stitch meshing failed: " + result.problems.front()).c_str());
      return;
    }
    faces = result.mesh.faces.size();
    benchmark::DoNotOptimize(faces);
  }
  state.counters["stitches"] = static_cast<double>(faces);
  state.counters["cut_faces"] = static_cast<double>(g_disc.faces.size());
}
BENCHMARK(StitchMesh)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (argc < 2) {
    std::fprintf(stderr, "usage: stitch_mesh_bench CUT_DIR [benchmark options]\n");
    return 2;
  }
  knitout::DiagnosticSink sink;
  const auto cut = planner::read_cut(argv[1], sink);
  if (!cut) {
    for (const auto& d : sink.diagnostics()) std::fprintf(stderr, "%s\n", format(d).c_str());
    return 1;
  }
  g_disc = planner::labelled_disc(cut->mesh);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
