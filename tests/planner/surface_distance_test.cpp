#include "planner/mesh/surface_distance.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "planner/mesh/shapes.hpp"
#include "tests/planner/test_meshes.hpp"

namespace planner {
namespace {

TEST(SurfaceDistanceTest, PointTriangleDistanceInEveryRegion) {
  const Vec3 a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  EXPECT_NEAR(point_triangle_distance(Vec3(0.5, 0.5, 3), a, b, c), 3.0, 1e-12);           // face
  EXPECT_NEAR(point_triangle_distance(Vec3(-1, -1, 0), a, b, c), std::sqrt(2.0), 1e-12);  // a
  EXPECT_NEAR(point_triangle_distance(Vec3(3, 0, 0), a, b, c), 1.0, 1e-12);               // b
  EXPECT_NEAR(point_triangle_distance(Vec3(0, 4, 1), a, b, c), std::sqrt(5.0), 1e-12);    // c
  EXPECT_NEAR(point_triangle_distance(Vec3(1, -2, 0), a, b, c), 2.0, 1e-12);              // ab
  EXPECT_NEAR(point_triangle_distance(Vec3(-3, 1, 0), a, b, c), 3.0, 1e-12);              // ac
  EXPECT_NEAR(point_triangle_distance(Vec3(2, 2, 0), a, b, c), std::sqrt(2.0), 1e-12);    // bc
}

TEST(SurfaceDistanceTest, AGridLiftedByOneIsOneAway) {
  PolygonMesh low = test_meshes::grid(20, 20);
  PolygonMesh high = low;
  for (Vec3& p : high.positions) p.z() += 1.0;
  const SurfaceDistance d = distance_to_surface(high, low);
  EXPECT_NEAR(d.max_mm, 1.0, 1e-12);
  EXPECT_NEAR(d.mean_mm, 1.0, 1e-12);
  EXPECT_EQ(d.samples, 21 * 21 + 20 * 20);
  // A point far outside the grid's box still finds its nearest triangle.
  const SurfaceLocator locator(low);
  EXPECT_NEAR(locator.distance(Vec3(50, 10, 0)), 30.0, 1e-12);
  EXPECT_NEAR(locator.distance(Vec3(10, 10, -7)), 7.0, 1e-12);
}

TEST(SurfaceDistanceTest, ACoarseSphereLiesInsideAFineOne) {
  // Chords of a coarse sphere sag inside the fine one, by millimetres at
  // the face centres; the fine one's own warped quads are a little off
  // their triangles (a quad's centroid is not on its two halves).
  const PolygonMesh fine = quad_ellipsoid(50.0, 1.0, 48);
  const PolygonMesh coarse = quad_ellipsoid(50.0, 1.0, 6);
  const SurfaceDistance d = distance_to_surface(coarse, fine);
  EXPECT_GT(d.max_mm, 0.5);
  EXPECT_LT(d.max_mm, 5.0);
  EXPECT_LT(distance_to_surface(fine, fine).max_mm, 0.01);
  const PolygonMesh grid = test_meshes::grid(10, 10);
  EXPECT_LT(distance_to_surface(grid, grid).max_mm, 1e-12);
}

}  // namespace
}  // namespace planner
