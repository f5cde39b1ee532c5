#include "tests/browser.hpp"

#include <fcntl.h>
#include <png.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <thread>

namespace wearknit::test {

namespace {

using Clock = std::chrono::steady_clock;

Clock::time_point after(double seconds) {
  return Clock::now() + std::chrono::milliseconds(static_cast<long long>(seconds * 1000));
}

// The browser binary to run, or "" when none is on the PATH.
std::string find_browser() {
  if (const char* chosen = std::getenv("WEARKNIT_CHROMIUM"); chosen != nullptr && *chosen) {
    return chosen;
  }
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "/usr/bin:/bin";
  for (const char* name : {"chromium", "chromium-browser", "google-chrome"}) {
    std::size_t start = 0;
    while (start <= dirs.size()) {
      const std::size_t end = std::min(dirs.find(':', start), dirs.size());
      const std::filesystem::path candidate =
          std::filesystem::path(dirs.substr(start, end - start)) / name;
      if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
      start = end + 1;
    }
  }
  return "";
}

std::string base64_decode(const std::string& text) {
  static const std::string kDigits =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve(text.size() * 3 / 4);
  std::uint32_t value = 0;
  int bits = 0;
  for (const char c : text) {
    const std::size_t digit = kDigits.find(c);
    if (digit == std::string::npos) continue;  // padding and line breaks
    value = (value << 6) | static_cast<std::uint32_t>(digit);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += static_cast<char>((value >> bits) & 0xff);
    }
  }
  return out;
}

}  // namespace

Image read_png(const std::string& bytes) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_memory(&image, bytes.data(), bytes.size()) == 0) {
    throw std::runtime_error(std::string("screenshot: not a PNG: ") + image.message);
  }
  image.format = PNG_FORMAT_RGBA;
  Image out;
  out.width = static_cast<int>(image.width);
  out.height = static_cast<int>(image.height);
  out.rgba.resize(PNG_IMAGE_SIZE(image));
  if (png_image_finish_read(&image, nullptr, out.rgba.data(), 0, nullptr) == 0) {
    throw std::runtime_error(std::string("screenshot: ") + image.message);
  }
  return out;
}

namespace {

// The text of a console call's arguments, joined by spaces.
std::string console_text(const nlohmann::json& args) {
  std::string text;
  for (const nlohmann::json& arg : args) {
    if (!text.empty()) text += ' ';
    if (arg.contains("value")) {
      text += arg["value"].is_string() ? arg["value"].get<std::string>() : arg["value"].dump();
    } else if (arg.contains("description")) {
      text += arg["description"].get<std::string>();
    } else {
      text += arg.value("type", "?");
    }
  }
  return text;
}

}  // namespace

std::size_t Image::count_near(std::uint32_t rgb, int tolerance) const {
  const int r = static_cast<int>((rgb >> 16) & 0xff);
  const int g = static_cast<int>((rgb >> 8) & 0xff);
  const int b = static_cast<int>(rgb & 0xff);
  std::size_t count = 0;
  for (std::size_t i = 0; i + 3 < rgba.size(); i += 4) {
    if (std::abs(rgba[i] - r) <= tolerance && std::abs(rgba[i + 1] - g) <= tolerance &&
        std::abs(rgba[i + 2] - b) <= tolerance) {
      ++count;
    }
  }
  return count;
}

std::string file_url(const std::filesystem::path& path) {
  const std::string absolute = std::filesystem::absolute(path).lexically_normal().string();
  std::string url = "file://";
  for (const unsigned char c : absolute) {
    if (std::isalnum(c) || std::strchr("/-_.~", c) != nullptr) {
      url += static_cast<char>(c);
    } else {
      static constexpr char kHex[] = "0123456789ABCDEF";
      url += '%';
      url += kHex[c >> 4];
      url += kHex[c & 15];
    }
  }
  return url;
}

std::unique_ptr<Browser> Browser::start(std::string* why, int width, int height) {
  const std::string binary = find_browser();
  if (binary.empty()) {
    *why =
        "no chromium on the PATH (scripts/install-deps.sh installs it; or set WEARKNIT_CHROMIUM)";
    return nullptr;
  }
  char profile_template[] = "/tmp/wearknit-browser-XXXXXX";
  if (::mkdtemp(profile_template) == nullptr) {
    *why = std::string("cannot make a profile folder: ") + std::strerror(errno);
    return nullptr;
  }
  std::unique_ptr<Browser> browser(new Browser());
  browser->profile_ = profile_template;
  int to[2];
  int from[2];
  if (::pipe2(to, O_CLOEXEC) != 0 || ::pipe2(from, O_CLOEXEC) != 0) {
    *why = std::string("pipe: ") + std::strerror(errno);
    return nullptr;
  }
  const std::string profile_arg = "--user-data-dir=" + browser->profile_.string();
  const std::string size_arg =
      "--window-size=" + std::to_string(width) + "," + std::to_string(height);
  // WebGL runs on SwiftShader, Chromium's CPU renderer, where there is no GPU.
  std::vector<std::string> args = {binary,
                                   "--headless=new",
                                   "--no-sandbox",
                                   "--remote-debugging-pipe",
                                   "--no-first-run",
                                   "--no-default-browser-check",
                                   "--disable-extensions",
                                   "--disable-background-networking",
                                   "--use-angle=swiftshader",
                                   "--enable-unsafe-swiftshader",
                                   "--hide-scrollbars",
                                   "--mute-audio",
                                   profile_arg,
                                   size_arg,
                                   "about:blank"};
  const pid_t pid = ::fork();
  if (pid < 0) {
    *why = std::string("fork: ") + std::strerror(errno);
    return nullptr;
  }
  if (pid == 0) {
    // The browser reads commands on descriptor 3 and writes on 4. Both ends
    // are first moved above 4 so that neither is overwritten by the other.
    ::setpgid(0, 0);
    const int in = ::fcntl(to[0], F_DUPFD, 10);
    const int out = ::fcntl(from[1], F_DUPFD, 10);
    ::dup2(in, 3);
    ::dup2(out, 4);
    const int null = ::open("/dev/null", O_RDWR);
    if (null >= 0) {
      ::dup2(null, 1);
      ::dup2(null, 2);
    }
    std::vector<char*> argv;
    for (std::string& arg : args) argv.push_back(arg.data());
    argv.push_back(nullptr);
    ::execv(binary.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(to[0]);
  ::close(from[1]);
  browser->pid_ = pid;
  browser->to_browser_ = to[1];
  browser->from_browser_ = from[0];
  try {
    const nlohmann::json target =
        browser->send("Target.createTarget", {{"url", "about:blank"}}, "", 30);
    const nlohmann::json attached = browser->send(
        "Target.attachToTarget", {{"targetId", target.at("targetId")}, {"flatten", true}}, "", 30);
    browser->session_ = attached.at("sessionId").get<std::string>();
    browser->command("Page.enable", nlohmann::json::object(), 30);
    browser->command("Runtime.enable", nlohmann::json::object(), 30);
    browser->command("Log.enable", nlohmann::json::object(), 30);
    browser->command(
        "Emulation.setDeviceMetricsOverride",
        {{"width", width}, {"height", height}, {"deviceScaleFactor", 1}, {"mobile", false}}, 30);
  } catch (const std::exception& error) {
    *why = binary + " did not start: " + error.what();
    return nullptr;
  }
  return browser;
}

Browser::~Browser() {
  if (to_browser_ >= 0) ::close(to_browser_);
  if (from_browser_ >= 0) ::close(from_browser_);
  if (pid_ > 0) {
    // Closing the pipe ends the browser; kill it if it lingers.
    for (int i = 0; i < 50; ++i) {
      if (::waitpid(pid_, nullptr, WNOHANG) == pid_) {
        pid_ = -1;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (pid_ > 0) {
      ::kill(-pid_, SIGKILL);
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
    }
  }
  std::error_code ignored;
  if (!profile_.empty()) std::filesystem::remove_all(profile_, ignored);
}

nlohmann::json Browser::command(const std::string& method, const nlohmann::json& params,
                                double timeout_s) {
  return send(method, params, session_, timeout_s);
}

nlohmann::json Browser::send(const std::string& method, const nlohmann::json& params,
                             const std::string& session, double timeout_s) {
  const int id = ++next_id_;
  nlohmann::json message = {{"id", id}, {"method", method}, {"params", params}};
  if (!session.empty()) message["sessionId"] = session;
  std::string text = message.dump();
  text += '\0';
  std::size_t written = 0;
  while (written < text.size()) {
    const ssize_t n = ::write(to_browser_, text.data() + written, text.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(method + ": the browser's pipe is closed");
    }
    written += static_cast<std::size_t>(n);
  }
  const auto deadline = after(timeout_s);
  while (true) {
    for (auto it = responses_.begin(); it != responses_.end(); ++it) {
      if ((*it)["id"] == id) {
        nlohmann::json response = std::move(*it);
        responses_.erase(it);
        if (response.contains("error")) {
          throw std::runtime_error(method + ": " + response["error"].dump());
        }
        return response.value("result", nlohmann::json::object());
      }
    }
    if (!pump(deadline)) throw std::runtime_error(method + ": no answer in time");
  }
}

bool Browser::pump(Clock::time_point deadline) {
  while (true) {
    const std::size_t end = buffer_.find('\0');
    if (end != std::string::npos) {
      nlohmann::json message = nlohmann::json::parse(buffer_.substr(0, end), nullptr, false);
      buffer_.erase(0, end + 1);
      if (message.is_discarded()) continue;
      if (message.contains("id")) {
        responses_.push_back(std::move(message));
      } else {
        handle_event(message);
      }
      return true;
    }
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    if (left <= 0) return false;
    pollfd fd{from_browser_, POLLIN, 0};
    const int ready = ::poll(&fd, 1, static_cast<int>(std::min<long long>(left, 1000)));
    if (ready < 0 && errno != EINTR) throw std::runtime_error("poll on the browser's pipe failed");
    if (ready <= 0) continue;
    char chunk[65536];
    const ssize_t n = ::read(from_browser_, chunk, sizeof chunk);
    if (n == 0) throw std::runtime_error("the browser ended");
    if (n < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      throw std::runtime_error("reading the browser's pipe failed");
    }
    buffer_.append(chunk, static_cast<std::size_t>(n));
  }
}

void Browser::handle_event(const nlohmann::json& message) {
  const std::string method = message.value("method", "");
  const nlohmann::json& params = message.contains("params") ? message["params"] : nlohmann::json();
  if (method == "Page.loadEventFired") {
    loaded_ = true;
  } else if (method == "Runtime.consoleAPICalled") {
    const std::string type = params.value("type", "");
    if (type == "error" || type == "assert") {
      errors_.push_back("console." + type + ": " +
                        console_text(params.value("args", nlohmann::json::array())));
    }
  } else if (method == "Runtime.exceptionThrown") {
    const nlohmann::json& details = params["exceptionDetails"];
    std::string text = details.value("text", "exception");
    if (details.contains("exception")) {
      text += " " + details["exception"].value("description", "");
    }
    errors_.push_back("uncaught: " + text);
  } else if (method == "Log.entryAdded") {
    const nlohmann::json& entry = params["entry"];
    if (entry.value("level", "") == "error") {
      errors_.push_back("log: " + entry.value("text", "") + " " + entry.value("url", ""));
    }
  }
}

std::string Browser::open(const std::string& url, double timeout_s) {
  errors_.clear();
  loaded_ = false;
  const auto deadline = after(timeout_s);
  command("Page.navigate", {{"url", url}}, timeout_s);
  while (!loaded_) {
    if (!pump(deadline)) return "";
  }
  while (Clock::now() < deadline) {
    const nlohmann::json ready =
        evaluate("document.body ? (document.body.dataset.ready || '') : ''", timeout_s);
    if (ready.is_string() && !ready.get<std::string>().empty()) return ready.get<std::string>();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return "";
}

nlohmann::json Browser::evaluate(const std::string& expression, double timeout_s) {
  const nlohmann::json result = command(
      "Runtime.evaluate",
      {{"expression", expression}, {"awaitPromise", true}, {"returnByValue", true}}, timeout_s);
  if (result.contains("exceptionDetails")) {
    const nlohmann::json& details = result["exceptionDetails"];
    std::string text = details.value("text", "exception");
    if (details.contains("exception")) text += " " + details["exception"].value("description", "");
    throw std::runtime_error("evaluate(" + expression + "): " + text);
  }
  const nlohmann::json& value = result["result"];
  return value.contains("value") ? value["value"] : nlohmann::json();
}

std::string Browser::screenshot_png() {
  const nlohmann::json shot = command("Page.captureScreenshot", {{"format", "png"}}, 60);
  return base64_decode(shot.at("data").get<std::string>());
}

Image Browser::screenshot() {
  return read_png(screenshot_png());
}

void Browser::mouse(const std::string& type, double x, double y, double delta_y) {
  nlohmann::json params = {{"type", type}, {"x", x}, {"y", y}};
  if (type == "mousePressed" || type == "mouseReleased") {
    params["button"] = "left";
    params["clickCount"] = 1;
  }
  if (type == "mouseWheel") {
    params["deltaX"] = 0;
    params["deltaY"] = delta_y;
  }
  command("Input.dispatchMouseEvent", params, 30);
}

}  // namespace wearknit::test
