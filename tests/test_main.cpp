// main() of every test binary: runs the selected tests as gtest_main does,
// and exits with kSkipped (ctest's SKIP_RETURN_CODE, tests/CMakeLists.txt)
// when tests ran and every one of them skipped. A ctest test that runs
// several cases in one process is then reported as skipped only when
// nothing passed and nothing failed: a failure among skips stays a failure,
// and a run without ../shared is never reported as passed.
#include <gtest/gtest.h>

namespace {

constexpr int kSkipped = 77;

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const int status = RUN_ALL_TESTS();
  const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
  if (status == 0 && unit.successful_test_count() == 0 && unit.skipped_test_count() > 0) {
    return kSkipped;
  }
  return status;
}
