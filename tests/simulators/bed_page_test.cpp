// The HTML bed view page: one self-contained file.
#include "simulators/bed/bed_page.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "knitout/parser.hpp"
#include "simulators/bed/bed_timeline.hpp"
#include "simulators/bed/web_assets.hpp"

namespace bed {
namespace {

std::string page_of(std::string_view source_text) {
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(source_text, "t.k", sink);
  BedPageInput input;
  input.title = "t.k <1>";
  input.subtitle = "on swg091n2";
  input.timeline = timeline_bytes(program, default_profile(), "t.k", sink);
  input.source_text = source_text;
  std::ostringstream out;
  write_bed_page(out, input);
  return out.str();
}

TEST(BedPageTest, IsOneFileThatLoadsNothing) {
  const std::string page =
      page_of(";!knitout-2\n;;Carriers: 1\nin 1\ntuck + f1 1\nknit - f1 1\nout 1\n");
  EXPECT_EQ(page.substr(0, 15), "<!DOCTYPE html>");
  EXPECT_NE(page.find("<title>t.k &lt;1&gt;</title>"), std::string::npos);
  EXPECT_NE(page.find("<script type=\"application/octet-stream\" id=\"bed-timeline\">"),
            std::string::npos);
  EXPECT_NE(page.find("<script type=\"application/octet-stream\" id=\"bed-source\">"),
            std::string::npos);
  // The viewer, its page script and style are inline.
  EXPECT_NE(page.find(std::string(web_asset("bed_view.js")).substr(0, 200)), std::string::npos);
  EXPECT_NE(page.find("wk.mountBedView(container"), std::string::npos);
  EXPECT_NE(page.find(".bv-stage"), std::string::npos);
  // Nothing is fetched: no URL and no element that loads a file.
  EXPECT_EQ(page.find("http://"), std::string::npos);
  EXPECT_EQ(page.find("https://"), std::string::npos);
  EXPECT_EQ(page.find(" src="), std::string::npos);
  EXPECT_EQ(page.find("<link"), std::string::npos);
  EXPECT_EQ(page.find("fetch("), std::string::npos);
  EXPECT_EQ(page.find("import("), std::string::npos);
}

TEST(BedPageTest, TheViewerScriptsExist) {
  EXPECT_NE(web_asset("bed_view.js").find("wk.mountBedView = function"), std::string::npos);
  EXPECT_NE(web_asset("bed_page.js").find("window.wkBedView"), std::string::npos);
  EXPECT_FALSE(web_asset("bed_view.css").empty());
}

}  // namespace
}  // namespace bed
