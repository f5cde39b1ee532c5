#include "knitout/output_file.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <stdexcept>

#include "tests/test_support.hpp"

namespace knitout {
namespace {

std::size_t files_in(const std::filesystem::path& dir) {
  std::size_t count = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++count;
  return count;
}

TEST(OutputFileTest, WritesAndReplacesTheTarget) {
  const auto dir = wearknit::test::make_temp_dir("wearknit-out");
  const auto path = (dir / "a.txt").string();
  EXPECT_EQ(write_file_atomically(path, [](std::ostream& out) { out << "one"; }), "");
  EXPECT_EQ(write_file_atomically(path, [](std::ostream& out) { out << "two"; }), "");
  EXPECT_EQ(wearknit::test::read_file(path), "two");
  EXPECT_EQ(files_in(dir), 1u);
  std::filesystem::remove_all(dir);
}

TEST(OutputFileTest, FailureLeavesTheOldFileAndNoTemporary) {
  const auto dir = wearknit::test::make_temp_dir("wearknit-out");
  const auto path = (dir / "a.txt").string();
  wearknit::test::write_file(path, "old");
  const std::string failure = write_file_atomically(path, [](std::ostream& out) {
    out << "half";
    throw std::runtime_error("disk full");
  });
  EXPECT_EQ(failure, "cannot write " + path + ": disk full");
  EXPECT_EQ(wearknit::test::read_file(path), "old");
  EXPECT_EQ(files_in(dir), 1u);
  std::filesystem::remove_all(dir);
}

TEST(OutputFileTest, MissingFolderIsAClearError) {
  const std::string failure =
      write_file_atomically("/nonexistent-dir/x.k", [](std::ostream& out) { out << "x"; });
  EXPECT_EQ(failure,
            "cannot create a temporary file for /nonexistent-dir/x.k: No such file or directory");
}

TEST(OutputFileTest, WriteFailureMidFileIsReportedAndNothingIsLeft) {
  // A file-size limit makes the disk "full" after 4 KiB: writes fail with
  // EFBIG like they fail with ENOSPC on a full disk. Run in a child process
  // so the limit does not outlive the test.
  const auto dir = wearknit::test::make_temp_dir("wearknit-out");
  const auto path = (dir / "big.k").string();
  wearknit::test::write_file(path, "old");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    const std::string failure =
        write_file_atomically(path, [](std::ostream& out) { out << std::string(1 << 20, 'x'); });
    std::_Exit(failure.rfind("cannot write " + path + ": ", 0) == 0 ? 0 : 1);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the failure was not reported as a write error";
  EXPECT_EQ(wearknit::test::read_file(path), "old");
  EXPECT_EQ(files_in(dir), 1u) << "a temporary file was left behind";
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace knitout
