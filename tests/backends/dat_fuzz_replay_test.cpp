// Replays every input the DAT reader fuzzer saved (tests/backends/fuzz_inputs:
// the crashes it found, each fixed since, and its seed inputs) through the
// same checks the fuzz target makes, as ordinary tests.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "tests/backends/dat_read_check.hpp"
#include "tests/test_support.hpp"

namespace dat {
namespace {

TEST(DatFuzzReplayTest, EverySavedInputPassesTheFuzzChecks) {
  const std::filesystem::path inputs = wearknit::test::source_dir() / "tests/backends/fuzz_inputs";
  std::size_t replayed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(inputs)) {
    if (!entry.is_regular_file()) continue;
    const std::string data = wearknit::test::read_file(entry.path());
    SCOPED_TRACE(entry.path().filename().string());
    EXPECT_EQ(
        check_read(std::span(reinterpret_cast<const std::uint8_t*>(data.data()), data.size())), "");
    ++replayed;
  }
  EXPECT_GT(replayed, 0u) << "no saved fuzz inputs found in " << inputs;
}

}  // namespace
}  // namespace dat
