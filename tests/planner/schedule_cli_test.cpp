// End-to-end tests of `wearknit schedule` on folders holding what the stitch
// stage writes (planner::write_smobj), read back with planner::parse_smobj.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "knitout/parser.hpp"
#include "planner/schedule/schedule.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "tests/planner/bed_check.hpp"
#include "tests/planner/schedule_fixtures.hpp"
#include "tests/test_support.hpp"

namespace planner {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using wearknit::test::TempDir;

TempDir plan_folder(const StitchMesh& mesh, const std::string& prefix) {
  TempDir dir(prefix);
  std::ostringstream text;
  write_smobj(text, mesh);
  wearknit::test::write_file(dir.path() / "stitch-mesh.smobj", text.str());
  return dir;
}

TEST(ScheduleCliTest, WritesPiecesTheScheduleFileAndTheReport) {
  const TempDir folder = plan_folder(fixtures::y_shape(12, 3, 4, 3), "sched-y");
  const fs::path& dir = folder.path();
  const auto result = wearknit::test::run_wearknit("schedule " + dir.string() + " --trials 5");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  // schedule.json is the stage's own file; report.json is the folder's
  // summary made from it.
  const json schedule = json::parse(wearknit::test::read_file(dir / "schedule.json"));
  EXPECT_EQ(schedule["format"], "wearknit-schedule 1");
  const json report = json::parse(wearknit::test::read_file(dir / "report.json"));
  EXPECT_EQ(report["schedule"], schedule["report"]);
  EXPECT_EQ(report["schedule"]["trials"], 5);
  EXPECT_EQ(report["schedule"]["cuts_per_trial"].size(), 5u);
  EXPECT_EQ(report["schedule"]["cuts"], 0);
  ASSERT_EQ(report["schedule"]["pieces"].size(), 1u);
  EXPECT_GT(report["schedule"]["pieces"][0]["estimated_knit_time_s"].get<double>(), 0);
  EXPECT_EQ(report["schedule"]["pieces"][0]["vm_warnings"], 0);
  EXPECT_EQ(report["schedule"]["pieces"][0]["bed_view"], "pieces/piece-1.svg");
  EXPECT_NE(wearknit::test::read_file(dir / "pieces" / "piece-1.svg").find("<svg"),
            std::string::npos);
  const std::string k = wearknit::test::read_file(dir / "pieces" / "piece-1.k");
  knitout::DiagnosticSink sink;
  const auto program = knitout::parse_string(k, "piece-1.k", sink);
  EXPECT_FALSE(sink.has_errors());
  EXPECT_TRUE(testing::check_bed(program).errors.empty());
  const json cuts = json::parse(wearknit::test::read_file(dir / "cuts.json"));
  EXPECT_TRUE(cuts["schedule_cuts"].empty());
  // The piece's DAT is what `wearknit dat` makes of its knitout, and reads back.
  EXPECT_EQ(report["schedule"]["pieces"][0]["dat"], "pieces/piece-1.dat");
  const fs::path again = dir / "again.dat";
  const auto converted = wearknit::test::run_wearknit(
      "dat " + (dir / "pieces" / "piece-1.k").string() + " -o " + again.string());
  ASSERT_EQ(converted.exit_code, 0) << converted.err;
  EXPECT_EQ(wearknit::test::read_file(dir / "pieces" / "piece-1.dat"),
            wearknit::test::read_file(again));
  const auto info =
      wearknit::test::run_wearknit("dat-info " + (dir / "pieces" / "piece-1.dat").string());
  EXPECT_EQ(info.exit_code, 0) << info.err;
}

TEST(ScheduleCliTest, CrossingBranchesGetASewCutAndTwoPieces) {
  const TempDir folder = plan_folder(fixtures::crossing_branches(12, 3, 30), "sched-x");
  const fs::path& dir = folder.path();
  const auto result =
      wearknit::test::run_wearknit("schedule " + dir.string() + " --trials 8 --pattern seed");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const json cuts = json::parse(wearknit::test::read_file(dir / "cuts.json"));
  ASSERT_EQ(cuts["schedule_cuts"].size(), 1u);
  EXPECT_EQ(cuts["schedule_cuts"][0]["label"], "sew");
  EXPECT_FALSE(cuts["schedule_cuts"][0]["faces"].empty());
  EXPECT_TRUE(fs::exists(dir / "pieces" / "piece-2.k"));
}

TEST(ScheduleCliTest, ARunWithFewerPiecesRemovesTheEarlierRunsExtraPieces) {
  // Two pieces, then a run that finds one piece: pieces/ must not keep the
  // second piece of the first run, which would be sent with the new one.
  const TempDir folder = plan_folder(fixtures::crossing_branches(12, 3, 30), "sched-stale");
  const fs::path& dir = folder.path();
  ASSERT_EQ(wearknit::test::run_wearknit("schedule " + dir.string() + " -q").exit_code, 0);
  for (const char* file : {"piece-2.k", "piece-2.dat", "piece-2.svg", "piece-2.layout.json"})
    ASSERT_TRUE(fs::exists(dir / "pieces" / file)) << file;
  wearknit::test::write_file(dir / "pieces" / "piece-2-notes.txt", "kept\n");
  wearknit::test::write_file(dir / "pieces" / "pieces.txt", "kept\n");
  std::ostringstream text;
  write_smobj(text, fixtures::rectangle(5, 3));
  wearknit::test::write_file(dir / "stitch-mesh.smobj", text.str());
  const auto again = wearknit::test::run_wearknit("schedule " + dir.string() + " -q");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  const json report = json::parse(wearknit::test::read_file(dir / "report.json"));
  ASSERT_EQ(report["schedule"]["pieces"].size(), 1u);
  EXPECT_TRUE(fs::exists(dir / "pieces" / "piece-1.k"));
  for (const char* file : {"piece-2.k", "piece-2.dat", "piece-2.svg", "piece-2.layout.json"})
    EXPECT_FALSE(fs::exists(dir / "pieces" / file)) << file;
  EXPECT_TRUE(fs::exists(dir / "pieces" / "piece-2-notes.txt"));
  EXPECT_TRUE(fs::exists(dir / "pieces" / "pieces.txt"));
}

TEST(ScheduleCliTest, MissingStitchMeshIsAnIoError) {
  const TempDir folder("sched-empty");
  const fs::path& dir = folder.path();
  const auto result = wearknit::test::run_wearknit("schedule " + dir.string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err,
            (dir / "stitch-mesh.smobj").string() +
                ": error: [S900] cannot open the stitch mesh (run wearknit stitch-mesh)\n");
}

TEST(ScheduleCliTest, UnschedulableMeshIsInvalidInput) {
  // A valid stitch mesh (it passes planner::check) that no machine can knit:
  // one row of 600 stitches on a 540-needle bed.
  const TempDir folder = plan_folder(fixtures::rectangle(600, 1), "sched-wide");
  const fs::path& dir = folder.path();
  const auto result = wearknit::test::run_wearknit("schedule " + dir.string() + " --trials 1");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err, (dir / "stitch-mesh.smobj").string() +
                            ": error: [S910] piece 1 is 600 needles wide; the machine has 540: "
                            "make the garment smaller (plan --size-mm, cut --scale) or knit it "
                            "at a coarser gauge (fewer needles per inch)\n");
  EXPECT_FALSE(fs::exists(dir / "pieces"));
}

TEST(ScheduleCliTest, NarrowerTwinIsScheduled) {
  const TempDir folder = plan_folder(fixtures::rectangle(500, 1), "sched-narrow");
  const fs::path& dir = folder.path();
  const auto result = wearknit::test::run_wearknit("schedule " + dir.string() + " --trials 1 -q");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(fs::exists(dir / "pieces" / "piece-1.k"));
}

// The stitch stage's reader judges the file: its diagnostics (P08x) name the
// line, and nothing is written.
TEST(ScheduleCliTest, MalformedStitchMeshIsInvalidInput) {
  const TempDir folder("sched-malformed");
  const fs::path& dir = folder.path();
  wearknit::test::write_file(dir / "stitch-mesh.smobj",
                             "L knit -l1 y1 +l1 y1\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                             "f 1 2 3 4\nT 2\n");
  const auto result = wearknit::test::run_wearknit("schedule " + dir.string());
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err, (dir / "stitch-mesh.smobj").string() +
                            ":7: error: [P083] face 1 has library index 2 (1 entries)\n");
  EXPECT_FALSE(fs::exists(dir / "pieces"));
  EXPECT_FALSE(fs::exists(dir / "report.json"));
}

TEST(ScheduleCliTest, WellFormedTwinOfTheMalformedMeshIsScheduled) {
  const TempDir folder("sched-wellformed");
  const fs::path& dir = folder.path();
  wearknit::test::write_file(dir / "stitch-mesh.smobj",
                             "L knit -l1 y1 +l1 y1\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                             "f 1 2 3 4\nT 1\n");
  const auto result = wearknit::test::run_wearknit("schedule " + dir.string() + " -q");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_TRUE(fs::exists(dir / "pieces" / "piece-1.k"));
}

TEST(ScheduleCliTest, TrialsAndTimeBudgetExcludeEachOther) {
  const TempDir folder = plan_folder(fixtures::rectangle(3, 2), "sched-opts");
  const fs::path& dir = folder.path();
  const auto result =
      wearknit::test::run_wearknit("schedule " + dir.string() + " --trials 3 --time-budget 1");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err, "wearknit schedule: give --trials or --time-budget, not both\n");
}

TEST(ScheduleCliTest, MaxShiftBeyondTheRackingLimitIsAUsageError) {
  const TempDir folder = plan_folder(fixtures::rectangle(3, 2), "sched-shift");
  const fs::path& dir = folder.path();
  const auto result = wearknit::test::run_wearknit("schedule " + dir.string() + " --max-shift 9");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err, "wearknit schedule: --max-shift takes 0 to 8 (the racking limit)\n");
}

TEST(ScheduleCliTest, MaxShiftIsReported) {
  const TempDir folder = plan_folder(fixtures::crossing_branches(12, 3, 10), "sched-shift-ok");
  const fs::path& dir = folder.path();
  const auto moved = wearknit::test::run_wearknit("schedule " + dir.string() + " --trials 8 -q");
  ASSERT_EQ(moved.exit_code, 0) << moved.err;
  json report = json::parse(wearknit::test::read_file(dir / "report.json"));
  EXPECT_EQ(report["schedule"]["max_shift"], kMaxPatchShift);
  EXPECT_EQ(report["schedule"]["patches_moved"], 1);
  EXPECT_EQ(report["schedule"]["cuts"], 0);
  EXPECT_EQ(report["schedule"]["loops_set_aside"], 0);
  // Patches kept in place: the three loops held for the branch knit second
  // are set aside instead.
  const auto aside =
      wearknit::test::run_wearknit("schedule " + dir.string() + " --trials 8 --max-shift 0 -q");
  ASSERT_EQ(aside.exit_code, 0) << aside.err;
  report = json::parse(wearknit::test::read_file(dir / "report.json"));
  EXPECT_EQ(report["schedule"]["patches_moved"], 0);
  EXPECT_EQ(report["schedule"]["max_aside"], kMaxAside);
  EXPECT_EQ(report["schedule"]["loops_set_aside"], 3);
  EXPECT_EQ(report["schedule"]["cuts"], 0);
  const auto fixed = wearknit::test::run_wearknit("schedule " + dir.string() +
                                                  " --trials 8 --max-shift 0 --max-aside 0 -q");
  ASSERT_EQ(fixed.exit_code, 0) << fixed.err;
  report = json::parse(wearknit::test::read_file(dir / "report.json"));
  EXPECT_EQ(report["schedule"]["patches_moved"], 0);
  EXPECT_EQ(report["schedule"]["loops_set_aside"], 0);
  EXPECT_EQ(report["schedule"]["cuts"], 1);
}

TEST(ScheduleCliTest, MaxAsideBeyondTheRackingLimitIsAUsageError) {
  const TempDir folder = plan_folder(fixtures::rectangle(3, 2), "sched-aside");
  const fs::path& dir = folder.path();
  for (const char* value : {"9", "-1"}) {
    const auto result =
        wearknit::test::run_wearknit("schedule " + dir.string() + " --max-aside " + value);
    EXPECT_EQ(result.exit_code, 2) << value;
    EXPECT_EQ(result.err, "wearknit schedule: --max-aside takes 0 to 8 (the racking limit)\n");
  }
}

TEST(ScheduleCliTest, NegativeImproveIsAUsageError) {
  const TempDir folder = plan_folder(fixtures::rectangle(3, 2), "sched-improve");
  const fs::path& dir = folder.path();
  const auto result = wearknit::test::run_wearknit("schedule " + dir.string() + " --improve -1");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err, "wearknit schedule: --improve must not be negative\n");
}

TEST(ScheduleCliTest, ImproveAndTheRandomOrdersCutsAreReported) {
  const TempDir folder = plan_folder(fixtures::crossing_branches(12, 3, 10), "sched-improve-ok");
  const fs::path& dir = folder.path();
  for (int improve : {0, 3}) {
    const auto result = wearknit::test::run_wearknit(
        "schedule " + dir.string() + " --trials 8 --improve " + std::to_string(improve) + " -q");
    ASSERT_EQ(result.exit_code, 0) << result.err;
    const json report = json::parse(wearknit::test::read_file(dir / "report.json"));
    EXPECT_EQ(report["schedule"]["improve"], improve);
    EXPECT_GE(report["schedule"]["random_cuts"].get<int>(), report["schedule"]["cuts"].get<int>());
    if (improve == 0) {
      EXPECT_EQ(report["schedule"]["random_cuts"], report["schedule"]["cuts"]);
    }
  }
}

TEST(ScheduleCliTest, TimeBudgetAloneIsAccepted) {
  const TempDir folder = plan_folder(fixtures::rectangle(3, 2), "sched-budget");
  const fs::path& dir = folder.path();
  const auto result =
      wearknit::test::run_wearknit("schedule " + dir.string() + " --time-budget 0.05 --quiet");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, "");
}

}  // namespace
}  // namespace planner
