// `wearknit plan` and `wearknit demo` end to end: the plan folder of
// DESIGN.md, every piece judged by the needle-bed VM, the failure of a stage,
// sending the pieces, and the same result on every run although two branches
// run concurrently.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "knitout/parser.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/shapes.hpp"
#include "simulators/bed/profile.hpp"
#include "simulators/bed/validate.hpp"
#include "tests/test_support.hpp"

namespace wearknit::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::read_file;
using test::run_wearknit;
using test::run_wearknit_and_kill;
using test::write_file;

// An all-quad ellipsoid as OBJ text (planner::quad_ellipsoid).
std::string ellipsoid_obj(double radius, double z_stretch, int n) {
  std::ostringstream obj;
  planner::write_obj(obj, planner::quad_ellipsoid(radius, z_stretch, n));
  return obj.str();
}

json read_json(const fs::path& path) {
  return json::parse(read_file(path));
}

// Every piece of the folder's report: VM-valid knitout, a DAT that reads back.
void expect_valid_pieces(const fs::path& dir) {
  const json report = read_json(dir / "report.json");
  const json& pieces = report["schedule"]["pieces"];
  ASSERT_GE(pieces.size(), 1u);
  for (const json& piece : pieces) {
    const fs::path k = dir / piece["knitout"].get<std::string>();
    knitout::DiagnosticSink sink;
    const knitout::Program program = knitout::parse_file(k.string(), sink);
    bed::validate(program, bed::default_profile(), sink, k.string());
    EXPECT_FALSE(sink.has_errors()) << k;
    EXPECT_GT(program.instructions.size(), 100u) << k;
    const fs::path dat = dir / piece["dat"].get<std::string>();
    const auto info = run_wearknit("dat-info " + dat.string());
    EXPECT_EQ(info.exit_code, 0) << dat << info.err;
  }
}

// The plans are shared by the tests (each costs seconds, more under the
// sanitizers): plan "a" sends its pieces to a folder, plan "b" the same
// garment to the loopback machine; the two must give the same files.
class PlanTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(test::make_temp_dir("wearknit-plan"));
    // A small egg and its cover 1 mm out: ~800 stitches, 7 cut-arcs.
    write_file(*dir_ / "wearer.obj", ellipsoid_obj(12, 1.6, 6));
    write_file(*dir_ / "garment.obj", ellipsoid_obj(13, 1.55, 6));
    fs::create_directories(*dir_ / "machine");
    plan_a_ = new test::CommandResult(
        run_wearknit(plan_command("a", "--send dir:" + (*dir_ / "machine").string())));
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete plan_a_;
    delete plan_b_;
  }
  static std::string plan_command(const std::string& out, const std::string& more = "") {
    return "plan " + (*dir_ / "garment.obj").string() + " --wearer " +
           (*dir_ / "wearer.obj").string() + " -o " + (*dir_ / out).string() +
           " --wear-trials 2 --threads 2 " +
           (more.find("--trials") == std::string::npos ? "--trials 20 " : "") + more;
  }
  static const test::CommandResult& plan_b() {
    if (plan_b_ == nullptr)
      plan_b_ = new test::CommandResult(
          run_wearknit(plan_command("b", "-q --send loopback:" + (*dir_ / "loopback").string())));
    return *plan_b_;
  }
  static fs::path* dir_;
  static test::CommandResult* plan_a_;
  static test::CommandResult* plan_b_;
};
fs::path* PlanTest::dir_ = nullptr;
test::CommandResult* PlanTest::plan_a_ = nullptr;
test::CommandResult* PlanTest::plan_b_ = nullptr;

TEST_F(PlanTest, WritesThePlanFolderWithEveryStage) {
  const auto& result = *plan_a_;
  ASSERT_EQ(result.exit_code, 0) << result.err << result.out;
  const fs::path plan = *dir_ / "a";
  for (const char* name : {"proxy.obj", "cut-mesh.obj", "cuts.json", "labels.json", "report.json",
                           "wearer.obj", "stitch-mesh.smobj", "wearability.png", "plan.log",
                           "assembly.svg", "assembly.pdf", "assembly-3d.png"})
    EXPECT_TRUE(fs::is_regular_file(plan / name)) << name;
  for (const char* name : {"cut.json", "wearability.json", "stitch-mesh.json", "schedule.json",
                           "assembly.json", "plan.json"})
    EXPECT_TRUE(fs::is_regular_file(plan / name)) << name;
  expect_valid_pieces(plan);

  // Both branches' results are in the merged files.
  const json cuts = read_json(plan / "cuts.json");
  ASSERT_GE(cuts["arcs"].size(), 1u);
  int sewn = 0, laced = 0;
  for (const json& arc : cuts["arcs"]) {
    EXPECT_TRUE(arc["label"] == "sew" || arc["label"] == "lace") << arc.dump();
    sewn += arc["label"] == "sew";
    laced += arc["label"] == "lace";
  }
  EXPECT_TRUE(cuts.contains("wearability"));
  EXPECT_TRUE(cuts.contains("schedule_cuts"));
  const json report = read_json(plan / "report.json");
  for (const char* member : {"input", "proxy", "time_s", "stitch_mesh", "schedule", "plan"})
    EXPECT_TRUE(report.contains(member)) << member;
  std::vector<std::string> names;
  for (const json& stage : report["plan"]["stages"]) {
    names.push_back(stage["name"]);
    EXPECT_EQ(stage["exit"], 0) << stage.dump();
    EXPECT_GE(stage["time_s"].get<double>(), 0.0);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"cut", "wearability", "stitch-mesh", "schedule",
                                             "assembly", "send"}));
  const json& summary = report["plan"]["summary"];
  EXPECT_EQ(summary["sewn"], sewn);
  EXPECT_EQ(summary["laced"], laced);
  EXPECT_EQ(summary["pieces"], report["schedule"]["pieces"].size());
  EXPECT_EQ(summary["stitches"], report["stitch_mesh"]["faces"]["total"]);
  EXPECT_GT(summary["estimated_knit_time_s"].get<double>(), 0.0);
  EXPECT_GT(report["plan"]["total_s"].get<double>(), 0.0);
  // Not a terminal: no progress line, only the summary, naming the plan folder.
  EXPECT_EQ(result.out.find('\r'), std::string::npos);
  EXPECT_NE(result.out.find("  wearability "), std::string::npos) << result.out;
  EXPECT_NE(result.out.find("  total "), std::string::npos) << result.out;
  EXPECT_NE(result.out.find(plan.string()), std::string::npos) << result.out;
}

TEST_F(PlanTest, SendsEveryPieceToAFolder) {
  ASSERT_EQ(plan_a_->exit_code, 0) << plan_a_->err;
  const json report = read_json(*dir_ / "a/report.json");
  const json& pieces = report["schedule"]["pieces"];
  ASSERT_EQ(report["plan"]["sent"].size(), pieces.size());
  for (const json& piece : pieces) {
    const std::string dat = piece["dat"];
    const fs::path sent = *dir_ / "machine" / fs::path(dat).filename();
    ASSERT_TRUE(fs::is_regular_file(sent)) << sent;
    EXPECT_EQ(read_file(sent), read_file(*dir_ / "a" / dat));
  }
}

TEST_F(PlanTest, SendsToTheLoopbackMachine) {
  ASSERT_EQ(plan_b().exit_code, 0) << plan_b().err;
  EXPECT_EQ(plan_b().out, "");  // --quiet
  const json report = read_json(*dir_ / "b/report.json");
  ASSERT_GE(report["plan"]["sent"].size(), 1u);
  for (const json& sent : report["plan"]["sent"]) {
    EXPECT_EQ(sent["exit"], 0);
    EXPECT_NE(sent["message"].get<std::string>().find("rows knitted (device confirmed)"),
              std::string::npos)
        << sent.dump();
  }
}

// The two branches run concurrently; the merged result must not depend on
// which finishes first.
TEST_F(PlanTest, TwoRunsGiveTheSameFiles) {
  ASSERT_EQ(plan_a_->exit_code, 0);
  ASSERT_EQ(plan_b().exit_code, 0);
  const json a = read_json(*dir_ / "a/cuts.json"), b = read_json(*dir_ / "b/cuts.json");
  EXPECT_EQ(a, b);
  for (const char* name : {"cut-mesh.obj", "stitch-mesh.smobj"})
    EXPECT_EQ(read_file(*dir_ / "a" / name), read_file(*dir_ / "b" / name)) << name;
  const json pieces = read_json(*dir_ / "a/report.json")["schedule"]["pieces"];
  ASSERT_GE(pieces.size(), 1u);
  for (const json& piece : pieces) {
    for (const char* kind : {"knitout", "dat"}) {
      const std::string name = piece[kind];
      EXPECT_EQ(read_file(*dir_ / "a" / name), read_file(*dir_ / "b" / name)) << name;
    }
  }
}

// Garment and wearer in files at half size, brought to the fixture's size
// by --scale 2: `plan` reads both at that scale, and so does the
// wearability verb on a folder cut with --scale 2 (the wearer at the
// garment's recorded units and scale), giving the same labels. Read at its
// file's size instead (--wearer-scale 1), the wearer is half the garment's
// size and the verb says so (W005).
TEST_F(PlanTest, TheWearabilityVerbReadsTheWearerAtTheCutsScale) {
  write_file(*dir_ / "half-wearer.obj", ellipsoid_obj(6, 1.6, 6));
  write_file(*dir_ / "half-garment.obj", ellipsoid_obj(6.5, 1.55, 6));
  const std::string wearer = (*dir_ / "half-wearer.obj").string();
  const auto plan = run_wearknit("plan " + (*dir_ / "half-garment.obj").string() + " --wearer " +
                                 wearer + " --scale 2 -o " + (*dir_ / "half-plan").string() +
                                 " --wear-trials 2 --threads 2 --trials 5 --no-pictures -q");
  ASSERT_EQ(plan.exit_code, 0) << plan.err;
  const fs::path cut = *dir_ / "half-cut";
  const auto cutting = run_wearknit("cut " + (*dir_ / "half-garment.obj").string() +
                                    " --scale 2 --no-pictures -q -o " + cut.string());
  ASSERT_EQ(cutting.exit_code, 0) << cutting.err;
  const auto verb = run_wearknit("wearability " + cut.string() + " --wearer " + wearer +
                                 " --trials 2 --threads 2 -q");
  ASSERT_EQ(verb.exit_code, 0) << verb.err;
  EXPECT_EQ(verb.err.find("W005"), std::string::npos) << verb.err;
  const json planned = read_json(*dir_ / "half-plan/cuts.json");
  const json labelled = read_json(cut / "cuts.json");
  ASSERT_EQ(planned["arcs"].size(), labelled["arcs"].size());
  ASSERT_GE(planned["arcs"].size(), 1u);
  for (std::size_t i = 0; i < planned["arcs"].size(); ++i) {
    EXPECT_EQ(planned["arcs"][i]["label"], labelled["arcs"][i]["label"]) << "arc " << i;
  }
  const auto unscaled = run_wearknit("wearability " + cut.string() + " --wearer " + wearer +
                                     " --wearer-scale 1 --trials 1 --max-steps 50 -q");
  EXPECT_NE(unscaled.err.find(wearer + ": warning: [W005] the garment (bounding box diagonal "),
            std::string::npos)
      << unscaled.err;
  EXPECT_NE(unscaled.err.find("differ in size by a factor of 2."), std::string::npos)
      << unscaled.err;
  const auto bad =
      run_wearknit("wearability " + cut.string() + " --wearer " + wearer + " --wearer-units inch");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.err, "wearknit wearability: --wearer-units takes mm, cm or m, not 'inch'\n");
}

TEST_F(PlanTest, AnUnreadableWearerFailsAtTheCut) {
  const auto result =
      run_wearknit("plan " + (*dir_ / "garment.obj").string() + " --wearer " +
                   (*dir_ / "absent.obj").string() + " -o " + (*dir_ / "c").string());
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("wearknit plan: the cut stage failed (exit 2):\n  " +
                            (*dir_ / "absent.obj").string() + ": error: [P001]"),
            std::string::npos)
      << result.err;
  EXPECT_NE(result.err.find("wearknit plan: no stage finished"), std::string::npos);
  EXPECT_FALSE(fs::exists(*dir_ / "c/cuts.json"));
}

TEST_F(PlanTest, AFailedScheduleKeepsTheEarlierStages) {
  // A file where the schedule's pieces/ folder goes: the schedule stage
  // cannot write its pieces; the stages before it keep their files.
  const fs::path plan = *dir_ / "d";
  fs::create_directories(plan);
  write_file(plan / "pieces", "not a folder\n");
  const auto result = run_wearknit(plan_command("d", "--no-pictures"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("wearknit plan: the schedule stage failed (exit 2):\n"),
            std::string::npos)
      << result.err;
  EXPECT_NE(result.err.find((plan / "pieces").string()), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("the outputs of cut, wearability, stitch-mesh are in"),
            std::string::npos)
      << result.err;
  for (const char* name :
       {"cut-mesh.obj", "cut.json", "wearability.json", "stitch-mesh.smobj", "stitch-mesh.json"})
    EXPECT_TRUE(fs::is_regular_file(plan / name)) << name;
  EXPECT_EQ(read_file(plan / "pieces"), "not a folder\n");
  EXPECT_FALSE(fs::exists(plan / "schedule.json"));
  EXPECT_FALSE(fs::exists(plan / "assembly.svg"));
  const json cuts = read_json(plan / "cuts.json");
  for (const json& arc : cuts["arcs"]) EXPECT_TRUE(arc["label"].is_string()) << arc.dump();
  const json report = read_json(plan / "report.json");
  EXPECT_TRUE(report.contains("stitch_mesh"));
  EXPECT_FALSE(report.contains("schedule"));
  EXPECT_EQ(report["plan"]["stages"].back()["name"], "schedule");
  EXPECT_EQ(report["plan"]["stages"].back()["exit"], 2);
}

TEST_F(PlanTest, RejectsBadOptionsBeforeAnyStage) {
  auto result = run_wearknit(plan_command("e", "--pattern lace"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err, "wearknit plan: --pattern takes plain or seed, not 'lace'\n");
  result = run_wearknit(plan_command("e", "--size-mm 50 --scale 2"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err, "wearknit plan: give --scale or --size-mm, not both\n");
  EXPECT_FALSE(fs::exists(*dir_ / "e"));
}

TEST_F(PlanTest, APlanKilledInItsWearabilityStageResumesIt) {
  // Plan "c" is plan "a" without the machine, killed once its wearability
  // stage has put the initial test and one more into the plan folder's
  // journal; run again, it reads them back and ends with plan "a"'s labels.
  ASSERT_EQ(plan_a_->exit_code, 0) << plan_a_->err;
  const fs::path plan = *dir_ / "c";
  const fs::path journal = plan / "wearability.journal";
  ASSERT_TRUE(run_wearknit_and_kill(plan_command("c", "-q"), journal, 3))
      << "the plan ended before it could be killed";
  EXPECT_FALSE(fs::exists(plan / "wearability.json"))
      << "killed in its wearability stage: the stage has not written its file";
  EXPECT_TRUE(fs::is_regular_file(plan / "cut.json")) << "the cut stage had finished";
  const auto result = run_wearknit(plan_command("c", "-q"));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(read_file(plan / "plan.log").find("tests read from the journal"), std::string::npos)
      << read_file(plan / "plan.log");
  const json cuts = read_json(plan / "cuts.json");
  EXPECT_GE(cuts["wearability"]["tests_replayed"].get<int>(), 2);
  EXPECT_EQ(cuts["arcs"], read_json(*dir_ / "a" / "cuts.json")["arcs"]);
  EXPECT_FALSE(fs::exists(journal)) << "the finished stage deletes its journal";
}

TEST(DemoTest, RunsThePipelineOnItsOwnShape) {
  const fs::path dir = test::make_temp_dir("wearknit-demo");
  const auto result = run_wearknit("demo -q -o " + (dir / "demo").string());
  ASSERT_EQ(result.exit_code, 0) << result.err << result.out;
  EXPECT_NE(result.out.find("valid on the needle-bed VM"), std::string::npos) << result.out;
  EXPECT_NE(result.out.find((dir / "demo/report.json").string()), std::string::npos);
  EXPECT_TRUE(fs::is_regular_file(dir / "demo/input/garment.obj"));
  EXPECT_TRUE(fs::is_regular_file(dir / "demo/assembly.svg"));
  expect_valid_pieces(dir / "demo");
  const json cuts = read_json(dir / "demo/cuts.json");
  ASSERT_GE(cuts["arcs"].size(), 1u);
  for (const json& arc : cuts["arcs"])
    EXPECT_TRUE(arc["label"] == "sew" || arc["label"] == "lace") << arc.dump();
  // The guide's seams in report.json and the plan's summary; no more pages
  // than pieces to lay out (docs/assembly.md, "How the pieces are laid out").
  const json report = read_json(dir / "demo/report.json");
  const json& guide = report["assembly"];
  EXPECT_LE(guide["pdf_pages"].get<int>(), std::max(guide["pieces"].get<int>(), 1));
  EXPECT_EQ(guide["seams"].get<int>(), guide["sewn"].get<int>() + guide["laced"].get<int>());
  EXPECT_GT(guide["sewn_mm"].get<double>() + guide["laced_mm"].get<double>(), 0.0);
  const json& summary = report["plan"]["summary"];
  EXPECT_EQ(summary["seams_sewn"], guide["sewn"]);
  EXPECT_EQ(summary["seams_laced"], guide["laced"]);
  EXPECT_EQ(summary["seams_sewn_mm"], guide["sewn_mm"]);
  EXPECT_EQ(summary["seams_laced_mm"], guide["laced_mm"]);
  EXPECT_FALSE(cuts["seams"].empty());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wearknit::cli
