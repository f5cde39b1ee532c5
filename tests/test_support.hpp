// Helpers shared by the tests: where ../shared is, running the CLI.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <utility>

namespace wearknit::test {

// The project root (the checkout the tests were built from).
std::filesystem::path source_dir();

// The path of the wearknit binary, for end-to-end tests of the verbs.
std::string wearknit_binary();

// The shared data folder: $WEARKNIT_SHARED, else ../shared beside the
// project root; nullopt when neither exists.
std::optional<std::filesystem::path> shared_dir();

// Skips the running test, visibly, when ../shared is absent.
#define WEARKNIT_REQUIRE_SHARED(var)                                                   \
  const auto var##_opt = ::wearknit::test::shared_dir();                               \
  if (!var##_opt) {                                                                    \
    GTEST_SKIP() << "needs ../shared (set WEARKNIT_SHARED): test data is not present"; \
  }                                                                                    \
  const std::filesystem::path var = *var##_opt

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Runs the wearknit binary with `args` (a shell-quoted string), capturing
// stdout and stderr.
CommandResult run_wearknit(const std::string& args, const std::string& stdin_text = "");

// Starts the wearknit binary with `args` (output discarded) and kills it
// (SIGKILL) as soon as the file `watch` has at least `lines` lines. Returns
// whether it was killed (false: it ended first, or not within 5 minutes).
bool run_wearknit_and_kill(const std::string& args, const std::filesystem::path& watch, int lines);

// A fresh empty folder under the system temp dir, removed by the caller.
std::filesystem::path make_temp_dir(const std::string& prefix);

// A fresh empty folder under the system temp dir, removed with everything in
// it when the object goes out of scope (also when an ASSERT returns early).
class TempDir {
 public:
  explicit TempDir(const std::string& prefix) : path_(make_temp_dir(prefix)) {}
  TempDir(TempDir&& other) noexcept : path_(std::move(other.path_)) { other.path_.clear(); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  TempDir& operator=(TempDir&&) = delete;
  ~TempDir() {
    std::error_code ignored;
    if (!path_.empty()) std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

std::string read_file(const std::filesystem::path& path);
void write_file(const std::filesystem::path& path, const std::string& content);

}  // namespace wearknit::test
