// Benchmarks of the cutting stage (§4): cutting a quad-dominant proxy as it
// is, and remeshing a triangle mesh and cutting it. bench/cut.sh runs them.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "planner/cut/cut.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/proxy/proxy.hpp"

namespace {

std::filesystem::path meshes_dir() {
  if (const char* env = std::getenv("WEARKNIT_SHARED"); env != nullptr && *env != '\0') {
    return std::filesystem::path(env) / "meshes";
  }
  return std::filesystem::path(WEARKNIT_SOURCE_DIR).parent_path() / "shared" / "meshes";
}

planner::PolygonMesh load(const std::string& name) {
  knitout::DiagnosticSink sink;
  auto mesh = planner::load_mesh((meshes_dir() / name).string(), {}, sink);
  if (!mesh) throw std::runtime_error("cannot load " + name + " (set WEARKNIT_SHARED)");
  return *mesh;
}

// Load, proxy (the input as is) and cut: what `wearknit cut bunny-qd.obj` computes.
void BM_CutBunnyQd(benchmark::State& state) {
  for (auto _ : state) {
    const planner::PolygonMesh mesh = load("bunny-qd.obj");
    planner::ProxyResult proxy = planner::make_proxy(mesh, {});
    planner::CutMesh cut = planner::cut_surface(planner::HalfedgeMesh(std::move(proxy.mesh)), {});
    benchmark::DoNotOptimize(cut.direction.data());
    state.counters["faces"] = cut.proxy.num_faces();
  }
}
BENCHMARK(BM_CutBunnyQd)->Unit(benchmark::kMillisecond)->MinTime(2.0);

// Load the 52,000-face armadillo, remesh it (about 3000 quads) and cut.
void BM_RemeshAndCutArmadillo(benchmark::State& state) {
  for (auto _ : state) {
    const planner::PolygonMesh mesh = load("armadillo.obj");
    planner::ProxyResult proxy = planner::make_proxy(mesh, {});
    planner::CutMesh cut = planner::cut_surface(planner::HalfedgeMesh(std::move(proxy.mesh)), {});
    benchmark::DoNotOptimize(cut.direction.data());
    state.counters["input_faces"] = static_cast<double>(mesh.faces.size());
    state.counters["proxy_faces"] = cut.proxy.num_faces();
    state.counters["extracted"] = proxy.method == "instant-meshes" ? 1 : 0;
  }
}
BENCHMARK(BM_RemeshAndCutArmadillo)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
