// `wearknit wearability` end to end on cut folders written here.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "planner/wearability_io.hpp"
#include "tests/planner/cover_shapes.hpp"
#include "tests/test_support.hpp"

namespace wearknit::test {
namespace {

namespace fs = std::filesystem;

std::string obj_text(const std::vector<Vec3>& vertices,
                     const std::vector<std::vector<int>>& faces) {
  std::ostringstream out;
  planner::write_obj(out, vertices, faces);
  return out.str();
}

// A cut folder as `wearknit cut` writes it: the cut-mesh split along every
// cut, and its arcs in the split mesh's vertex indices.
fs::path write_cut_folder(const CoverMesh& cover, const std::string& name) {
  const fs::path dir = make_temp_dir(name);
  std::vector<int> source;
  const auto split = planner::open_cuts(cover, std::vector<bool>(cover.arcs.size(), true), &source);
  write_file(dir / "cut-mesh.obj", obj_text(split.positions, split.faces));
  std::vector<int> copy_of(cover.vertices.size(), -1);
  for (std::size_t v = 0; v < source.size(); ++v) {
    if (copy_of[source[v]] < 0) copy_of[source[v]] = static_cast<int>(v);
  }
  nlohmann::json cuts = {{"arcs", nlohmann::json::array()}};
  for (std::size_t a = 0; a < cover.arcs.size(); ++a) {
    nlohmann::json edges = nlohmann::json::array();
    for (const auto& [u, v] : cover.arcs[a].edges) edges.push_back({copy_of[u], copy_of[v]});
    cuts["arcs"].push_back({{"id", a}, {"edges", edges}, {"kept", "as written"}});
  }
  write_file(dir / "cuts.json", cuts.dump(1));
  return dir;
}

TEST(WearabilityVerbTest, LabelsTorusCoverArcsAndWritesPictureAndFrames) {
  const fs::path dir = write_cut_folder(torus_cover(1.0, 0.4, 24, 12, 1), "wearability-torus");
  const CoverMesh ring = torus_mesh(1.0, 0.4, 48, 24);
  write_file(dir / "torus.obj", obj_text(ring.vertices, ring.faces));
  const auto result =
      run_wearknit("wearability " + dir.string() + " --wearer " + (dir / "torus.obj").string() +
                   " --trials 2 --max-steps 1500 --seed 3 --resolution 32 --frames " +
                   (dir / "frames").string() + " --frame-every 250");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("wearability: 2 arcs, "), std::string::npos) << result.out;
  const auto cuts = nlohmann::json::parse(read_file(dir / "cuts.json"));
  ASSERT_EQ(cuts["arcs"].size(), 2u);
  // Sewing the outer equator closes a band around the tube.
  EXPECT_EQ(cuts["arcs"][1]["label"], "lace");
  EXPECT_EQ(cuts["arcs"][1]["wearability"]["trials"].size(), 2u);
  EXPECT_EQ(cuts["arcs"][1]["wearability"]["trials"][0]["success"], false);
  EXPECT_EQ(cuts["arcs"][0]["kept"], "as written");
  EXPECT_EQ(cuts["wearability"]["wearable"], true);
  EXPECT_EQ(read_file(dir / "wearability.png").substr(1, 3), "PNG");
  EXPECT_TRUE(fs::exists(dir / "frames" / "frame-00000.obj"));
  EXPECT_TRUE(fs::exists(dir / "frames" / "frame-00250.obj"));
  fs::remove_all(dir);
}

TEST(WearabilityVerbTest, ClosedShellIsRejectedAndEveryArcLaced) {
  // A sphere cover with one short slit (two edges by the pole): it cannot
  // come off the sphere, whatever is sewn.
  CoverMesh shell = sphere_mesh(1.0, 12, 6);
  shell.arcs.push_back(planner::arc_from_path({0, 1, 13}, "slit"));
  const fs::path dir = write_cut_folder(shell, "wearability-shell");
  const CoverMesh ball = sphere_mesh(1.0, 24, 12);
  write_file(dir / "ball.obj", obj_text(ball.vertices, ball.faces));
  const auto result =
      run_wearknit("wearability " + dir.string() + " --wearer " + (dir / "ball.obj").string() +
                   " --trials 2 --max-steps 600 --resolution 24");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.err.find("error: [W020] the garment with every cut open did not come off the "
                            "wearer in 2 trials of 600 steps"),
            std::string::npos)
      << result.err;
  const auto cuts = nlohmann::json::parse(read_file(dir / "cuts.json"));
  EXPECT_EQ(cuts["arcs"][0]["label"], "lace");
  EXPECT_EQ(cuts["wearability"]["wearable"], false);
  fs::remove_all(dir);
}

TEST(WearabilityVerbTest, BadFolderGivesDiagnostics) {
  const fs::path dir = make_temp_dir("wearability-bad");
  write_file(dir / "cut-mesh.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  write_file(dir / "w.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  auto result =
      run_wearknit("wearability " + dir.string() + " --wearer " + (dir / "w.obj").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err, (dir / "cuts.json").string() + ": error: [W004] cannot open file\n");

  write_file(dir / "cuts.json", R"({"arcs": [{"edges": [[0, 1], [1, 0]]}]})");
  result = run_wearknit("wearability " + dir.string() + " --wearer " + (dir / "w.obj").string());
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err,
            (dir / "cuts.json").string() + ": error: [W011] arc 0 edge 1 (1-0) is also in arc 0\n");
  const std::string before = read_file(dir / "cuts.json");
  EXPECT_EQ(before, R"({"arcs": [{"edges": [[0, 1], [1, 0]]}]})") << "nothing written on error";

  result = run_wearknit("wearability " + dir.string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("--wearer"), std::string::npos) << result.err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wearknit::test
