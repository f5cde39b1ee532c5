// The headless-browser harness itself (tests/browser.hpp): a page loads from
// file://, its script runs, its errors are seen, its pixels are read.
#include "tests/browser.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "tests/test_support.hpp"

namespace wearknit::test {
namespace {

TEST(BrowserTest, LoadsAPageFromAFileAndReadsItsScriptPixelsAndErrors) {
  WEARKNIT_REQUIRE_BROWSER(browser);
  TempDir dir("wearknit-browser-test");
  const auto page = dir.path() / "a page.html";
  std::ofstream(page) << R"(<!DOCTYPE html><html><body style="margin:0">
<canvas id="c" width="200" height="100"></canvas>
<script>
const c = document.getElementById("c").getContext("2d");
c.fillStyle = "#1f9d55"; c.fillRect(0, 0, 100, 100);
c.fillStyle = "#d64545"; c.fillRect(100, 0, 50, 100);
window.clicks = 0;
document.getElementById("c").addEventListener("click", () => ++window.clicks);
console.error("seen by the harness");
setTimeout(() => { document.body.dataset.ready = "1"; }, 100);
</script></body></html>)";
  ASSERT_EQ(browser->open(file_url(page)), "1");
  ASSERT_EQ(browser->console_errors().size(), 1u);
  EXPECT_NE(browser->console_errors()[0].find("seen by the harness"), std::string::npos);
  EXPECT_EQ(browser->evaluate("1 + 2").get<int>(), 3);
  EXPECT_EQ(browser->evaluate("Promise.resolve('later')").get<std::string>(), "later");
  EXPECT_THROW(browser->evaluate("undefinedName.x"), std::runtime_error);

  const Image shot = browser->screenshot();
  EXPECT_EQ(shot.width, 1280);
  EXPECT_NEAR(static_cast<double>(shot.count_near(0x1f9d55, 8)), 100.0 * 100, 50);
  EXPECT_NEAR(static_cast<double>(shot.count_near(0xd64545, 8)), 50.0 * 100, 50);

  browser->mouse("mousePressed", 20, 20);
  browser->mouse("mouseReleased", 20, 20);
  EXPECT_EQ(browser->evaluate("window.clicks").get<int>(), 1);
}

TEST(BrowserTest, AnUncaughtExceptionIsAConsoleError) {
  WEARKNIT_REQUIRE_BROWSER(browser);
  TempDir dir("wearknit-browser-test");
  const auto page = dir.path() / "throws.html";
  std::ofstream(page) << "<!DOCTYPE html><body><script>document.body.dataset.ready = '1';"
                         "throw new Error('thrown on purpose');</script></body>";
  ASSERT_EQ(browser->open(file_url(page)), "1");
  ASSERT_FALSE(browser->console_errors().empty());
  EXPECT_NE(browser->console_errors()[0].find("thrown on purpose"), std::string::npos);
}

TEST(BrowserTest, WebGlIsThereForThePages) {
  WEARKNIT_REQUIRE_BROWSER(browser);
  TempDir dir("wearknit-browser-test");
  const auto page = dir.path() / "gl.html";
  std::ofstream(page) << "<!DOCTYPE html><body><script>document.body.dataset.ready = "
                         "document.createElement('canvas').getContext('webgl') ? 'gl' : 'none';"
                         "</script></body>";
  EXPECT_EQ(browser->open(file_url(page)), "gl");
}

}  // namespace
}  // namespace wearknit::test
