// The cut of every shared test mesh (shared_cuts.hpp), made once per test
// run into $WEARKNIT_SHARED_CUTS for the suites that stitch-mesh and
// schedule it: the proxy of each triangle input is remeshed along its field
// with no coincident vertices and no folded quads, and the cut is one disc.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>

#include "tests/planner/shared_cuts.hpp"
#include "tests/test_support.hpp"

namespace planner {
namespace {

namespace fs = std::filesystem;

TEST(SharedMeshesTest, ListsEveryMesh) {
  WEARKNIT_REQUIRE_SHARED(shared);
  std::set<std::string> on_disk;
  for (const auto& entry : fs::directory_iterator(shared / "meshes")) {
    if (entry.path().extension() == ".obj") on_disk.insert(entry.path().stem().string());
  }
  const std::vector<std::string> listed = shared_cuts::mesh_names();
  EXPECT_EQ(on_disk, std::set<std::string>(listed.begin(), listed.end()));
}

class SharedCutTest : public ::testing::TestWithParam<std::string> {};

TEST_P(SharedCutTest, CutsTheMeshIntoOneDiscForTheSuitesThatUseIt) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const char* cuts = std::getenv("WEARKNIT_SHARED_CUTS");
  if (cuts == nullptr || *cuts == '\0') {
    // Run by hand: the suites that read the cut make it themselves.
    const wearknit::test::TempDir dir("shared-cut");
    shared_cuts::cut_into(shared, GetParam(), dir.path() / GetParam());
    return;
  }
  shared_cuts::cut_into(shared, GetParam(), fs::path(cuts) / GetParam());
}

INSTANTIATE_TEST_SUITE_P(Meshes, SharedCutTest, ::testing::ValuesIn(shared_cuts::mesh_names()),
                         shared_cuts::test_name);

}  // namespace
}  // namespace planner
