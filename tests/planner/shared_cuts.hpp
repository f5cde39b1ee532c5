// The shared test meshes (../shared/meshes) and their cuts, for the suites
// that run on every one of them (shared_cut_test.cpp, stitch_mesh_shared_test.cpp,
// schedule_shared_test.cpp).
//
// Each mesh is cut once per test run: ctest runs SharedCut/NAME first, as
// the fixture the other suites' tests of mesh NAME require
// (tests/planner/CMakeLists.txt), and it writes the cut folder
// $WEARKNIT_SHARED_CUTS/NAME, which they read. A test binary run by hand,
// without that variable, cuts the mesh itself the same way.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "planner/cut/cut.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/pipeline.hpp"
#include "planner/proxy/proxy.hpp"
#include "planner/proxy/remesh.hpp"
#include "planner/wearability/wearability.hpp"
#include "tests/test_support.hpp"

namespace planner::shared_cuts {

namespace fs = std::filesystem;

// Every .obj of ../shared/meshes by name, as tests/planner/CMakeLists.txt
// lists them (SharedMeshesTest.ListsEveryMesh checks the list).
inline std::vector<std::string> mesh_names() {
  std::vector<std::string> names;
  std::istringstream list(WEARKNIT_SHARED_MESHES);
  for (std::string name; std::getline(list, name, ',');) names.push_back(name);
  return names;
}

// The name of the test of mesh `info.param`: its name with '_' for '-'.
inline std::string test_name(const ::testing::TestParamInfo<std::string>& info) {
  std::string name = info.param;
  for (char& c : name) {
    if (c == '-') c = '_';
  }
  return name;
}

// Cuts the shared mesh `name` as the suites take it: scaled to 100 mm along
// its longest side, its quad proxy (§4.1) and its cut (§4) with the default
// options; writes the cut folder `dir` as `wearknit cut --no-pictures`
// does. Checks the proxy and the disc on the way (gtest failures).
inline void cut_into(const fs::path& shared, const std::string& name, const fs::path& dir) {
  const fs::path file = shared / "meshes" / (name + ".obj");
  knitout::DiagnosticSink sink;
  std::optional<PolygonMesh> mesh = load_mesh(file.string(), {}, sink);
  ASSERT_TRUE(mesh) << file;
  const Vec3 size = bounding_box_size(*mesh);
  for (Vec3& p : mesh->positions) p *= 100.0 / size.maxCoeff();
  const bool quad_input = is_quad_dominant(*mesh);
  ProxyResult proxy = make_proxy(*mesh, ProxyParams{});
  // Every triangle input is remeshed along its field (no fallback to
  // pairing triangles).
  EXPECT_EQ(proxy.method, quad_input ? "input" : "instant-meshes") << file << proxy.remesh_failure;
  // No two proxy vertices at one point (a pinch split by the remesher is
  // pulled apart): the wearability stage welds the cut mesh's two sides by
  // position, which must give back this surface.
  {
    std::vector<Vec3> points = proxy.mesh.positions;
    std::vector<std::vector<int>> faces = proxy.mesh.faces;
    weld_vertices(points, faces, 1e-9 * 100.0 * std::sqrt(3.0));
    EXPECT_EQ(points.size(), proxy.mesh.positions.size()) << file << ": coincident proxy vertices";
  }
  // No quad of nil area is left where the lattice folded (each would put a
  // needle-thin spike into the cut boundary).
  if (!quad_input) {
    PolygonMesh welded = proxy.mesh;
    EXPECT_EQ(collapse_folded_quads(welded, RemeshParams{}.fold_ratio), 0)
        << file << ": folded quads left in the proxy";
  }
  const CutMesh cut = cut_surface(HalfedgeMesh(std::move(proxy.mesh)), CutParams{});
  EXPECT_TRUE(check_disc(labelled_disc(cut)).empty()) << file << ": the cut is not a disc";
  std::error_code ignored;
  fs::remove_all(dir, ignored);
  // The garment's surface goes with it, as the cut stage writes it.
  Cut written;
  written.mesh = cut;
  written.surface = std::move(*mesh);
  ASSERT_EQ(write_cut(dir.string(), written, {false, 600}), "") << name;
}

// The cut of the shared mesh `name`, read from its cut folder (the
// stitch-mesh stage reads the cut so, and depends on the rounding of the
// files); nullopt, with a gtest failure, when there is none.
inline std::optional<Cut> read_shared_cut(const fs::path& shared, const std::string& name) {
  std::optional<wearknit::test::TempDir> own;
  fs::path dir;
  if (const char* cuts = std::getenv("WEARKNIT_SHARED_CUTS"); cuts != nullptr && *cuts != '\0') {
    dir = fs::path(cuts) / name;
  } else {
    own.emplace("shared-cut");
    dir = own->path() / name;
    cut_into(shared, name, dir);
  }
  knitout::DiagnosticSink sink;
  std::optional<Cut> cut = read_cut(dir.string(), sink);
  EXPECT_TRUE(cut) << name << ": no cut (the test SharedCut/" << name << " writes it): "
                   << (sink.diagnostics().empty() ? ""
                                                  : knitout::format(sink.diagnostics().front()));
  return cut;
}

}  // namespace planner::shared_cuts
