// End-to-end tests of `wearknit cut`.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "planner/mesh/mesh_io.hpp"
#include "tests/test_support.hpp"

namespace planner {
namespace {

using wearknit::test::make_temp_dir;
using wearknit::test::read_file;
using wearknit::test::run_wearknit;
using wearknit::test::write_file;

TEST(CutCliTest, WritesTheCutFolder) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const auto dir = make_temp_dir("cut_cli");
  const auto result =
      run_wearknit("cut " + (shared / "meshes" / "sphere-qd.obj").string() + " --units cm -o " +
                   (dir / "out").string() + " --seed 3 --picture-px 100 --proxy remesh");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  for (const char* name : {"proxy.obj", "cut-mesh.obj", "cuts.json", "labels.json", "report.json",
                           "cuts-3d.png", "layout-2d.png"}) {
    EXPECT_TRUE(std::filesystem::is_regular_file(dir / "out" / name)) << name;
  }
  const auto report = nlohmann::json::parse(read_file(dir / "out" / "report.json"));
  EXPECT_EQ(report["params"]["seed"], 3);
  EXPECT_EQ(report["disc"]["euler_characteristic"], 1);
  EXPECT_EQ(report["disc"]["boundary_loops"], 1);
  EXPECT_EQ(report["proxy"]["remeshed"], false);
  // sphere-qd spans 2 units; in cm that is 20 mm.
  EXPECT_NEAR(report["input"]["size_mm"][0].get<double>(), 20.0, 0.5);
  const auto cuts = nlohmann::json::parse(read_file(dir / "out" / "cuts.json"));
  EXPECT_EQ(cuts["arcs"].size(), report["arcs"].get<std::size_t>());
  double total = 0;
  for (const auto& arc : cuts["arcs"]) total += arc["length_mm"].get<double>();
  EXPECT_NEAR(total, cuts["cut_length_mm"].get<double>(), 1e-6);
  EXPECT_NE(result.out.find("mm; proxy 691 faces (input as is)"), std::string::npos) << result.out;
  std::filesystem::remove_all(dir);
}

TEST(CutCliTest, BadMeshExitsOneNamingTheElementAndWritesNothing) {
  const auto dir = make_temp_dir("cut_cli_bad");
  write_file(dir / "bowtie.obj",
             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n");
  const auto result =
      run_wearknit("cut " + (dir / "bowtie.obj").string() + " -o " + (dir / "out").string());
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err, (dir / "bowtie.obj").string() +
                            ": error: [P013] vertex 1 joins surface sheets that share no edge "
                            "there (a pinch point); split the vertex or connect the sheets\n");
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  std::filesystem::remove_all(dir);
}

TEST(CutCliTest, TriangleInputIsRemeshedAtTheTargetEdgeLength) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const auto dir = make_temp_dir("cut_cli_tri");
  const auto result =
      run_wearknit("cut " + (shared / "meshes" / "half-torus.obj").string() + " -o " +
                   (dir / "out").string() + " --proxy-edge-mm 0.2 --no-pictures -q --proxy remesh");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, "");
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "cuts-3d.png"));
  const auto report = nlohmann::json::parse(read_file(dir / "out" / "report.json"));
  EXPECT_EQ(report["proxy"]["remeshed"], true);
  EXPECT_EQ(report["proxy"]["method"], "instant-meshes");
  EXPECT_EQ(report["proxy"]["edge_mm"], 0.2);
  EXPECT_EQ(report["disc"]["euler_characteristic"], 1);
  EXPECT_EQ(report["disc"]["boundary_loops"], 1);
  // Mean edge of the proxy near the target: within 40 %.
  knitout::DiagnosticSink sink;
  const auto proxy = planner::read_polygon_soup((dir / "out" / "proxy.obj").string(), sink);
  ASSERT_TRUE(proxy.has_value());
  double total = 0;
  int count = 0;
  for (const auto& face : proxy->faces) {
    for (std::size_t i = 0; i < face.size(); ++i) {
      const auto& a = proxy->positions[static_cast<std::size_t>(face[i])];
      const auto& b = proxy->positions[static_cast<std::size_t>(face[(i + 1) % face.size()])];
      if (face.size() == 4) {
        total += (a - b).norm();
        ++count;
      }
    }
  }
  ASSERT_GT(count, 0);
  EXPECT_NEAR(total / count, 0.2, 0.2 * 0.4);
  std::filesystem::remove_all(dir);
}

TEST(CutCliTest, JsonDiagnosticsGoToStdout) {
  const auto result = run_wearknit("cut /nonexistent/x.obj -o out --json");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err, "");
  EXPECT_EQ(result.out,
            "[\n  {\"file\": \"/nonexistent/x.obj\", \"line\": 0, \"column\": 0, \"severity\": "
            "\"error\", \"code\": \"P001\", \"message\": \"cannot open file\"}\n]\n");
}

TEST(CutCliTest, UsageErrorsExitTwo) {
  EXPECT_EQ(run_wearknit("cut").exit_code, 2);
  const auto units = run_wearknit("cut x.obj -o out --units inch");
  EXPECT_EQ(units.exit_code, 2);
  EXPECT_EQ(units.err, "wearknit cut: --units takes mm, cm or m, not 'inch'\n");
  const auto missing = run_wearknit("cut /nonexistent/x.obj -o out");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(missing.err, "/nonexistent/x.obj: error: [P001] cannot open file\n");
}

TEST(CutCliTest, VanishingOptionIsCheckedAndRecorded) {
  const auto bad = run_wearknit("cut x.obj -o out --vanishing sharpest");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_EQ(bad.err, "wearknit cut: --vanishing takes optimal, acute or regular, not 'sharpest'\n");
  const auto slack = run_wearknit("cut x.obj -o out --vanishing regular --vanishing-slack -5");
  EXPECT_EQ(slack.exit_code, 2);
  EXPECT_EQ(slack.err, "wearknit cut: --vanishing-slack must be between 0 and 180 degrees\n");

  WEARKNIT_REQUIRE_SHARED(shared);
  const auto dir = make_temp_dir("cut_cli_vanishing");
  const std::string mesh = (shared / "meshes" / "torus-qd.obj").string();
  // The vanishing rule labels a quad-dominant proxy kept as it is (--proxy
  // remesh); the field proxy's corners come from its own flow.
  ASSERT_EQ(run_wearknit("cut " + mesh + " -o " + (dir / "optimal").string() +
                         " --no-pictures --proxy remesh --vanishing optimal")
                .exit_code,
            0);
  ASSERT_EQ(run_wearknit("cut " + mesh + " -o " + (dir / "acute").string() +
                         " --no-pictures --proxy remesh")
                .exit_code,
            0);
  const auto result = run_wearknit("cut " + mesh + " -o " + (dir / "regular").string() +
                                   " --no-pictures --proxy remesh --vanishing regular "
                                   "--vanishing-slack 20");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  const auto optimal = nlohmann::json::parse(read_file(dir / "optimal" / "report.json"));
  const auto acute = nlohmann::json::parse(read_file(dir / "acute" / "report.json"));
  const auto regular = nlohmann::json::parse(read_file(dir / "regular" / "report.json"));
  EXPECT_EQ(optimal["params"]["vanishing"], "optimal");
  EXPECT_EQ(acute["params"]["vanishing"], "acute");
  EXPECT_EQ(regular["params"]["vanishing"], "regular");
  EXPECT_NEAR(regular["params"]["vanishing_slack_deg"].get<double>(), 20.0, 1e-9);
  EXPECT_LT(regular["irregular_vertex_count"].get<int>(),
            acute["irregular_vertex_count"].get<int>());
  EXPECT_LT(regular["arcs"].get<int>(), acute["arcs"].get<int>());
  EXPECT_LT(optimal["irregular_vertex_count"].get<int>(),
            regular["irregular_vertex_count"].get<int>());
  EXPECT_LT(optimal["arcs"].get<int>(), regular["arcs"].get<int>());
  for (const auto* report : {&optimal, &acute, &regular}) {
    EXPECT_EQ((*report)["disc"]["boundary_loops"], 1);
  }
  std::filesystem::remove_all(dir);
}

TEST(CutCliTest, ProxyGrowthAndArcTurnOptionsAreCheckedAndRecorded) {
  const auto proxy = run_wearknit("cut x.obj -o out --proxy quads");
  EXPECT_EQ(proxy.exit_code, 2);
  EXPECT_EQ(proxy.err, "wearknit cut: --proxy takes field or remesh, not 'quads'\n");
  const auto growth = run_wearknit("cut x.obj -o out --growth round");
  EXPECT_EQ(growth.exit_code, 2);
  EXPECT_EQ(growth.err, "wearknit cut: --growth takes auto, random or square, not 'round'\n");
  const auto tighten = run_wearknit("cut x.obj -o out --tighten yes");
  EXPECT_EQ(tighten.exit_code, 2);
  EXPECT_EQ(tighten.err, "wearknit cut: --tighten takes auto, on or off, not 'yes'\n");
  const auto turn = run_wearknit("cut x.obj -o out --arc-turn 200");
  EXPECT_EQ(turn.exit_code, 2);
  EXPECT_EQ(turn.err, "wearknit cut: --arc-turn must be between 0 and 180 degrees\n");

  WEARKNIT_REQUIRE_SHARED(shared);
  const auto dir = make_temp_dir("cut_cli_proxy");
  // torus-qd carries 136 singular vertices where the field has 8: with
  // the field proxy (the default) it is not clean and is replaced; with
  // --proxy remesh it is kept.
  const std::string mesh = (shared / "meshes" / "torus-qd.obj").string();
  const auto field = run_wearknit("cut " + mesh + " -o " + (dir / "field").string() +
                                  " --no-pictures --arc-turn 90");
  ASSERT_EQ(field.exit_code, 0) << field.err;
  EXPECT_NE(field.out.find("proxy remeshed: the input has "), std::string::npos) << field.out;
  ASSERT_EQ(run_wearknit("cut " + mesh + " -o " + (dir / "kept").string() +
                         " --no-pictures --proxy remesh")
                .exit_code,
            0);
  const auto replaced = nlohmann::json::parse(read_file(dir / "field" / "report.json"));
  const auto kept = nlohmann::json::parse(read_file(dir / "kept" / "report.json"));
  EXPECT_EQ(replaced["proxy"]["method"], "field");
  EXPECT_EQ(replaced["proxy"]["input_verdict"].get<std::string>().rfind("remeshed: ", 0), 0U);
  EXPECT_EQ(replaced["params"]["growth"], "square");
  EXPECT_NEAR(replaced["params"]["arc_turn_deg"].get<double>(), 90.0, 1e-9);
  const int field_singularities = replaced["field"]["singularities"].get<int>();
  const int singular = replaced["proxy"]["singular_vertices"].get<int>();
  EXPECT_LE(singular, 1.2 * field_singularities + 4);
  EXPECT_LE(replaced["proxy"]["adjacent_pairs"].get<int>(), 0.1 * singular);
  EXPECT_LT(replaced["arcs"].get<int>(), kept["arcs"].get<int>());
  EXPECT_EQ(kept["proxy"]["method"], "input");
  EXPECT_EQ(kept["proxy"]["input_verdict"], "");
  EXPECT_EQ(kept["params"]["growth"], "random");
  // --growth and --tighten auto: square and on with the field proxy, random
  // and off with the remeshed one. On
  // torus-qd's field proxy (no singular vertex) the tightened cut is two
  // loops and what joins them, 3 arcs, and here a few more where it turns
  // by over 90° (--arc-turn 90); the grown cut of that proxy has 49 arcs.
  EXPECT_EQ(replaced["params"]["tighten"], true);
  EXPECT_EQ(kept["params"]["tighten"], false);
  EXPECT_EQ(singular, 0);
  EXPECT_LE(replaced["arcs"].get<int>(), 6);
  // The cut folder carries the garment's surface for the stitch mesh.
  EXPECT_TRUE(std::filesystem::is_regular_file(dir / "field" / "surface.obj"));
  EXPECT_GT(kept["proxy"]["adjacent_pairs"].get<int>(), 0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace planner
