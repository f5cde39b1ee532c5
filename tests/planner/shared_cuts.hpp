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
// its longest side and cut (§4) by the cut stage with the default options
// (the field-guided proxy, square growth, the cut tightened); writes the
// cut folder `dir` as `wearknit cut --no-pictures` does, with the garment's
// surface. Checks the proxy and the disc on the way (gtest failures).
inline void cut_into(const fs::path& shared, const std::string& name, const fs::path& dir) {
  const fs::path file = shared / "meshes" / (name + ".obj");
  knitout::DiagnosticSink sink;
  std::optional<PolygonMesh> mesh = load_mesh(file.string(), {}, sink);
  ASSERT_TRUE(mesh) << file;
  const Vec3 size = bounding_box_size(*mesh);
  for (Vec3& p : mesh->positions) p *= 100.0 / size.maxCoeff();
  Cut cut = cut_garment(*mesh, CutStageParams{});  // verify_cut runs inside
  // A quad-dominant input is kept only when clean; anything else becomes
  // the field-guided proxy.
  EXPECT_TRUE(cut.report.proxy_method == "input" || cut.report.proxy_method == "field")
      << file << ": proxy " << cut.report.proxy_method;
  // No two proxy vertices at one point (each would be a pinch of the
  // garment the wearability stage rebuilds from the cut).
  {
    std::vector<Vec3> points = cut.mesh.proxy.polygons().positions;
    std::vector<std::vector<int>> faces = cut.mesh.proxy.polygons().faces;
    const std::size_t before = points.size();
    weld_vertices(points, faces, 1e-9 * 100.0 * std::sqrt(3.0));
    EXPECT_EQ(points.size(), before) << file << ": coincident proxy vertices";
  }
  EXPECT_TRUE(check_disc(labelled_disc(cut.mesh)).empty()) << file << ": the cut is not a disc";
  std::error_code ignored;
  fs::remove_all(dir, ignored);
  ASSERT_EQ(write_cut(dir.string(), cut, {false, 600}), "") << name;
}

// The cut of the shared mesh `name` at 100 mm with §4.1's remeshed quad
// proxy (`wearknit cut --proxy remesh`: random growth, the cut as grown),
// with the garment's surface; made in memory, not read from a folder.
inline std::optional<Cut> remeshed_cut(const fs::path& shared, const std::string& name) {
  knitout::DiagnosticSink sink;
  std::optional<PolygonMesh> mesh =
      load_mesh((shared / "meshes" / (name + ".obj")).string(), {}, sink);
  if (!mesh) return std::nullopt;
  const Vec3 size = bounding_box_size(*mesh);
  for (Vec3& p : mesh->positions) p *= 100.0 / size.maxCoeff();
  CutStageParams params;
  params.proxy.method = ProxyMethod::Remesh;
  params.cut.square_growth = false;
  params.cut.tighten = false;
  return cut_garment(*mesh, params);
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
