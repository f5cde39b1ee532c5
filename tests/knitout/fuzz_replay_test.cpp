// Replays every input the parser fuzzer saved (tests/knitout/fuzz_inputs:
// the crashes it found, each fixed since, and its seed inputs) through the
// same checks the fuzz target makes, as ordinary tests.
#include <gtest/gtest.h>

#include "tests/knitout/parse_check.hpp"
#include "tests/test_support.hpp"

namespace knitout {
namespace {

TEST(FuzzReplayTest, EverySavedInputPassesTheFuzzChecks) {
  const std::filesystem::path inputs = wearknit::test::source_dir() / "tests/knitout/fuzz_inputs";
  std::size_t replayed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(inputs)) {
    if (!entry.is_regular_file()) continue;
    const std::string data = wearknit::test::read_file(entry.path());
    SCOPED_TRACE(entry.path().filename().string());
    EXPECT_EQ(check_parse_round_trip(data), "");
    ++replayed;
  }
  EXPECT_GT(replayed, 0u) << "no saved fuzz inputs found in " << inputs;
}

}  // namespace
}  // namespace knitout
