#include "tests/test_support.hpp"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

namespace wearknit::test {

std::filesystem::path source_dir() {
  return WEARKNIT_SOURCE_DIR;
}

std::string wearknit_binary() {
  return WEARKNIT_BINARY;
}

std::optional<std::filesystem::path> shared_dir() {
  if (const char* env = std::getenv("WEARKNIT_SHARED"); env != nullptr && *env != '\0') {
    if (std::filesystem::is_directory(env)) return std::filesystem::path(env);
    return std::nullopt;
  }
  const auto candidate = source_dir().parent_path() / "shared";
  if (std::filesystem::is_directory(candidate)) return candidate;
  return std::nullopt;
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

void write_file(const std::filesystem::path& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary);
  out << content;
}

std::filesystem::path make_temp_dir(const std::string& prefix) {
  std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "-XXXXXX")).string();
  if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  return pattern;
}

bool run_wearknit_and_kill(const std::string& args, const std::filesystem::path& watch, int lines) {
  const auto dir = make_temp_dir("wearknit-kill");
  const auto pid_file = dir / "pid";
  const std::string command = "'" + wearknit_binary() + "' " + args +
                              " >/dev/null 2>&1 </dev/null & echo $! >'" + pid_file.string() +
                              "'; wait";
  std::thread runner([&] { [[maybe_unused]] const int status = std::system(command.c_str()); });
  bool killed = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
  while (!killed && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (!std::filesystem::exists(watch)) continue;
    const std::string text = read_file(watch);
    if (std::count(text.begin(), text.end(), '\n') < lines) continue;
    const std::string pid = read_file(pid_file);
    if (pid.empty()) continue;
    killed = ::kill(static_cast<pid_t>(std::stol(pid)), SIGKILL) == 0;
  }
  runner.join();
  std::filesystem::remove_all(dir);
  return killed;
}

CommandResult run_wearknit(const std::string& args, const std::string& stdin_text) {
  const auto dir = make_temp_dir("wearknit-run");
  const auto in_path = dir / "stdin";
  const auto out_path = dir / "stdout";
  const auto err_path = dir / "stderr";
  write_file(in_path, stdin_text);
  const std::string command = "'" + wearknit_binary() + "' " + args + " <'" + in_path.string() +
                              "' >'" + out_path.string() + "' 2>'" + err_path.string() + "'";
  const int status = std::system(command.c_str());
  CommandResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = read_file(out_path);
  result.err = read_file(err_path);
  std::filesystem::remove_all(dir);
  return result;
}

}  // namespace wearknit::test
