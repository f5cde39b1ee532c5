#include <gtest/gtest.h>

#include "tests/test_support.hpp"

namespace wearknit::cli {
namespace {

using test::run_wearknit;

TEST(CliTest, UnknownVerbPrintsUsageAndExitsTwo) {
  const auto result = run_wearknit("frobnicate");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("unknown verb 'frobnicate'"), std::string::npos);
  EXPECT_NE(result.err.find("usage: wearknit VERB"), std::string::npos);
}

}  // namespace
}  // namespace wearknit::cli
