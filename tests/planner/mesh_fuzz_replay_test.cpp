// Replays every input the mesh reader fuzzer saved (tests/planner/fuzz_inputs:
// the faults it found, each fixed since, and its seed inputs) through the
// same checks the fuzz target makes, as ordinary tests.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "tests/planner/mesh_read_check.hpp"
#include "tests/test_support.hpp"

namespace planner {
namespace {

TEST(MeshFuzzReplayTest, EverySavedInputPassesTheFuzzChecks) {
  const std::filesystem::path inputs = wearknit::test::source_dir() / "tests/planner/fuzz_inputs";
  std::size_t replayed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(inputs)) {
    if (!entry.is_regular_file()) continue;
    const std::string data = wearknit::test::read_file(entry.path());
    SCOPED_TRACE(entry.path().filename().string());
    EXPECT_EQ(mesh_fuzz::check_read(
                  std::span(reinterpret_cast<const std::uint8_t*>(data.data()), data.size())),
              "");
    ++replayed;
  }
  EXPECT_GT(replayed, 0u) << "no saved fuzz inputs found in " << inputs;
}

}  // namespace
}  // namespace planner
