// `wearknit wearability` end to end on cut folders written here.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "planner/cut/cut.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/pipeline.hpp"
#include "planner/wearability/wearability_io.hpp"
#include "tests/planner/cover_shapes.hpp"
#include "tests/test_support.hpp"

namespace wearknit::test {
namespace {

namespace fs = std::filesystem;

std::string obj_text(const std::vector<Vec3>& vertices,
                     const std::vector<std::vector<int>>& faces) {
  std::ostringstream out;
  planner::write_obj(out, planner::PolygonMesh{vertices, faces});
  return out.str();
}

// A garment made by hand, as the wearability stage takes it: the cut-mesh
// split along every cut, and its arcs (cut.json) in the split mesh's vertex
// indices.
fs::path write_cut_folder(const CoverMesh& cover, const std::string& name) {
  const fs::path dir = make_temp_dir(name);
  std::vector<int> source;
  const auto split = planner::open_cuts(cover, std::vector<bool>(cover.arcs.size(), true), &source);
  write_file(dir / "cut-mesh.obj", obj_text(split.positions, split.faces));
  std::vector<int> copy_of(cover.positions.size(), -1);
  for (std::size_t v = 0; v < source.size(); ++v) {
    if (copy_of[source[v]] < 0) copy_of[source[v]] = static_cast<int>(v);
  }
  nlohmann::json cuts = {{"arcs", nlohmann::json::array()}};
  for (std::size_t a = 0; a < cover.arcs.size(); ++a) {
    nlohmann::json edges = nlohmann::json::array();
    for (const auto& [u, v] : cover.arcs[a].edges) edges.push_back({copy_of[u], copy_of[v]});
    cuts["arcs"].push_back({{"id", a}, {"edges", edges}, {"kept", "as written"}});
  }
  write_file(dir / "cut.json", cuts.dump(1));
  return dir;
}

TEST(WearabilityVerbTest, LabelsTorusCoverArcsAndWritesPictureAndFrames) {
  const fs::path dir = write_cut_folder(torus_cover(1.0, 0.4, 24, 12, 1), "wearability-torus");
  const CoverMesh ring = torus_mesh(1.0, 0.4, 48, 24);
  write_file(dir / "torus.obj", obj_text(ring.positions, ring.faces));
  const auto result =
      run_wearknit("wearability " + dir.string() + " --wearer " + (dir / "torus.obj").string() +
                   " --trials 2 --max-steps 1500 --seed 3 --resolution 32 --frames " +
                   (dir / "frames").string() + " --frame-every 250 --cloth-max-vertices 0");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("wearability: 2 arcs, "), std::string::npos) << result.out;
  const auto cuts = nlohmann::json::parse(read_file(dir / "cuts.json"));
  ASSERT_EQ(cuts["arcs"].size(), 2u);
  // Sewing the outer equator closes a band around the tube: linked with
  // the torus, it fails without a trial.
  EXPECT_EQ(cuts["arcs"][1]["label"], "lace");
  EXPECT_EQ(cuts["arcs"][1]["wearability"]["linked_with_wearer"], true);
  EXPECT_EQ(cuts["arcs"][1]["wearability"]["trials"].size(), 0u);
  EXPECT_EQ(cuts["wearability"]["tests_linked"], 1);
  EXPECT_NE(result.out.find("; 1 of 3 tests failed unsimulated, a garment curve linked with the "
                            "wearer\n"),
            std::string::npos)
      << result.out;
  EXPECT_EQ(cuts["arcs"][0]["kept"], "as written");
  // The arcs were taken in the opening order: each has how far its sides
  // parted with every cut open.
  EXPECT_EQ(cuts["wearability"]["arc_order"], "opening");
  for (const auto& arc : cuts["arcs"]) {
    EXPECT_GT(arc["wearability"]["opening_mm"].get<double>(), 0.0);
  }
  EXPECT_EQ(cuts["wearability"]["wearable"], true);
  // The final check ran on the labels at a finer cloth, every trial off;
  // report.json records it.
  const auto& check = cuts["wearability"]["final_check"];
  EXPECT_EQ(check["ran"], true);
  EXPECT_EQ(check["passed"], true);
  EXPECT_EQ(check["trials"], 4);
  EXPECT_GT(check["cloth_vertices"].get<int>(), 4000);
  ASSERT_FALSE(check["rounds"].empty());
  EXPECT_EQ(check["rounds"].back()["trials"].size(), 4u);
  EXPECT_NE(result.out.find("final check: off in every one of 4 fresh trials"), std::string::npos)
      << result.out;
  const auto report = nlohmann::json::parse(read_file(dir / "report.json"));
  EXPECT_EQ(report["wearability"]["final_check"]["passed"], true);
  EXPECT_EQ(report["wearability"]["final_check"]["rounds"], check["rounds"].size());
  EXPECT_EQ(read_file(dir / "wearability.png").substr(1, 3), "PNG");
  EXPECT_TRUE(fs::exists(dir / "frames" / "frame-00000.obj"));
  EXPECT_TRUE(fs::exists(dir / "frames" / "frame-00250.obj"));
  // The 288-vertex cover was subdivided once for the cloth (--cloth-vertices
  // 500 by default): 288 + 576 edge midpoints + 288 face centres, and more
  // where the open arcs split it; --cloth-max-vertices 0 keeps it so
  // (coarse_cloth_test.cpp covers the coarse cloth).
  const std::string frame = read_file(dir / "frames" / "frame-00000.obj");
  std::size_t vertices = 0;
  for (std::size_t at = frame.find("v "); at != std::string::npos; at = frame.find("\nv ", at + 1))
    ++vertices;
  EXPECT_GT(vertices, 1152u);
  fs::remove_all(dir);
}

TEST(WearabilityVerbTest, ClosedShellIsRejectedAndEveryArcLaced) {
  // A sphere cover with one short slit (two edges by the pole): it cannot
  // come off the sphere, whatever is sewn.
  CoverMesh shell = sphere_mesh(1.0, 12, 6);
  shell.arcs.push_back(planner::arc_from_path({0, 1, 13}, "slit"));
  const fs::path dir = write_cut_folder(shell, "wearability-shell");
  const CoverMesh ball = sphere_mesh(1.0, 24, 12);
  write_file(dir / "ball.obj", obj_text(ball.positions, ball.faces));
  const auto result =
      run_wearknit("wearability " + dir.string() + " --wearer " + (dir / "ball.obj").string() +
                   " --trials 2 --max-steps 600 --resolution 24 --cloth-vertices 0");
  EXPECT_EQ(result.exit_code, 1);
  // The folder has no proxy.obj to cut again (§5's re-cut needs one).
  EXPECT_EQ(result.err, (dir / "wearability.json").string() +
                            ": error: [W020] the garment with every cut open did not come off the "
                            "wearer in 2 trials of 600 steps, with the cut of an unrecorded seed "
                            "(the folder's); cannot cut again: a garment made by hand (no "
                            "proxy.obj) cannot be cut again; every arc is labelled lace. In the "
                            "trial that got farthest, 63 of the 63 cloth vertices are still on the "
                            "wearer: the open garment does not move off it at all (it encloses the "
                            "wearer, or the trials are too short: --max-steps)\n");
  const auto cuts = nlohmann::json::parse(read_file(dir / "cuts.json"));
  EXPECT_EQ(cuts["arcs"][0]["label"], "lace");
  EXPECT_EQ(cuts["wearability"]["wearable"], false);
  fs::remove_all(dir);
}

// A torus cover cut by `wearknit cut`, then given a first cut that cannot
// work: its cut.json lists no arc, so the garment is a closed shell around
// the torus. Returns the cut folder; the wearer is DIR/../torus.obj.
fs::path write_closed_torus_cut(const std::string& name) {
  const fs::path dir = make_temp_dir(name);
  // Coarse (16 x 8 quads): the cutter splits a torus into many short arcs,
  // and the elimination of the new cut tests each of them.
  const CoverMesh garment = torus_mesh(1.0, 0.4, 16, 8);
  write_file(dir / "garment.obj", obj_text(garment.positions, garment.faces));
  const CoverMesh ring = torus_mesh(1.0, 0.4, 48, 24);
  write_file(dir / "torus.obj", obj_text(ring.positions, ring.faces));
  const auto cut =
      run_wearknit("cut " + (dir / "garment.obj").string() + " -o " + (dir / "cut").string() +
                   " --seed 1 --picture-px 60 --quiet --vanishing regular --vanishing-slack 25");
  EXPECT_EQ(cut.exit_code, 0) << cut.err;
  auto cuts = nlohmann::json::parse(read_file(dir / "cut" / "cut.json"));
  EXPECT_GE(cuts["arcs"].size(), 2u) << "a torus needs two loops cut";
  cuts["arcs"] = nlohmann::json::array();
  write_file(dir / "cut" / "cut.json", cuts.dump(1));
  return dir;
}

// The larger side of a PNG image.
int png_extent(const fs::path& path) {
  const std::string png = read_file(path);
  if (png.size() < 24 || png.substr(1, 3) != "PNG") return 0;
  int width = 0, height = 0;
  for (int i = 16; i < 20; ++i) width = width * 256 + static_cast<unsigned char>(png[i]);
  for (int i = 20; i < 24; ++i) height = height * 256 + static_cast<unsigned char>(png[i]);
  return std::max(width, height);
}

TEST(WearabilityVerbTest, UnwearableCutIsCutAgainWithAnotherSeed) {
  const fs::path dir = write_closed_torus_cut("wearability-recut");
  const fs::path cut = dir / "cut";
  const std::uint64_t recut_seed = planner::recut_seed(3, 1);
  // The folder's cut has no arcs: the garment is the closed torus, linked
  // with its wearer, so it fails without a trial. A short budget keeps the
  // elimination of the new cut's many arcs quick; the new cut, a disc,
  // comes off within it (seed 3: 230 steps).
  const auto result =
      run_wearknit("wearability " + cut.string() + " --wearer " + (dir / "torus.obj").string() +
                   " --trials 1 --max-steps 400 --seed 3 --resolution 32 --cloth-vertices 0");
  ASSERT_EQ(result.exit_code, 0) << result.err << result.out;
  EXPECT_NE(result.out.find("the cut with seed 1 does not come off the wearer with every cut open; "
                            "cutting again with seed " +
                            std::to_string(recut_seed) + "\n"),
            std::string::npos)
      << result.out;
  EXPECT_NE(
      result.out.find("; re-cut with seed " + std::to_string(recut_seed) + " (attempt 1 of 3)"),
      std::string::npos)
      << result.out;

  // cuts.json: the new cut's arcs, labelled, and both attempts.
  const auto cuts = nlohmann::json::parse(read_file(cut / "cuts.json"));
  ASSERT_GE(cuts["arcs"].size(), 2u);
  for (const auto& arc : cuts["arcs"]) EXPECT_TRUE(arc["label"] == "sew" || arc["label"] == "lace");
  const auto& summary = cuts["wearability"];
  EXPECT_EQ(summary["wearable"], true);
  EXPECT_EQ(summary["recut"], true);
  EXPECT_EQ(summary["cut_seed"], recut_seed);
  ASSERT_EQ(summary["cut_attempts"].size(), 2u);
  EXPECT_EQ(summary["cut_attempts"][0]["cut_seed"], 1);
  EXPECT_EQ(summary["cut_attempts"][0]["arcs"], 0);
  EXPECT_EQ(summary["cut_attempts"][0]["wearable"], false);
  EXPECT_EQ(summary["cut_attempts"][0]["linked_with_wearer"], true);
  EXPECT_EQ(summary["cut_attempts"][0]["initial_trials"].size(), 0u);
  EXPECT_EQ(summary["cut_attempts"][1]["cut_seed"], recut_seed);
  EXPECT_EQ(summary["cut_attempts"][1]["wearable"], true);
  EXPECT_FALSE(summary["cut_attempts"][1].contains("linked_with_wearer"));

  // report.json: the new seed, the input kept, every attempt.
  const auto report = nlohmann::json::parse(read_file(cut / "report.json"));
  EXPECT_EQ(report["params"]["seed"], recut_seed);
  // The re-cut keeps the cut's other parameters.
  EXPECT_EQ(report["params"]["vanishing"], "regular");
  EXPECT_NEAR(report["params"]["vanishing_slack_deg"].get<double>(), 25.0, 1e-9);
  EXPECT_EQ(report["input"]["file"], (dir / "garment.obj").string());
  EXPECT_EQ(report["wearability"]["recut"], true);
  EXPECT_EQ(report["wearability"]["cut_attempts"], summary["cut_attempts"]);

  // The rewritten folder is a consistent cut folder, pictures redrawn at their size.
  knitout::DiagnosticSink sink;
  const auto reread = planner::read_cut(cut.string(), sink);
  ASSERT_TRUE(reread.has_value()) << (sink.diagnostics().empty() ? ""
                                                                 : sink.diagnostics()[0].message);
  EXPECT_EQ(planner::verify_cut(reread->mesh), std::vector<std::string>{});
  EXPECT_EQ(reread->mesh.arcs.size(), cuts["arcs"].size());
  EXPECT_EQ(png_extent(cut / "cuts-3d.png"), 120);
  EXPECT_NEAR(png_extent(cut / "layout-2d.png"), 100, 1);
  fs::remove_all(dir);
}

TEST(WearabilityVerbTest, NoWearableCutWithinTheLimitIsW020NamingEveryAttempt) {
  // Ten steps cannot take any cover off (the garment moves at most half a
  // clearance per step), so every cut fails. The folder's cut, the closed
  // torus, is simulated too (--simulate-linked).
  const fs::path dir = write_closed_torus_cut("wearability-recut-fails");
  const fs::path cut = dir / "cut";
  const std::string base = "wearability " + cut.string() + " --wearer " +
                           (dir / "torus.obj").string() +
                           " --trials 1 --max-steps 10 --seed 3 --resolution 24 --cloth-vertices 0"
                           " --simulate-linked";
  auto result = run_wearknit(base + " --recut-limit 0");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err,
            (cut / "wearability.json").string() +
                ": error: [W020] the garment with every cut open did not come off the "
                "wearer in 1 trials of 10 steps, with the cut of seed 1 (the folder's) "
                "(--recut-limit 0); every arc is labelled lace"
                ". In the trial that got farthest, 128 of the 128 cloth vertices are still "
                "on the wearer: the open garment does not move off it at all (it "
                "encloses the wearer, or the trials are too short: --max-steps)\n");
  auto report = nlohmann::json::parse(read_file(cut / "report.json"));
  EXPECT_EQ(report["params"]["seed"], 1) << "not cut again";
  EXPECT_EQ(report["wearability"]["cut_attempts"].size(), 1u);

  result = run_wearknit(base + " --recut-limit 2");
  EXPECT_EQ(result.exit_code, 1);
  const std::uint64_t first = planner::recut_seed(3, 1), second = planner::recut_seed(3, 2);
  EXPECT_EQ(result.err,
            (cut / "wearability.json").string() +
                ": error: [W020] the garment with every cut open did not come off the "
                "wearer in 1 trials of 10 steps, with each of the cuts of seed 1 (the "
                "folder's), seed " +
                std::to_string(first) + " (re-cut 1), seed " + std::to_string(second) +
                " (re-cut 2); every arc is labelled lace"
                ". In the trial that got farthest, 128 of the 128 cloth vertices are still "
                "on the wearer: the open garment does not move off it at all (it "
                "encloses the wearer, or the trials are too short: --max-steps)\n");
  EXPECT_NE(first, second);
  report = nlohmann::json::parse(read_file(cut / "report.json"));
  EXPECT_EQ(report["params"]["seed"], second) << "the folder holds the last cut tried";
  ASSERT_EQ(report["wearability"]["cut_attempts"].size(), 3u);
  for (const auto& attempt : report["wearability"]["cut_attempts"]) {
    EXPECT_EQ(attempt["wearable"], false);
  }
  const auto cuts = nlohmann::json::parse(read_file(cut / "cuts.json"));
  EXPECT_EQ(cuts["wearability"]["wearable"], false);
  EXPECT_EQ(cuts["wearability"]["recut"], true);
  for (const auto& arc : cuts["arcs"]) EXPECT_EQ(arc["label"], "lace");
  fs::remove_all(dir);
}

TEST(WearabilityVerbTest, AGarmentLinkedWithItsWearerIsW020WithoutATrial) {
  const fs::path dir = write_closed_torus_cut("wearability-linked");
  const fs::path cut = dir / "cut";
  const auto result =
      run_wearknit("wearability " + cut.string() + " --wearer " + (dir / "torus.obj").string() +
                   " --trials 1 --max-steps 10 --seed 3 --resolution 24 --cloth-vertices 0"
                   " --recut-limit 0");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err, (cut / "wearability.json").string() +
                            ": error: [W020] the garment with every cut open cannot come off the "
                            "wearer: a closed curve of it winds around a handle of the wearer, "
                            "with the cut of seed 1 (the folder's) (--recut-limit 0); every arc "
                            "is labelled lace\n");
  const auto report = nlohmann::json::parse(read_file(cut / "report.json"));
  ASSERT_EQ(report["wearability"]["cut_attempts"].size(), 1u);
  EXPECT_EQ(report["wearability"]["cut_attempts"][0]["linked_with_wearer"], true);
  EXPECT_EQ(report["wearability"]["cut_attempts"][0]["initial_trials"].size(), 0u);
  fs::remove_all(dir);
}

std::vector<std::string> labels_of(const fs::path& dir) {
  std::vector<std::string> labels;
  const auto cuts = nlohmann::json::parse(read_file(dir / "cuts.json"));
  for (const auto& arc : cuts["arcs"]) labels.push_back(arc.value("label", ""));
  return labels;
}

TEST(WearabilityVerbTest, ARunKilledMidwayResumesFromItsJournal) {
  const CoverMesh cover = torus_cover(1.0, 0.4, 24, 12, 2);
  const fs::path dir = write_cut_folder(cover, "wearability-killed");
  const fs::path whole = write_cut_folder(cover, "wearability-whole");
  const CoverMesh ring = torus_mesh(1.0, 0.4, 48, 24);
  write_file(dir / "torus.obj", obj_text(ring.positions, ring.faces));
  const std::string options = " --wearer " + (dir / "torus.obj").string() +
                              " --trials 2 --max-steps 1500 --seed 5 --resolution 32";
  const fs::path journal = dir / "wearability.journal";

  // The run as it goes when nothing stops it: no journal is left behind.
  const auto reference = run_wearknit("wearability " + whole.string() + options);
  ASSERT_EQ(reference.exit_code, 0) << reference.err;
  EXPECT_EQ(reference.out.find("journal"), std::string::npos) << reference.out;
  EXPECT_FALSE(fs::exists(whole / "wearability.journal"));
  const auto expected = labels_of(whole);

  // The same run killed (SIGKILL) once the initial test and one more are in
  // its journal.
  const std::string before = read_file(dir / "cut.json");
  const bool killed =
      run_wearknit_and_kill("wearability " + dir.string() + options + " -q", journal, 3);
  ASSERT_TRUE(killed) << "the run ended before it could be killed";
  ASSERT_TRUE(fs::exists(journal));
  EXPECT_EQ(read_file(dir / "cut.json"), before) << "the stage's input is left as it was";
  EXPECT_FALSE(fs::exists(dir / "wearability.json")) << "a killed run writes no labels";

  const auto resumed = run_wearknit("wearability " + dir.string() + options);
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("tests read from the journal"), std::string::npos) << resumed.out;
  EXPECT_EQ(labels_of(dir), expected);
  const auto cuts = nlohmann::json::parse(read_file(dir / "cuts.json"));
  EXPECT_GE(cuts["wearability"]["tests_replayed"].get<int>(), 2);
  EXPECT_EQ(cuts["arcs"], nlohmann::json::parse(read_file(whole / "cuts.json"))["arcs"])
      << "the same tests, trial by trial";
  EXPECT_FALSE(fs::exists(journal)) << "the finished stage deletes its journal";
  fs::remove_all(dir);
  fs::remove_all(whole);
}

TEST(WearabilityVerbTest, BadFolderGivesDiagnostics) {
  const fs::path dir = make_temp_dir("wearability-bad");
  write_file(dir / "cut-mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  write_file(dir / "w.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  auto result =
      run_wearknit("wearability " + dir.string() + " --wearer " + (dir / "w.obj").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err, (dir / "cut.json").string() + ": error: [W004] cannot open file\n");

  write_file(dir / "cut.json", R"({"arcs": [{"edges": [[0, 1], [1, 0]]}]})");
  result = run_wearknit("wearability " + dir.string() + " --wearer " + (dir / "w.obj").string());
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err,
            (dir / "cut.json").string() + ": error: [W011] arc 0 edge 1 (1-0) is also in arc 0\n");
  const std::string before = read_file(dir / "cut.json");
  EXPECT_EQ(before, R"({"arcs": [{"edges": [[0, 1], [1, 0]]}]})") << "nothing written on error";

  result = run_wearknit("wearability " + dir.string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--wearer"), std::string::npos) << result.err;

  result = run_wearknit("wearability " + dir.string() + " --wearer " + (dir / "w.obj").string() +
                        " --arc-order sideways");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--arc-order takes opening or random, not 'sideways'"),
            std::string::npos)
      << result.err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wearknit::test

namespace wearknit::test {
namespace {

// The garment of a cut is the proxy's vertices with the disc's faces, joined
// by which proxy vertex each disc vertex copies, not by position: the
// field-guided proxy of sphere-qd at 100 mm has two vertices 1.8 µm apart,
// which cut-mesh.obj's precision writes at one point, and welding them made
// an edge of three faces (an internal error of the wearability stage).
TEST(WearabilityVerbTest, TheGarmentOfACutKeepsProxyVerticesCloserThanTheFilesPrecision) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const fs::path mesh = shared / "meshes" / "sphere-qd.obj";
  knitout::DiagnosticSink sink;
  const auto sphere = planner::read_stage_mesh(mesh.string(), sink);
  ASSERT_TRUE(sphere);
  Eigen::AlignedBox3d box;
  for (const auto& p : sphere->positions) box.extend(p);
  const double scale = 100.0 / box.sizes().maxCoeff();
  const TempDir folder("cover-of-field");
  const auto cut = run_wearknit("cut '" + mesh.string() + "' --scale " + std::to_string(scale) +
                                " --proxy field --growth square --no-pictures -q -o '" +
                                folder.path().string() + "'");
  ASSERT_EQ(cut.exit_code, 0) << cut.err;
  const auto read = planner::read_cut(folder.path().string(), sink);
  ASSERT_TRUE(read);
  const planner::CoverMesh cover = planner::cover_of(*read, 0);
  EXPECT_EQ(cover.positions.size(), read->mesh.proxy.polygons().positions.size());
  EXPECT_TRUE(planner::validate(cover).empty());
  EXPECT_EQ(cover.arcs.size(), read->mesh.arcs.size());
}

}  // namespace
}  // namespace wearknit::test
