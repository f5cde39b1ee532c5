// Runs `wearknit ARGS` in the background (for mock-device), reading its
// output. The object owns exactly one process, the wearknit itself: `stop`
// sends it one SIGTERM, and every wait is bounded, so a failing test cannot
// hang and a process that will not end is killed and said so in its output.
//
// One signal, to one process: a pattern match (pkill -f) would also reach a
// wrapper such as timeout(1), which forwards the signal, and a second
// SIGTERM arriving while an address-sanitizer build runs its leak check at
// exit can leave that process spinning for ever.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <string>

#include "tests/test_support.hpp"

extern char** environ;

namespace devices::test {

class BackgroundWearknit {
 public:
  // `args` is shell text (quoted paths are welcome); the shell execs
  // wearknit, so the process started is wearknit itself.
  explicit BackgroundWearknit(const std::string& args,
                              std::chrono::seconds lifetime = std::chrono::seconds(60))
      : deadline_(std::chrono::steady_clock::now() + lifetime) {
    int ends[2];
    if (::pipe2(ends, O_CLOEXEC) != 0) return;
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, ends[1], 1);
    posix_spawn_file_actions_adddup2(&actions, ends[1], 2);
    const std::string command = "exec '" + wearknit::test::wearknit_binary() + "' " + args;
    const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
    const int spawned =
        ::posix_spawn(&pid_, "/bin/sh", &actions, nullptr, const_cast<char* const*>(argv), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(ends[1]);
    if (spawned != 0) {
      pid_ = -1;
      ::close(ends[0]);
      first_line_ = "cannot start wearknit";
      return;
    }
    fd_ = ends[0];
    while (rest_.find('\n') == std::string::npos && read_more()) {
    }
    const std::size_t end = rest_.find('\n');
    first_line_ = rest_.substr(0, end);
    rest_ = end == std::string::npos ? "" : rest_.substr(end + 1);
  }
  BackgroundWearknit(const BackgroundWearknit&) = delete;
  BackgroundWearknit& operator=(const BackgroundWearknit&) = delete;
  ~BackgroundWearknit() {
    if (pid_ > 0) ::kill(pid_, SIGKILL);
    finish();
  }

  const std::string& first_line() const { return first_line_; }
  // The URI after "listening ".
  std::string uri() const {
    return first_line_.rfind("listening ", 0) == 0 ? first_line_.substr(10) : "";
  }
  // Asks the process to end (one SIGTERM).
  void stop() {
    if (pid_ > 0 && !stopped_) ::kill(pid_, SIGTERM);
    stopped_ = true;
  }
  // Waits for the process to end, at most until its lifetime is over (then
  // kills it); returns the rest of its output.
  std::string finish() {
    while (read_more()) {
    }
    if (fd_ >= 0) {
      ::close(fd_);
      fd_ = -1;
    }
    if (pid_ > 0) {
      if (std::chrono::steady_clock::now() >= deadline_) {
        ::kill(pid_, SIGKILL);
        rest_ += "\n[killed: wearknit had not ended when its lifetime was over]\n";
      }
      int status = 0;
      ::waitpid(pid_, &status, 0);
      pid_ = -1;
    }
    return rest_;
  }

 private:
  // Reads what the process wrote, until its end of the pipe closes or the
  // lifetime is over. False when there is nothing more to read.
  bool read_more() {
    if (fd_ < 0) return false;
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline_ - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    pollfd p{fd_, POLLIN, 0};
    const int ready = ::poll(&p, 1, static_cast<int>(left.count()));
    if (ready < 0 && errno == EINTR) return true;
    if (ready <= 0) return false;
    char buffer[4096];
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) return true;
    if (n <= 0) return false;
    rest_.append(buffer, static_cast<std::size_t>(n));
    return true;
  }

  pid_t pid_ = -1;
  int fd_ = -1;
  bool stopped_ = false;
  std::chrono::steady_clock::time_point deadline_;
  std::string first_line_;
  std::string rest_;
};

}  // namespace devices::test
