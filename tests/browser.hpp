// Headless Chromium for the tests of the pages wearknit writes (index.html,
// simulate --html): a page is loaded from file:// and driven through the
// DevTools protocol over a pipe (--remote-debugging-pipe: JSON messages
// ended by a NUL byte on descriptors 3 and 4), so no network port, no
// WebSocket and no package beyond Debian's chromium are needed.
#pragma once

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace wearknit::test {

// A page's pixels, row by row from the top, 4 bytes (RGBA) each.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;
  // Pixels whose R, G and B are each within `tolerance` of `rgb` (0xRRGGBB).
  std::size_t count_near(std::uint32_t rgb, int tolerance) const;
};

// The pixels of a PNG file's bytes; throws std::runtime_error when they are
// not a PNG.
Image read_png(const std::string& bytes);

// file:// URL of an absolute or relative path.
std::string file_url(const std::filesystem::path& path);

class Browser {
 public:
  // Starts headless Chromium with one page of width x height CSS pixels.
  // The browser is $WEARKNIT_CHROMIUM, else chromium, chromium-browser or
  // google-chrome on the PATH. Returns null, with the reason in `why`, when
  // none can be started or it does not answer within 30 s.
  static std::unique_ptr<Browser> start(std::string* why, int width = 1280, int height = 900);
  ~Browser();
  Browser(const Browser&) = delete;
  Browser& operator=(const Browser&) = delete;

  // Loads `url`, waits for its load event and then until the page's
  // document.body.dataset.ready is set (pages written by wearknit set it to
  // "1" once they are interactive, "error" when they failed). Returns that
  // value ("" when the page never set it within the time). Clears the
  // console errors seen so far.
  std::string open(const std::string& url, double timeout_s = 60);

  // Evaluates a JavaScript expression in the page, awaiting it when it is a
  // promise, and returns its value as JSON. Throws std::runtime_error with
  // the page's exception text when it throws.
  nlohmann::json evaluate(const std::string& expression, double timeout_s = 60);

  // Errors the page reported since the last open(): console.error and
  // console.assert messages, uncaught exceptions and failed loads.
  const std::vector<std::string>& console_errors() const { return errors_; }

  // The page as it is on screen now: its pixels, or the PNG file's bytes.
  Image screenshot();
  std::string screenshot_png();

  // A mouse event at client coordinates: type is "mouseMoved",
  // "mousePressed", "mouseReleased" or "mouseWheel" (delta_y for the wheel).
  void mouse(const std::string& type, double x, double y, double delta_y = 0);

  // Sends one DevTools command to the page and returns its result.
  nlohmann::json command(const std::string& method, const nlohmann::json& params,
                         double timeout_s = 60);

 private:
  Browser() = default;
  nlohmann::json send(const std::string& method, const nlohmann::json& params,
                      const std::string& session, double timeout_s);
  // Reads messages until one arrives or the deadline passes; false at the
  // deadline. Events are handled as they come.
  bool pump(std::chrono::steady_clock::time_point deadline);
  void handle_event(const nlohmann::json& message);

  int pid_ = -1;
  int to_browser_ = -1;
  int from_browser_ = -1;
  std::filesystem::path profile_;
  std::string session_;
  std::string buffer_;
  int next_id_ = 0;
  std::vector<nlohmann::json> responses_;
  std::vector<std::string> errors_;
  bool loaded_ = false;
};

}  // namespace wearknit::test

// Starts a browser into `var` or skips the running test, visibly, saying why.
#define WEARKNIT_REQUIRE_BROWSER(var)                                     \
  std::string var##_why;                                                  \
  auto var = ::wearknit::test::Browser::start(&var##_why);                \
  if (!var) {                                                             \
    GTEST_SKIP() << "needs a headless browser (chromium): " << var##_why; \
  }
