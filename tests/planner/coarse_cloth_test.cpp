#include "planner/wearability/coarse_cloth.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numbers>
#include <set>

#include "planner/wearability/wearability_stage.hpp"
#include "tests/planner/cover_shapes.hpp"

namespace wearknit::test {
namespace {

// V - E + F of a polygon mesh.
int euler_characteristic(const cloth::PolygonMesh& mesh) {
  std::set<std::pair<int, int>> edges;
  for (const auto& face : mesh.faces)
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  return static_cast<int>(mesh.positions.size()) - static_cast<int>(edges.size()) +
         static_cast<int>(mesh.faces.size());
}

// Connected runs of boundary edges (edges with one face).
int boundary_loops(const cloth::PolygonMesh& mesh) {
  std::map<std::pair<int, int>, int> count;
  for (const auto& face : mesh.faces)
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  std::map<int, int> parent;
  auto find = [&](int v) {
    while (parent.at(v) != v) v = parent.at(v) = parent.at(parent.at(v));
    return v;
  };
  for (const auto& [edge, n] : count)
    if (n == 1) parent.emplace(edge.first, edge.first), parent.emplace(edge.second, edge.second);
  for (const auto& [edge, n] : count)
    if (n == 1) parent[find(edge.first)] = find(edge.second);
  int loops = 0;
  for (const auto& [v, p] : parent) loops += find(v) == v;
  return loops;
}

// Vertex → how many of the arc's edges meet there.
std::map<int, int> arc_degrees(const planner::CoverArc& arc) {
  std::map<int, int> degree;
  for (const auto& [a, b] : arc.edges) {
    ++degree[a];
    ++degree[b];
  }
  return degree;
}

// Vertices of degree one: an open arc's two ends, none for a loop.
std::vector<Vec3> arc_ends(const CoverMesh& mesh, const planner::CoverArc& arc) {
  std::vector<Vec3> ends;
  for (const auto& [v, d] : arc_degrees(arc))
    if (d == 1) ends.push_back(mesh.positions[static_cast<std::size_t>(v)]);
  std::sort(ends.begin(), ends.end(), [](const Vec3& a, const Vec3& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  return ends;
}

TEST(CoarseClothTest, CoarseningKeepsEveryArcItsEndsAndTheTopology) {
  // 96 x 24 torus, 2,304 vertices: a meridian loop and three equator arcs.
  const CoverMesh cover = torus_cover(1.0, 0.4, 96, 24, 3);
  const CoverMesh coarse = planner::coarsened(cover, 400);
  ASSERT_TRUE(planner::validate(coarse).empty()) << planner::validate(coarse).front();
  EXPECT_LE(coarse.positions.size(), 400u);
  EXPECT_GE(coarse.positions.size(), 350u);
  ASSERT_EQ(coarse.arcs.size(), cover.arcs.size());
  for (std::size_t a = 0; a < cover.arcs.size(); ++a) {
    const auto& arc = coarse.arcs[a];
    EXPECT_EQ(arc.name, cover.arcs[a].name);
    // Simplified along itself: fewer edges, still one chain with the same
    // ends (the meridian a loop of at least three edges).
    EXPECT_LT(arc.edges.size(), cover.arcs[a].edges.size()) << arc.name;
    EXPECT_GE(arc.edges.size(), 3u) << arc.name;
    for (const auto& [v, d] : arc_degrees(arc)) EXPECT_LE(d, 2) << arc.name;
    EXPECT_EQ(arc_ends(coarse, arc), arc_ends(cover, cover.arcs[a])) << arc.name;
  }
  // Every vertex is one of the garment's own: the shape is sampled, not
  // moved.
  std::set<std::array<double, 3>> original;
  for (const Vec3& p : cover.positions) original.insert({p.x(), p.y(), p.z()});
  for (const Vec3& p : coarse.positions) EXPECT_EQ(original.count({p.x(), p.y(), p.z()}), 1u);
  // The topology of every configuration is the garment's: closed, a torus;
  // the meridian open, a tube; every arc open, a disc.
  for (const auto& [open, chi] :
       std::vector<std::pair<std::vector<bool>, int>>{{{false, false, false, false}, 0},
                                                      {{true, false, false, false}, 0},
                                                      {{true, true, true, true}, 1}}) {
    EXPECT_EQ(euler_characteristic(planner::open_cuts(coarse, open)), chi);
  }
  // Most of the cloth is quads, for §8.2's shear and bend springs.
  std::size_t quads = 0;
  for (const auto& face : coarse.faces) quads += face.size() == 4;
  EXPECT_GT(quads * 10, coarse.faces.size() * 6);
}

TEST(CoarseClothTest, AGarmentAsSmallAsTheTargetIsKept) {
  const CoverMesh cover = torus_cover(1.0, 0.4, 24, 12, 4);  // 288 vertices
  for (const int target : {0, 288, 1000}) {
    const CoverMesh same = planner::coarsened(cover, target);
    EXPECT_EQ(same.positions, cover.positions);
    EXPECT_EQ(same.faces, cover.faces);
  }
}

TEST(CoarseClothTest, AnOpenCapKeepsOneBoundaryLoop) {
  // A hemispherical cap (boundary: the equator) and a slit from its pole.
  CoverMesh cap = sphere_mesh(1.0, 64, 32, std::numbers::pi / 2);
  const int pole = 0;
  int nearest = -1;
  for (std::size_t v = 0; v < cap.positions.size(); ++v)
    if (std::abs(cap.positions[v].z() - std::cos(std::numbers::pi / 4)) < 0.05 &&
        std::abs(cap.positions[v].y()) < 1e-9 && cap.positions[v].x() > 0)
      nearest = static_cast<int>(v);
  ASSERT_GE(nearest, 0);
  cap.arcs.push_back(
      planner::arc_from_path(planner::shortest_edge_path(cap, pole, nearest), "slit"));
  ASSERT_TRUE(planner::validate(cap).empty());
  const CoverMesh coarse = planner::coarsened(cap, cap.positions.size() / 4);
  ASSERT_TRUE(planner::validate(coarse).empty()) << planner::validate(coarse).front();
  EXPECT_LT(coarse.positions.size(), cap.positions.size() / 3);
  // Still a disc with the slit inside it; opened, the slit is a second
  // boundary loop (an annulus, χ = 0), as it is on the cap.
  EXPECT_EQ(euler_characteristic(coarse), 1);
  EXPECT_EQ(boundary_loops(coarse), 1);
  EXPECT_EQ(euler_characteristic(planner::open_cuts(cap, {true})), 0);
  EXPECT_EQ(euler_characteristic(planner::open_cuts(coarse, {true})), 0);
  EXPECT_EQ(boundary_loops(planner::open_cuts(coarse, {true})), 2);
  EXPECT_EQ(arc_ends(coarse, coarse.arcs[0]), arc_ends(cap, cap.arcs[0]));
}

// The wearer of the stage runs below: the 96 x 24 torus.
const cloth::SignedDistanceField& fine_torus_field() {
  static const auto field = [] {
    cloth::SdfParams sdf;
    sdf.resolution = 48;
    const CoverMesh torus = torus_mesh(1.0, 0.4, 96, 24);
    return cloth::SignedDistanceField(torus.positions, torus.faces, sdf);
  }();
  return field;
}

// A test budget (1500 steps, 2 trials on two threads) and no re-cut: a
// garment made in code has no proxy to cut again.
planner::WearabilityStageParams stage_params() {
  planner::WearabilityStageParams params;
  params.test.cloth.max_steps = 1500;
  params.test.trials = 2;
  params.test.threads = 2;
  params.test.seed = 5;
  params.recut_limit = 0;
  return params;
}

TEST(CoarseClothTest, TheStageEliminatesOnTheCoarseClothAndChecksOnTheGarment) {
  // A 96 x 24 torus cover (2,304 vertices) over its torus: cut into a disc
  // it comes off; sewing an equator arc closes a band around the tube, which
  // never does. The coarse cloth gives the same answer.
  const CoverMesh cover = torus_cover(1.0, 0.4, 96, 24, 3);
  const cloth::SignedDistanceField& wearer = fine_torus_field();
  planner::WearabilityStageParams params = stage_params();
  params.cloth_max_vertices = 600;
  const auto result = planner::label_garment(cover, wearer, params);
  ASSERT_TRUE(result.wearable());
  EXPECT_EQ(result.cover.positions.size(), cover.positions.size());
  EXPECT_LE(result.cloth.positions.size(), 600u);
  const auto& run = result.study.runs[0];
  for (std::size_t a = 1; a < cover.arcs.size(); ++a)
    EXPECT_EQ(run.arcs[a].label, planner::Label::Lace) << cover.arcs[a].name;
  // Every trial of the elimination ran on the coarse cloth (and the opened
  // copies along its cuts); the check on the garment as it is.
  for (const auto& arc : run.arcs)
    for (const auto& trial : arc.test.trials) EXPECT_LT(trial.cloth_vertices, 700);
  ASSERT_TRUE(result.check.ran);
  EXPECT_TRUE(result.check.passed);
  EXPECT_EQ(result.check.cloth_vertices, static_cast<int>(cover.positions.size()));
  EXPECT_NE(planner::describe(result).find("of a cloth of " +
                                           std::to_string(result.cloth.positions.size()) +
                                           " vertices (the garment's 2304, coarsened)"),
            std::string::npos)
      << planner::describe(result);
}

TEST(CoarseClothTest, AClothTooCoarseToComeOffGivesWayToAFinerOne) {
  // The same torus cover coarsened to about 40 vertices: a cloth that stiff
  // does not bend off the tube even cut into a disc (as the 6 x 5 cover of
  // ACoarseTorusCoverComesOffOnceSubdivided). Before the cut is called
  // unwearable, cloths of twice the vertices are tried in turn.
  const CoverMesh cover = torus_cover(1.0, 0.4, 96, 24, 3);
  const cloth::SignedDistanceField& wearer = fine_torus_field();
  planner::WearabilityStageParams params = stage_params();
  params.check_trials = 0;
  params.cloth_max_vertices = 40;
  const auto result = planner::label_garment(cover, wearer, params);
  ASSERT_TRUE(result.wearable());
  ASSERT_EQ(result.attempts.size(), 1u);
  const auto& attempt = result.attempts.front();
  EXPECT_TRUE(attempt.wearable);
  EXPECT_GT(attempt.coarse_cloth_vertices, 0);
  EXPECT_LE(attempt.coarse_cloth_vertices, static_cast<int>(cover.positions.size()) / 2);
  EXPECT_EQ(attempt.cloth_vertices, static_cast<int>(result.cloth.positions.size()));
  EXPECT_GT(result.cloth.positions.size(), 40u);
  // The coarse cloth that failed was coarser than the one that answered.
  EXPECT_LT(attempt.coarse_cloth_vertices, attempt.cloth_vertices);
}

}  // namespace
}  // namespace wearknit::test
