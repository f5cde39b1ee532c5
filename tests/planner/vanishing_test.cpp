#include "planner/cut/vanishing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "planner/cut/cut.hpp"
#include "tests/planner/test_meshes.hpp"

namespace planner {
namespace {

int singular_count(const HalfedgeMesh& q, const std::vector<int>& vanishing) {
  return static_cast<int>(labels_with_vanishing(q, vanishing).singular_vertices.size());
}

// The vertex where face f's vanishing corner is.
int vanishing_vertex(const HalfedgeMesh& q, const std::vector<int>& vanishing, int f) {
  return q.from(q.face_start(f) + vanishing[static_cast<std::size_t>(f)]);
}

// The quads of `mesh` at the given face indices split into two triangles
// each, along the diagonal from their corner 0 (diagonal 0) or corner 1
// (diagonal 1); the triangles replace the quads at the end of the list.
PolygonMesh split_quads(PolygonMesh mesh, const std::vector<std::pair<int, int>>& splits) {
  std::vector<std::vector<int>> kept, triangles;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto split =
        std::find_if(splits.begin(), splits.end(), [&](const auto& s) { return at(s.first) == f; });
    const std::vector<int>& c = mesh.faces[f];
    if (split == splits.end()) {
      kept.push_back(c);
    } else if (split->second == 0) {
      triangles.push_back({c[0], c[1], c[2]});
      triangles.push_back({c[0], c[2], c[3]});
    } else {
      triangles.push_back({c[1], c[2], c[3]});
      triangles.push_back({c[1], c[3], c[0]});
    }
  }
  kept.insert(kept.end(), triangles.begin(), triangles.end());
  mesh.faces = kept;
  return mesh;
}

// A 3 x 3 grid whose middle cell is split along its diagonal from a =
// vertex 5 to c = vertex 10, c pulled outwards: both triangles are
// sharpest at c, which then keeps 3 corners and leaves a with 5. Vertex 9
// is moved a little so that the two triangles' angles differ: face 8 (a, 6,
// c) is 45 degrees at a and 39.8 at c, face 9 (a, c, 9) 50.7 at a and 40.2
// at c.
PolygonMesh grid_with_split_cell() {
  PolygonMesh mesh = test_meshes::grid(3, 3);
  mesh.positions[10] = {2.1, 2.1, 0.0};
  mesh.positions[9] = {0.9, 2.0, 0.0};
  return split_quads(mesh, {{4, 0}});
}

// Calls visit(vanishing) with every choice of vanishing corners of q's triangles.
template <typename Visit>
void for_every_choice(const HalfedgeMesh& q, Visit visit) {
  std::vector<int> triangles;
  for (int f = 0; f < q.num_faces(); ++f) {
    if (q.degree(f) == 3) triangles.push_back(f);
  }
  std::vector<int> vanishing(at(q.num_faces()), -1);
  for (int f : triangles) vanishing[at(f)] = 0;
  while (true) {
    visit(vanishing);
    std::size_t k = 0;
    while (k < triangles.size() && vanishing[at(triangles[k])] == 2) {
      vanishing[at(triangles[k])] = 0;
      ++k;
    }
    if (k == triangles.size()) return;
    ++vanishing[at(triangles[k])];
  }
}

TEST(VanishingTest, ATriangleOnTheBoundaryVanishesAtItsMostAcuteCorner) {
  PolygonMesh mesh;
  mesh.positions = {{0, 0, 0}, {4, 0, 0}, {4, 1, 0}};  // sharpest at vertex 0
  mesh.faces = {{1, 2, 0}};
  EXPECT_EQ(optimal_vanishing_corners(HalfedgeMesh(mesh)), std::vector<int>{2});
}

TEST(VanishingTest, QuadsHaveNoVanishingCornerAndEveryTriangleOne) {
  const HalfedgeMesh q(split_quads(test_meshes::torus(6, 4), {{0, 0}, {7, 1}, {15, 0}}));
  const std::vector<int> vanishing = optimal_vanishing_corners(q);
  ASSERT_EQ(vanishing.size(), static_cast<std::size_t>(q.num_faces()));
  for (int f = 0; f < q.num_faces(); ++f) {
    if (q.degree(f) == 4) {
      EXPECT_EQ(vanishing[at(f)], -1) << f;
    } else {
      EXPECT_GE(vanishing[at(f)], 0) << f;
      EXPECT_LE(vanishing[at(f)], 2) << f;
    }
  }
}

TEST(VanishingTest, TheSplitCellComesOutRegularWhereTheAcuteRuleLeavesTwoIrregularVertices) {
  const HalfedgeMesh q(grid_with_split_cell());
  VanishingRule acute;
  acute.method = VanishingRule::Method::Acute;
  const FieldLabels by_angle = label_field(q, acute);
  EXPECT_EQ(corner_misfit(q, by_angle.vanishing_corner), 2);
  EXPECT_EQ(by_angle.irregular_vertices, (std::vector<int>{5, 10}));

  const std::vector<int> vanishing = optimal_vanishing_corners(q);
  EXPECT_EQ(corner_misfit(q, vanishing), 0);
  EXPECT_TRUE(labels_with_vanishing(q, vanishing).irregular_vertices.empty());
  // One triangle vanishes at a, the other at c; of the two ways to do it,
  // the one whose vanishing corners are sharper in sum: face 8 at a and
  // face 9 at c (45 + 40.2 degrees against 39.8 + 50.7).
  EXPECT_EQ(vanishing_vertex(q, vanishing, 8), 5);
  EXPECT_EQ(vanishing_vertex(q, vanishing, 9), 10);
  VanishingRule optimal;
  optimal.method = VanishingRule::Method::Optimal;
  EXPECT_EQ(label_field(q, optimal).vanishing_corner, vanishing);
}

TEST(VanishingTest, AmongEquallyRegularChoicesTheSharperCornersVanish) {
  // A split cell in the corner of the grid, along the diagonal from vertex
  // 1 to vertex 4: three of its vertices are on the boundary and the
  // fourth, vertex 5, is interior and keeps its four corners unless one of
  // them vanishes. Any other choice is as regular; the sharpest corners are
  // at vertex 1 in triangle (1, 5, 4) (39.8 degrees; 90 at vertex 5) and at
  // vertex 4 in triangle (1, 4, 0) (52.8; 54.6 at vertex 1).
  PolygonMesh mesh = test_meshes::grid(3, 3);
  mesh.positions[0] = {-0.3, -0.3, 0.0};
  mesh.positions[1] = {1.0, -0.2, 0.0};
  const HalfedgeMesh q(split_quads(mesh, {{0, 1}}));
  const std::vector<int> vanishing = optimal_vanishing_corners(q);
  VanishingRule acute;
  acute.method = VanishingRule::Method::Acute;
  EXPECT_EQ(vanishing, label_field(q, acute).vanishing_corner);
  EXPECT_EQ(vanishing_vertex(q, vanishing, 8), 1);
  EXPECT_EQ(vanishing_vertex(q, vanishing, 9), 4);
  EXPECT_EQ(corner_misfit(q, vanishing), 0);
}

TEST(VanishingTest, MatchesTheBestOfEveryChoiceOnSmallRandomMeshes) {
  std::mt19937 rng(7);
  int regular_worse = 0, acute_worse = 0, singular_best = 0;
  const int cases = 60;
  for (int c = 0; c < cases; ++c) {
    // A 4 x 3 torus (every vertex interior) or a 4 x 4 grid, three or four
    // of its quads split, its vertices moved at random so the sharpest
    // corners differ from case to case.
    const bool closed = c % 2 == 0;
    PolygonMesh mesh = closed ? test_meshes::torus(4, 3) : test_meshes::grid(4, 4);
    std::uniform_real_distribution<double> jitter(-0.2, 0.2);
    for (Vec3& p : mesh.positions) p += Vec3(jitter(rng), jitter(rng), jitter(rng));
    std::vector<int> order(mesh.faces.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::shuffle(order.begin(), order.end(), rng);
    const int splits = 3 + static_cast<int>(rng() % 2);
    std::vector<std::pair<int, int>> split;
    for (int s = 0; s < splits; ++s) split.emplace_back(order[at(s)], static_cast<int>(rng() % 2));
    const HalfedgeMesh q(split_quads(mesh, split));

    int best = std::numeric_limits<int>::max();
    int best_singular = std::numeric_limits<int>::max();
    for_every_choice(q, [&](const std::vector<int>& vanishing) {
      const int misfit = corner_misfit(q, vanishing);
      if (misfit > best) return;
      const int singular = singular_count(q, vanishing);
      if (misfit < best || singular < best_singular) {
        best = misfit;
        best_singular = singular;
      }
    });
    const std::vector<int> vanishing = optimal_vanishing_corners(q);
    EXPECT_EQ(corner_misfit(q, vanishing), best) << "case " << c;
    EXPECT_EQ(vanishing, optimal_vanishing_corners(q)) << "case " << c << ": not deterministic";
    singular_best += singular_count(q, vanishing) == best_singular ? 1 : 0;

    VanishingRule acute, regular;
    acute.method = VanishingRule::Method::Acute;
    regular.method = VanishingRule::Method::Regular;
    regular.slack_deg = 180.0;
    const int by_angle = corner_misfit(q, label_field(q, acute).vanishing_corner);
    const int by_moves = corner_misfit(q, label_field(q, regular).vanishing_corner);
    EXPECT_LE(best, by_angle) << "case " << c;
    EXPECT_LE(best, by_moves) << "case " << c;
    acute_worse += by_angle > best ? 1 : 0;
    regular_worse += by_moves > best ? 1 : 0;
  }
  // The cases are not all easy: the acute rule misses the best in many, and
  // moving one corner at a time (regular, any corner allowed) in some.
  EXPECT_GE(acute_worse, cases / 3) << acute_worse;
  EXPECT_GE(regular_worse, 1) << regular_worse;
  // Among the least-misfit choices, the fewest singular vertices.
  EXPECT_GE(singular_best, cases * 9 / 10) << singular_best;
}

}  // namespace
}  // namespace planner
