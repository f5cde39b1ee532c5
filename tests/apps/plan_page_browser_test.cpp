// The demo's plan page (DIR/index.html, planner/viewer/plan_page.hpp) in
// headless Chromium from file:// (tests/browser.hpp): it loads with no
// console error, draws the garment with WebGL (and on a 2D canvas with
// ?gl=0), shows sew and lace seams in their colours, and a seam clicked in
// the 3D view, or selected, is the one the info panel names.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/browser.hpp"
#include "tests/test_support.hpp"

namespace wearknit::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class PlanPageBrowserTest : public ::testing::Test {
 protected:
  // One demo for the suite.
  static void SetUpTestSuite() {
    dir_ = new fs::path(make_temp_dir("plan-page-browser") / "demo");
    const auto r = run_wearknit("demo -q -o '" + dir_->string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // The page to open is the first thing the demo says.
    ASSERT_EQ(r.out.rfind("open: " + (*dir_ / "index.html").string() + "\n", 0), 0u) << r.out;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static fs::path* dir_;
};
fs::path* PlanPageBrowserTest::dir_ = nullptr;

std::string errors_of(const Browser& browser) {
  std::string all;
  for (const std::string& e : browser.console_errors()) all += e + "\n";
  return all;
}

TEST_F(PlanPageBrowserTest, LoadsWithWebGlAndShowsTheSeamsInTheirColours) {
  WEARKNIT_REQUIRE_BROWSER(browser);
  ASSERT_EQ(browser->open(file_url(*dir_ / "index.html")), "1") << errors_of(*browser);
  EXPECT_TRUE(browser->console_errors().empty()) << errors_of(*browser);
  EXPECT_EQ(browser->evaluate("wkPlan.renderer()"), "webgl");
  const json seams = browser->evaluate("wkPlan.seams()");
  ASSERT_FALSE(seams.empty());
  // Each label the demo has, with one of its seams turned towards the viewer.
  for (const std::string label : {"sew", "lace"}) {
    int number = 0;
    for (const json& s : seams) {
      if (s.at("label") == label) {
        number = s.at("number").get<int>();
        break;
      }
    }
    if (number == 0) continue;
    ASSERT_TRUE(browser->evaluate("wkPlan.selectSeam(" + std::to_string(number) + ")").get<bool>());
    browser->evaluate("wkPlan.frame()");
    const Image shot = browser->screenshot();
    const std::uint32_t colour = label == "sew" ? 0x1f9d55 : 0xd64545;
    EXPECT_GT(shot.count_near(colour, 24), 200u) << label << " seam " << number;
  }
  EXPECT_TRUE(browser->console_errors().empty()) << errors_of(*browser);
}

TEST_F(PlanPageBrowserTest, AClickOnASeamShowsItsNumber) {
  WEARKNIT_REQUIRE_BROWSER(browser);
  ASSERT_EQ(browser->open(file_url(*dir_ / "index.html")), "1") << errors_of(*browser);
  const json seams = browser->evaluate("wkPlan.seams()");
  ASSERT_GE(seams.size(), 2u);
  const int number = seams.back().at("number").get<int>();
  // Selected by number: the info panel names it.
  ASSERT_TRUE(browser->evaluate("wkPlan.selectSeam(" + std::to_string(number) + ")").get<bool>());
  EXPECT_EQ(browser->evaluate("wkPlan.selectedSeam()").get<int>(), number);
  const std::string text = browser->evaluate("wkPlan.seamInfoText()").get<std::string>();
  EXPECT_NE(text.find("seam " + std::to_string(number) + ":"), std::string::npos) << text;
  EXPECT_NE(text.find("piece"), std::string::npos) << text;
  // Another seam, clicked where the 3D view draws it.
  const int first = seams.front().at("number").get<int>();
  browser->evaluate("wkPlan.selectSeam(null)");
  const json at = browser->evaluate("wkPlan.seamScreenPoint(" + std::to_string(first) + ")");
  ASSERT_TRUE(at.is_object()) << at;
  const double x = at.at("x").get<double>(), y = at.at("y").get<double>();
  browser->mouse("mouseMoved", x, y);
  browser->mouse("mousePressed", x, y);
  browser->mouse("mouseReleased", x, y);
  EXPECT_EQ(browser->evaluate("wkPlan.selectedSeam()").get<int>(), first);
  EXPECT_NE(browser->evaluate("wkPlan.seamInfoText()")
                .get<std::string>()
                .find("seam " + std::to_string(first) + ":"),
            std::string::npos);
  EXPECT_TRUE(browser->console_errors().empty()) << errors_of(*browser);
}

TEST_F(PlanPageBrowserTest, WithoutWebGlTheCanvasDrawsIt) {
  WEARKNIT_REQUIRE_BROWSER(browser);
  ASSERT_EQ(browser->open(file_url(*dir_ / "index.html") + "?gl=0"), "1") << errors_of(*browser);
  EXPECT_EQ(browser->evaluate("wkPlan.renderer()"), "canvas");
  const json seams = browser->evaluate("wkPlan.seams()");
  ASSERT_FALSE(seams.empty());
  const int number = seams.front().at("number").get<int>();
  browser->evaluate("wkPlan.selectSeam(" + std::to_string(number) + ")");
  const Image shot = browser->screenshot();
  const std::uint32_t colour = seams.front().at("label") == "sew" ? 0x1f9d55 : 0xd64545;
  EXPECT_GT(shot.count_near(colour, 24), 200u);
  EXPECT_TRUE(browser->console_errors().empty()) << errors_of(*browser);
}

// The Pieces tab shows piece 1 on the needle bed as the interactive bed
// view: a sweep scrubbed to shows its own line of pieces/piece-1.k.
TEST_F(PlanPageBrowserTest, ThePiecesTabScrubsThroughAPiecesKnitout) {
  WEARKNIT_REQUIRE_BROWSER(browser);
  ASSERT_EQ(browser->open(file_url(*dir_ / "index.html") + "#pieces"), "1") << errors_of(*browser);
  json sweeps;
  for (int i = 0; i < 100 && sweeps.is_null(); ++i) {
    sweeps = browser->evaluate(
        "new Promise(r => setTimeout(() => r(window.wkPlanBedView ? "
        "wkPlanBedView.sweeps() : null), 50))");
  }
  ASSERT_TRUE(sweeps.is_number()) << errors_of(*browser);
  ASSERT_GT(sweeps.get<int>(), 10);
  const int k = sweeps.get<int>() / 2;
  browser->evaluate("wkPlanBedView.goToSweep(" + std::to_string(k) + ")");
  EXPECT_EQ(browser->evaluate("wkPlanBedView.currentSweep()").get<int>(), k);
  const auto line = browser->evaluate("wkPlanBedView.currentLine()").get<std::size_t>();
  // The text shown is that line of the piece's file.
  std::ifstream in(*dir_ / "pieces" / "piece-1.k");
  std::string text;
  for (std::size_t n = 1; n <= line && std::getline(in, text); ++n) {
  }
  EXPECT_EQ(browser->evaluate("wkPlanBedView.currentSourceText()").get<std::string>(), text);
  EXPECT_TRUE(browser->console_errors().empty()) << errors_of(*browser);
}

}  // namespace
}  // namespace wearknit::test
