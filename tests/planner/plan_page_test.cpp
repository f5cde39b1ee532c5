// The plan page (planner/viewer/plan_page.hpp, `wearknit view`): the data it
// collects from a plan folder made here by the real stages, a cut-only folder
// first and the same folder once stitch-meshed, scheduled and assembled.
#include "planner/viewer/plan_page.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/shapes.hpp"
#include "tests/test_support.hpp"

namespace wearknit::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class PlanPageTest : public ::testing::Test {
 protected:
  // One folder for the suite: a small ellipsoid cover, cut.
  static void SetUpTestSuite() {
    dir_ = new fs::path(make_temp_dir("plan-page"));
    {
      std::ofstream out(*dir_ / "garment.obj");
      planner::write_obj(out, planner::quad_ellipsoid(14, 1.5, 4), "test garment, mm");
    }
    const auto r = run_wearknit("cut '" + (*dir_ / "garment.obj").string() +
                                "' -q --no-pictures -o '" + dir_->string() + "'");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  // Stitch mesh, schedule and assembly guide, once.
  static void finish_plan() {
    if (finished_) return;
    finished_ = true;
    const std::string d = "'" + dir_->string() + "'";
    for (const std::string& args : {"stitch-mesh " + d + " -q --no-picture",
                                    "schedule " + d + " --trials 2 -q", "assembly " + d + " -q"}) {
      const auto r = run_wearknit(args);
      ASSERT_EQ(r.exit_code, 0) << args << '\n' << r.err;
    }
  }
  static fs::path* dir_;
  static bool finished_;
};
fs::path* PlanPageTest::dir_ = nullptr;
bool PlanPageTest::finished_ = false;

TEST_F(PlanPageTest, ACutFolderShowsItsCutArcs) {
  if (finished_) GTEST_SKIP() << "the folder was finished by an earlier case";
  const planner::viewer::PlanPageData page = planner::viewer::collect_plan_page(*dir_);
  const json cut = json::parse(read_file(*dir_ / "cut.json"));
  EXPECT_EQ(page.meta.at("seam_kind"), "cut-arc");
  ASSERT_EQ(page.meta.at("seams").size(), cut.at("arcs").size());
  for (const json& seam : page.meta.at("seams")) {
    EXPECT_FALSE(seam.at("labelled").get<bool>());  // no wearability.json
    EXPECT_FALSE(seam.at("p3").empty());
  }
  EXPECT_EQ(page.meta.at("garment").at("kind"), "cut disc");
  EXPECT_TRUE(page.meta.at("pieces").empty());
  EXPECT_FALSE(page.meta.at("notes").empty());  // says that the seams come later
}

TEST_F(PlanPageTest, SeamsMatchTheAssemblyGuide) {
  finish_plan();
  const planner::viewer::PlanPageData page = planner::viewer::collect_plan_page(*dir_);
  const json assembly = json::parse(read_file(*dir_ / "assembly.json")).at("summary");
  const json& seams = page.meta.at("seams");
  // One entry per seam or part of a seam, as the guide draws them.
  ASSERT_EQ(static_cast<int>(seams.size()), assembly.at("parts").get<int>());
  EXPECT_EQ(page.meta.at("sewn"), assembly.at("sewn"));
  EXPECT_EQ(static_cast<int>(page.meta.at("pieces").size()), assembly.at("pieces").get<int>());
  // Numbered 1..n in closing order, the sewn ones first, the parts of a
  // seam in a row, as in the guide; each names both its pieces with their
  // stitch sides.
  const int sewn = assembly.at("sewn").get<int>();
  const std::string svg = read_file(*dir_ / "assembly.svg");
  int number = 0;
  for (std::size_t i = 0; i < seams.size(); ++i) {
    const json& s = seams[i];
    const int part = s.contains("part") ? s.at("part").at(0).get<int>() : 1;
    if (part == 1) ++number;
    EXPECT_EQ(s.at("number").get<int>(), number);
    const std::string name =
        std::to_string(number) + (s.contains("part") ? "." + std::to_string(part) : "");
    EXPECT_EQ(s.at("name"), name);
    EXPECT_EQ(s.at("label"), number <= sewn ? "sew" : "lace");
    const std::string line = s.at("text").get<std::string>();
    EXPECT_EQ(line.rfind(name + "  " + s.at("label").get<std::string>() + "  piece ", 0), 0u)
        << line;
    EXPECT_NE(svg.find(">" + line + "<"), std::string::npos) << "not a line of the guide: " << line;
    ASSERT_EQ(s.at("sides").size(), 2u);
    for (const json& side : s.at("sides")) {
      EXPECT_GE(side.at("piece").get<int>(), 1);
      EXPECT_EQ(side.at("flat").size() % 5, 0u);
    }
    EXPECT_NE(
        line.find(", " + std::to_string(s.at("sides")[0].at("stitch_sides").get<int>()) + " / " +
                  std::to_string(s.at("sides")[1].at("stitch_sides").get<int>()) + " stitch sides"),
        std::string::npos)
        << line;
    EXPECT_GT(s.at("length_mm").get<double>(), 0);
  }
  EXPECT_EQ(number, assembly.at("seams").get<int>());
  // The stitch mesh with its face types, and every piece's figures.
  EXPECT_EQ(page.meta.at("garment").at("kind"), "stitch mesh");
  int faces = 0;
  for (const auto& [type, n] : page.meta.at("garment").at("face_types").items())
    faces += n.get<int>();
  EXPECT_EQ(faces, page.meta.at("garment").at("faces").get<int>());
  for (const json& piece : page.meta.at("pieces")) {
    EXPECT_TRUE(piece.at("figures").contains("passes"));
    EXPECT_TRUE(piece.at("figures").contains("estimated_knit_time_s"));
    // Each piece's knitout as the bed view's timeline, with its source.
    ASSERT_TRUE(piece.contains("bed_timeline"));
    ASSERT_TRUE(piece.contains("bed_source"));
    const auto has_block = [&](const std::string& id) {
      return std::any_of(page.blocks.begin(), page.blocks.end(),
                         [&](const auto& block) { return block.id == id; });
    };
    EXPECT_TRUE(has_block(piece["bed_timeline"].get<std::string>()));
    EXPECT_TRUE(has_block(piece["bed_source"].get<std::string>()));
  }
}

TEST_F(PlanPageTest, ThePageIsOneFileThatFetchesNothing) {
  finish_plan();
  const auto r = run_wearknit("view '" + dir_->string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("open: " + (*dir_ / "index.html").string(), 0), 0u) << r.out;
  const std::string html = read_file(*dir_ / "index.html");
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  EXPECT_EQ(html.find(" src=\""), std::string::npos);  // no script or image from elsewhere
  EXPECT_NE(html.find("id=\"plan\""), std::string::npos);
  EXPECT_NE(html.find("window.wkPlan"), std::string::npos);
}

TEST(PlanPageVerbTest, RefusesWhatIsNotAFolder) {
  const auto r = run_wearknit("view /nonexistent/plan");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("/nonexistent/plan: error: not a folder"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace wearknit::test
