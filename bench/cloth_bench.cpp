// Speed of the strip-off simulation (§8.2) on the bunny cover: time steps per
// second and constraint projections per second, one and two threads, and the
// cost of building the wearer's distance field.
//   cloth_bench [--benchmark_filter=...]   (needs ../shared or $WEARKNIT_SHARED)
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

#include "planner/wearability/wearability.hpp"
#include "planner/wearability/wearability_io.hpp"

namespace {

std::filesystem::path shared_dir() {
  if (const char* env = std::getenv("WEARKNIT_SHARED"); env != nullptr && *env != '\0') return env;
  return std::filesystem::path(WEARKNIT_SOURCE_DIR).parent_path() / "shared";
}

planner::PolygonMesh load(const std::string& name) {
  knitout::DiagnosticSink sink;
  auto mesh = planner::read_stage_mesh((shared_dir() / "meshes" / name).string(), sink);
  if (!mesh) {
    knitout::print_text(std::cerr, sink.diagnostics());
    std::exit(2);
  }
  return *mesh;
}

struct Bunny {
  planner::PolygonMesh wearer = load("bunny.obj");
  planner::PolygonMesh garment = load("bunny-qd.obj");
  cloth::SignedDistanceField field{wearer.positions, wearer.faces, {}};
};

const Bunny& bunny() {
  static const Bunny instance;
  return instance;
}

void BM_SdfBuild(benchmark::State& state) {
  const auto& b = bunny();
  cloth::SdfParams params;
  params.resolution = static_cast<int>(state.range(0));
  params.threads = 2;
  for (auto _ : state) {
    cloth::SignedDistanceField field(b.wearer.positions, b.wearer.faces, params);
    benchmark::DoNotOptimize(field.value(b.wearer.positions[0]));
  }
  state.counters["nodes"] = static_cast<double>(static_cast<long>(params.resolution + 1) *
                                                (params.resolution + 1) * (params.resolution + 1));
}
BENCHMARK(BM_SdfBuild)->Arg(64)->Arg(96)->Unit(benchmark::kMillisecond)->UseRealTime();

// The bunny-qd cover dressed on the bunny, stepped under the global force
// (the steady contact state that failing trials spend their budget in).
void BM_ClothStep(benchmark::State& state) {
  const auto& b = bunny();
  cloth::ClothParams params;
  params.threads = static_cast<int>(state.range(0));
  cloth::PolygonMesh garment{b.garment.positions, b.garment.faces};
  cloth::dress(garment, b.field, params.clearance);
  cloth::ClothSimulation sim(garment, b.field, params);
  const auto axes = cloth::global_directions(1, 1000);
  std::int64_t steps = 0;
  for (auto _ : state) {
    sim.step(axes[(steps / params.switch_steps) % axes.size()]);
    ++steps;
  }
  state.counters["steps/s"] =
      benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kIsRate);
  state.counters["projections/s"] =
      benchmark::Counter(static_cast<double>(sim.projections()), benchmark::Counter::kIsRate);
  state.counters["vertices"] = static_cast<double>(garment.positions.size());
  state.counters["springs"] = static_cast<double>(sim.springs().size());
}
BENCHMARK(BM_ClothStep)->Arg(1)->Arg(2)->Unit(benchmark::kMicrosecond)->UseRealTime()->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
