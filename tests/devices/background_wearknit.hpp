// Runs `wearknit ARGS` in the background (for mock-device), reading its
// output; `timeout` bounds it so a failing test cannot hang.
#pragma once

#include <cstdio>
#include <string>

#include "tests/test_support.hpp"

namespace devices::test {

class BackgroundWearknit {
 public:
  explicit BackgroundWearknit(const std::string& args) {
    const std::string command =
        "timeout 60 '" + wearknit::test::wearknit_binary() + "' " + args + " 2>&1";
    pipe_ = ::popen(command.c_str(), "r");
    if (pipe_ == nullptr) return;
    char line[4096];
    if (std::fgets(line, sizeof line, pipe_) != nullptr) first_line_ = line;
    if (!first_line_.empty() && first_line_.back() == '\n') first_line_.pop_back();
  }
  ~BackgroundWearknit() { finish(); }

  const std::string& first_line() const { return first_line_; }
  // The URI after "listening ".
  std::string uri() const {
    return first_line_.rfind("listening ", 0) == 0 ? first_line_.substr(10) : "";
  }
  // Waits for the process to end; returns the rest of its output.
  std::string finish() {
    if (pipe_ == nullptr) return rest_;
    char buffer[4096];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe_)) > 0) rest_.append(buffer, n);
    ::pclose(pipe_);
    pipe_ = nullptr;
    return rest_;
  }

 private:
  FILE* pipe_ = nullptr;
  std::string first_line_;
  std::string rest_;
};

}  // namespace devices::test
