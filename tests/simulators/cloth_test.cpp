#include "simulators/cloth/cloth.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "simulators/cloth/sdf.hpp"
#include "tests/planner/cover_shapes.hpp"

namespace wearknit::test {
namespace {

std::vector<std::array<int, 3>> fan_triangles(const CoverMesh& mesh) {
  std::vector<std::array<int, 3>> triangles;
  for (const auto& f : mesh.faces) {
    for (std::size_t i = 1; i + 1 < f.size(); ++i) triangles.push_back({f[0], f[i], f[i + 1]});
  }
  return triangles;
}

cloth::SignedDistanceField unit_sphere_field(int resolution = 32) {
  const CoverMesh ball = sphere_mesh(1.0, 32, 16);
  cloth::SdfParams params;
  params.resolution = resolution;
  return cloth::SignedDistanceField(ball.positions, ball.faces, params);
}

TEST(SdfTest, WindingNumberIsOneInsideAndZeroOutside) {
  const CoverMesh ball = sphere_mesh(1.0, 24, 12);
  const std::vector<std::array<int, 3>> triangles = fan_triangles(ball);
  const cloth::TriangleMeshQuery query(ball.positions, triangles);
  // The far field is a dipole approximation: a few percent, far from 1/2.
  EXPECT_NEAR(query.winding_number({0, 0, 0}), 1.0, 0.05);
  EXPECT_NEAR(query.winding_number({0.3, -0.2, 0.5}), 1.0, 0.05);
  EXPECT_NEAR(query.winding_number({2, 0, 0}), 0.0, 0.05);
  EXPECT_NEAR(query.winding_number({0, 0, -5}), 0.0, 0.05);
}

TEST(SdfTest, ClosestPointLiesOnTheNearestTriangle) {
  // Two triangles: a unit right triangle in z = 0 and its copy raised to z = 1.
  const std::vector<Vec3> vertices{{0, 0, 0}, {1, 0, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  const cloth::TriangleMeshQuery query(vertices, {{0, 1, 2}, {3, 4, 5}});
  // Above the lower face's inside: straight down onto it.
  EXPECT_TRUE(query.closest_point({0.2, 0.3, 0.4}).isApprox(Vec3(0.2, 0.3, 0.0)));
  // Nearer the upper one: onto it.
  EXPECT_TRUE(query.closest_point({0.2, 0.3, 0.7}).isApprox(Vec3(0.2, 0.3, 1.0)));
  // Beyond the hypotenuse: onto the edge; beyond a corner: the corner.
  EXPECT_TRUE(query.closest_point({1, 1, -0.1}).isApprox(Vec3(0.5, 0.5, 0.0)));
  EXPECT_TRUE(query.closest_point({-1, -2, -0.3}).isApprox(Vec3(0, 0, 0)));
  // The distance is the distance to that point.
  const Vec3 p(0.9, 0.8, 0.3);
  EXPECT_DOUBLE_EQ(query.distance(p), (query.closest_point(p) - p).norm());
}

TEST(SdfTest, RayHitFindsTheFirstCrossingItCounts) {
  const CoverMesh ball = sphere_mesh(1.0, 48, 24);
  const std::vector<std::array<int, 3>> triangles = fan_triangles(ball);
  const cloth::TriangleMeshQuery query(ball.positions, triangles);
  const Vec3 x = Vec3::UnitX();
  // From the centre: the sphere's radius, less the facets' sag.
  EXPECT_NEAR(query.ray_hit(Vec3::Zero(), x), 1.0, 0.01);
  EXPECT_NEAR(query.ray_hit(Vec3::Zero(), Vec3(1, 1, 1).normalized()), 1.0, 0.01);
  // From outside: in at 1, out at 3; facing picks one of them.
  const Vec3 outside(-2, 0.001, 0.002);
  EXPECT_NEAR(query.ray_hit(outside, x), 1.0, 0.01);
  EXPECT_NEAR(query.ray_hit(outside, x, 0.0, -1), 1.0, 0.01);
  EXPECT_NEAR(query.ray_hit(outside, x, 0.0, +1), 3.0, 0.01);
  // Crossings nearer than min_t are skipped.
  EXPECT_NEAR(query.ray_hit(outside, x, 1.5), 3.0, 0.01);
  // A ray that misses, and one pointing away.
  EXPECT_EQ(query.ray_hit(Vec3(0, 5, 0), x), std::numeric_limits<double>::infinity());
  EXPECT_EQ(query.ray_hit(outside, -x), std::numeric_limits<double>::infinity());
}

TEST(SdfTest, WindingNumberSignSurvivesAHole) {
  // A sphere with its north cap removed is no longer closed; ray parity
  // would flip at random, the winding number stays near 1 in the middle.
  CoverMesh ball = sphere_mesh(1.0, 24, 12);
  ball.faces.erase(ball.faces.begin(), ball.faces.begin() + 24);  // the pole fan
  const std::vector<std::array<int, 3>> triangles = fan_triangles(ball);
  const cloth::TriangleMeshQuery query(ball.positions, triangles);
  EXPECT_GT(query.winding_number({0, 0, -0.2}), 0.8);
  EXPECT_LT(query.winding_number({0, 0, -3}), 0.2);
  EXPECT_LT(query.signed_distance({0, 0, -0.2}), 0);
}

TEST(SdfTest, GridMatchesExactDistanceOfASphere) {
  const auto field = unit_sphere_field(48);
  // The mesh is a polygonal sphere; its true distance differs from the round
  // sphere's by the sagitta of its facets (~0.02), the grid adds its own
  // interpolation error (~cell²).
  for (const Vec3& p : {Vec3(0, 0, 0), Vec3(0.5, 0.1, 0), Vec3(1.3, 0, 0.2), Vec3(0, -1.8, 0.4),
                        Vec3(0.2, 0.2, 0.9)}) {
    const double exact = field.mesh().signed_distance(p);
    EXPECT_NEAR(field.value(p), exact, 0.02) << p.transpose();
    EXPECT_NEAR(exact, p.norm() - 1.0, 0.03) << p.transpose();
  }
  Vec3 gradient;
  field.value_and_gradient({0.9, 0.9, 0.1}, gradient);
  EXPECT_GT(gradient.dot(Vec3(1, 1, 0).normalized()), 0.98);
  // Far outside the grid: distance to the box plus the value on it, growing.
  EXPECT_NEAR(field.value({10, 0, 0}), 9.0, 0.05);
  EXPECT_GT(field.value({20, 0, 0}), field.value({10, 0, 0}));
  field.value_and_gradient({10, 0, 0}, gradient);
  EXPECT_NEAR(gradient.x(), 1.0, 1e-9);
}

TEST(SdfTest, RejectsAFaceWithABadIndex) {
  const std::vector<Vec3> vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_THROW(cloth::SignedDistanceField(vertices, {{0, 1, 3}}), std::invalid_argument);
  EXPECT_THROW(cloth::SignedDistanceField(vertices, {}), std::invalid_argument);
}

TEST(ClothTest, SpringsFollowSection82) {
  // A 3×3-vertex patch of 4 quads: 12 edges, 8 diagonals, and bend springs
  // between every other vertex along each of the 3 rows and 3 columns.
  cloth::PolygonMesh patch;
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 3; ++x) patch.positions.push_back({double(x), double(y), 0});
  }
  auto v = [](int x, int y) { return y * 3 + x; };
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 2; ++x)
      patch.faces.push_back({v(x, y), v(x + 1, y), v(x + 1, y + 1), v(x, y + 1)});
  }
  const auto springs = cloth::build_springs(patch);
  int stretch = 0, shear = 0, bend = 0;
  for (const auto& s : springs) {
    switch (s.kind) {
      case cloth::SpringKind::Stretch:
        ++stretch;
        EXPECT_DOUBLE_EQ(s.rest_length, 1.0);
        break;
      case cloth::SpringKind::Shear:
        ++shear;
        EXPECT_DOUBLE_EQ(s.rest_length, std::sqrt(2.0));
        break;
      case cloth::SpringKind::Bend:
        ++bend;
        EXPECT_DOUBLE_EQ(s.rest_length, 2.0);
        break;
    }
  }
  EXPECT_EQ(stretch, 12);
  EXPECT_EQ(shear, 8);
  EXPECT_EQ(bend, 6);
}

TEST(ClothTest, GlobalDirectionsChangeEverySwitch) {
  const auto axes = cloth::global_directions(7, 50);
  ASSERT_EQ(axes.size(), 50u);
  for (std::size_t i = 0; i < axes.size(); ++i) {
    EXPECT_GE(axes[i], 0);
    EXPECT_LT(axes[i], 6);
    if (i > 0) {
      EXPECT_NE(axes[i], axes[i - 1]);
    }
  }
  EXPECT_EQ(axes, cloth::global_directions(7, 50));
  EXPECT_NE(axes, cloth::global_directions(8, 50));
}

TEST(ClothTest, DressedGarmentStaysOutsideTheWearer) {
  const auto field = unit_sphere_field();
  CoverMesh shell = sphere_mesh(0.9, 12, 8);  // starts inside the wearer
  cloth::PolygonMesh garment{shell.positions, shell.faces};
  cloth::ClothParams params;
  cloth::dress(garment, field, params.clearance);
  for (const Vec3& x : garment.positions)
    EXPECT_GE(field.value(x), 0.99 * params.clearance * field.scale());
  params.max_steps = 200;
  cloth::ClothSimulation sim(garment, field, params);
  sim.run(3);
  EXPECT_GE(sim.min_distance(), 0.9 * params.clearance * field.scale());
}

TEST(ClothTest, SameSeedSameTrajectoryForAnyThreadCount) {
  const auto field = unit_sphere_field();
  CoverMesh cap = sphere_mesh(1.0, 12, 4, std::numbers::pi / 2);
  cloth::PolygonMesh garment{cap.positions, cap.faces};
  cloth::ClothParams params;
  cloth::dress(garment, field, params.clearance);
  params.max_steps = 120;
  params.threads = 1;
  cloth::ClothSimulation one(garment, field, params);
  one.run(11);
  params.threads = 2;
  cloth::ClothSimulation two(garment, field, params);
  two.run(11);
  params.threads = 3;  // parts of unequal size
  cloth::ClothSimulation three(garment, field, params);
  three.run(11);
  ASSERT_EQ(one.positions().size(), two.positions().size());
  ASSERT_EQ(one.positions().size(), three.positions().size());
  for (std::size_t i = 0; i < one.positions().size(); ++i) {
    EXPECT_EQ(one.positions()[i], two.positions()[i]) << i;
    EXPECT_EQ(one.positions()[i], three.positions()[i]) << i;
  }
  cloth::ClothSimulation other(garment, field, params);
  other.run(12);
  double moved = 0;
  for (std::size_t i = 0; i < one.positions().size(); ++i) {
    moved += (one.positions()[i] - other.positions()[i]).norm();
  }
  EXPECT_GT(moved, 0) << "another seed drives the global force elsewhere";
}

TEST(ClothTest, LocalForceLiftsAnOpenCapOffASphere) {
  const auto field = unit_sphere_field();
  CoverMesh cap = sphere_mesh(1.0, 12, 4, std::numbers::pi / 2);
  cloth::PolygonMesh garment{cap.positions, cap.faces};
  cloth::ClothParams params;
  cloth::dress(garment, field, params.clearance);
  params.global_acceleration = 0;  // local force alone (Fig. 6b)
  params.max_steps = 400;
  cloth::ClothSimulation sim(garment, field, params);
  const double before = sim.min_distance();
  sim.run(1);
  EXPECT_GT(sim.min_distance(), 2 * before);
  EXPECT_GT(sim.projections(), 0u);
}

}  // namespace
}  // namespace wearknit::test
