// bench/sweep.sh on a few shared meshes, seeds and sizes (the whole sweep is
// a bench run, docs/results.md): the knit branch ends in a result or in a
// diagnostic with a code, never in an internal error, and every piece it
// makes passes the VM.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.hpp"

namespace wearknit::test {
namespace {

namespace fs = std::filesystem;

TEST(SweepTest, KnitBranchOverMeshesSeedsAndSizesHasNoInternalError) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const fs::path out = make_temp_dir("sweep");
  // Three meshes (closed, open, quad-dominant) at the small and the large
  // size, where a size change moves every level curve and needle.
  const std::string command = "cd '" + source_dir().string() + "' && WEARKNIT='" +
                              wearknit_binary() + "' WEARKNIT_SHARED='" + shared.string() +
                              "' OUT='" + out.string() +
                              "' MESHES='sphere-qd half-torus torus-npm' SEEDS=3 SIZES='60 250' "
                              "PLAN_MESHES='' JOBS=2 bash bench/sweep.sh > '" +
                              (out / "summary.txt").string() + "' 2>&1";
  const int status = std::system(command.c_str());
  const std::string summary = read_file(out / "summary.txt");
  EXPECT_EQ(status, 0) << summary;
  std::ifstream table(out / "sweep.tsv");
  int rows = 0;
  for (std::string line; std::getline(table, line);) {
    std::vector<std::string> field;
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, '\t');) field.push_back(cell);
    ASSERT_GE(field.size(), 10u) << line;
    ++rows;
    EXPECT_NE(field[3], "internal") << line;
    if (field[3] != "ok") {
      EXPECT_NE(field[5], "-") << "a failure without a code: " << line;
    }
    EXPECT_EQ(field[8], "0") << "pieces the VM rejects: " << line;
  }
  EXPECT_EQ(rows, 6) << summary;
  fs::remove_all(out);
}

}  // namespace
}  // namespace wearknit::test
