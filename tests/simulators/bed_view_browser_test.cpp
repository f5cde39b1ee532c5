// The HTML bed view in headless Chromium (tests/browser.hpp): the page of
// bed::write_bed_page opens from file:// without errors, and the viewer's
// current sweep, source line and source text agree with the knitout.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "knitout/generate.hpp"
#include "knitout/parser.hpp"
#include "simulators/bed/bed_page.hpp"
#include "simulators/bed/bed_timeline.hpp"
#include "simulators/bed/validate.hpp"
#include "tests/browser.hpp"
#include "tests/test_support.hpp"

namespace bed {
namespace {

using wearknit::test::file_url;
using wearknit::test::TempDir;

struct Written {
  std::filesystem::path page;
  std::vector<BedTimeline::Sweep> sweeps;
  std::vector<std::string> lines;  // lines[n - 1] is source line n
};

Written write(const TempDir& dir, const std::string& name, const std::string& text) {
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(text, name, sink);
  BedTimeline timeline;
  MachineOptions options;
  options.observer = &timeline;
  validate(program, default_profile(), sink, name, options);
  BedPageInput input;
  input.title = name;
  input.timeline = timeline.serialize(sink.sorted());
  input.source_text = text;
  Written w;
  w.page = dir.path() / (name + ".html");
  std::ofstream out(w.page, std::ios::binary);
  write_bed_page(out, input);
  w.sweeps = timeline.sweeps();
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) w.lines.push_back(line);
  return w;
}

TEST(BedViewBrowserTest, TheScrubbedSweepShowsItsSourceLine) {
  WEARKNIT_REQUIRE_BROWSER(browser);
  TempDir dir("wearknit-bed-view");
  knitout::SheetParams params;
  params.width_needles = 24;
  params.rows = 30;
  const Written w = write(dir, "sheet", knitout::sheet_text(params));
  ASSERT_GT(w.sweeps.size(), 30u);
  ASSERT_EQ(browser->open(file_url(w.page)), "1");
  EXPECT_TRUE(browser->console_errors().empty()) << browser->console_errors()[0];
  EXPECT_EQ(browser->evaluate("wkBedView.sweeps()").get<std::size_t>(), w.sweeps.size());
  for (const std::size_t k :
       {std::size_t{0}, std::size_t{7}, w.sweeps.size() / 2, w.sweeps.size() - 1}) {
    const std::string sweep = std::to_string(k);
    EXPECT_EQ(browser->evaluate("wkBedView.goToSweep(" + sweep + ")").get<std::size_t>(), k);
    EXPECT_EQ(browser->evaluate("wkBedView.currentSweep()").get<std::size_t>(), k);
    const auto line = browser->evaluate("wkBedView.currentLine()").get<std::uint32_t>();
    EXPECT_EQ(line, w.sweeps[k].first_line) << "sweep " << k;
    ASSERT_GE(line, 1u);
    ASSERT_LE(line, w.lines.size());
    EXPECT_EQ(browser->evaluate("wkBedView.currentSourceText()").get<std::string>(),
              w.lines[line - 1])
        << "sweep " << k;
    // The page says the same under the scrubber.
    EXPECT_NE(browser->evaluate("document.querySelector('.bv-source').textContent")
                  .get<std::string>()
                  .find(w.lines[line - 1]),
              std::string::npos);
  }
  // Keys move the sweep; the wheel zooms in and the reset shows the whole bed.
  browser->evaluate("wkBedView.goToSweep(3)");
  browser->command("Input.dispatchKeyEvent", {{"type", "keyDown"},
                                              {"key", "ArrowRight"},
                                              {"code", "ArrowRight"},
                                              {"windowsVirtualKeyCode", 39}});
  EXPECT_EQ(browser->evaluate("wkBedView.currentSweep()").get<int>(), 4);
  const nlohmann::json whole = browser->evaluate("wkBedView.view()");
  browser->mouse("mouseWheel", 300, 300, -400);
  const nlohmann::json zoomed = browser->evaluate("wkBedView.view()");
  EXPECT_LT(zoomed["n1"].get<double>() - zoomed["n0"].get<double>(),
            whole["n1"].get<double>() - whole["n0"].get<double>());
  browser->evaluate("wkBedView.resetZoom()");
  EXPECT_EQ(browser->evaluate("wkBedView.view()"), whole);
  // Pointing at a needle names it with its source line.
  browser->mouse("mouseMoved", 300, 400);
  EXPECT_NE(browser->evaluate("document.querySelector('.bv-hover').textContent")
                .get<std::string>()
                .find("sweep"),
            std::string::npos);
  // The fabric is drawn: carrier 3 of the sheet is the palette's third colour.
  EXPECT_GT(browser->screenshot().count_near(0x33a02c, 10), 2000u);
  EXPECT_TRUE(browser->console_errors().empty()) << browser->console_errors()[0];
}

TEST(BedViewBrowserTest, ListsTheMachinesDiagnosticsAndJumpsToThem) {
  WEARKNIT_REQUIRE_BROWSER(browser);
  TempDir dir("wearknit-bed-view");
  const Written w = write(dir, "bad",
                          ";!knitout-2\n;;Carriers: 1 2 3\nin 3\ntuck + f1 3\ntuck + f2 3\n"
                          "knit - f2 3\nknit - f1 3\nknit + f5 2\nout 3\n");
  ASSERT_EQ(browser->open(file_url(w.page)), "1");
  EXPECT_TRUE(browser->console_errors().empty()) << browser->console_errors()[0];
  EXPECT_GE(browser->evaluate("document.querySelectorAll('.bv-diag').length").get<int>(), 1);
  const std::string first_code =
      browser->evaluate("document.querySelector('.bv-diag td:nth-child(4)').textContent")
          .get<std::string>();
  EXPECT_EQ(first_code, "V004");
  browser->evaluate("document.querySelector('.bv-diag').click()");
  EXPECT_EQ(browser->evaluate("wkBedView.currentLine()").get<int>(), 8);
  EXPECT_EQ(browser->evaluate("wkBedView.currentSourceText()").get<std::string>(), "knit + f5 2");
}

}  // namespace
}  // namespace bed
