#include "planner/mesh/girth.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "planner/mesh/shapes.hpp"
#include "tests/planner/test_meshes.hpp"

namespace planner {
namespace {

using test_meshes::revolution;

TEST(GirthTest, ATubeIsAsRoundAsItsCrossSection) {
  // A torus whose tube has radius 4: every vertex lies on a cross-section
  // of girth 2 pi 4. The sampled tangent lines miss the cross-section's
  // plane by up to 22.5 degrees, which overstates the width a little.
  const PolygonMesh ring = test_meshes::torus(96, 24, 30.0, 4.0);
  const std::vector<double> girth = measure_girth(ring);
  ASSERT_EQ(girth.size(), ring.positions.size());
  const double expected = 2 * std::numbers::pi * 4.0;
  for (const double g : girth) {
    EXPECT_GT(g, 0.95 * expected);
    EXPECT_LT(g, 1.1 * expected);
  }
}

TEST(GirthTest, ABallIsAsRoundAsItsGreatCircle) {
  const PolygonMesh ball = quad_ellipsoid(20.0, 1.0, 12);
  for (const double g : measure_girth(ball)) EXPECT_NEAR(g, 2 * std::numbers::pi * 20.0, 0.06 * g);
}

TEST(GirthTest, APlateIsThinButNotFine) {
  // A 10 x 10 x 0.5 plate: the ray through it is short, the plate is wide.
  PolygonMesh plate = test_meshes::cube(10);
  for (Vec3& p : plate.positions) p.z() *= 0.05;
  const std::vector<double> girth = measure_girth(plate);
  for (std::size_t v = 0; v < plate.positions.size(); ++v) {
    const Vec3& p = plate.positions[v];
    if (std::abs(p.x() - 5) < 1e-9 && std::abs(p.y() - 5) < 1e-9) {  // the middle of a face
      EXPECT_GT(girth[v], 10.0) << "vertex " << v;
    }
  }
}

TEST(GirthTest, AnOpenSheetHasNoGirth) {
  for (const double g : measure_girth(test_meshes::grid(6, 6))) EXPECT_EQ(g, kNoGirth);
}

TEST(GirthTest, InwardFacingFacesGiveTheSameGirth) {
  // Faces listed clockwise: the enclosed volume says which way is out.
  PolygonMesh ball = quad_ellipsoid(20.0, 1.0, 12);
  const std::vector<double> outward = measure_girth(ball);
  for (auto& face : ball.faces) std::reverse(face.begin(), face.end());
  const std::vector<double> inward = measure_girth(ball);
  ASSERT_EQ(inward.size(), outward.size());
  // The same up to the quads' other diagonal in the fan triangulation.
  for (std::size_t v = 0; v < inward.size(); ++v)
    EXPECT_NEAR(inward[v], outward[v], 0.002 * outward[v]);
}

TEST(GirthTest, NarrowPartsAreTheThinEndsNotTheBody) {
  // A spindle 80 long: radius 12 in the middle, thinning to 1.5 near both
  // ends. The two ends are the fine parts; the body is not.
  const auto radius = [](double z) {
    const double t = (z - 40.0) / 40.0;  // -1 .. 1
    return 1.5 + 10.5 * std::max(0.0, 1.0 - 2.0 * t * t);
  };
  const PolygonMesh spindle = revolution(80.0, 79, 24, radius);
  const std::vector<double> girth = measure_girth(spindle);
  const double bound = 2 * std::numbers::pi * 3.0;
  const std::vector<NarrowPart> parts = narrow_parts(spindle, girth, bound);
  ASSERT_EQ(parts.size(), 2u);
  for (const NarrowPart& part : parts) {
    EXPECT_LT(part.girth_mm, bound);
    EXPECT_GT(part.girth_mm, 0.8 * 2 * std::numbers::pi * 1.5);
    // One part at each end.
    EXPECT_TRUE(part.centre.z() < 20.0 || part.centre.z() > 60.0) << part.centre.z();
    // Its narrowest girth lies where the spindle is thinnest, within 11.7
    // of its tip.
    EXPECT_LT(std::min(part.narrowest_at.z(), 80.0 - part.narrowest_at.z()), 12.0);
    EXPECT_GE(part.vertices, 24);
  }
  EXPECT_NE(parts[0].centre.z() < 40.0, parts[1].centre.z() < 40.0);
  EXPECT_LE(parts[0].girth_mm, parts[1].girth_mm);  // narrowest first
  // Below every girth: no part.
  EXPECT_TRUE(narrow_parts(spindle, girth, 1.0).empty());
}

TEST(GirthTest, TransferTakesTheNearestVertex) {
  const PolygonMesh ball = quad_ellipsoid(20.0, 1.0, 8);
  std::vector<double> girth(ball.positions.size());
  for (std::size_t v = 0; v < girth.size(); ++v) girth[v] = static_cast<double>(v);
  // Each vertex, moved a little outwards, finds itself.
  std::vector<Vec3> points;
  for (const Vec3& p : ball.positions) points.push_back(1.01 * p);
  const std::vector<double> moved = girth_at(ball, girth, points);
  ASSERT_EQ(moved.size(), girth.size());
  for (std::size_t v = 0; v < girth.size(); ++v) EXPECT_EQ(moved[v], girth[v]);
  // A far point finds the vertex nearest it.
  const std::vector<double> far = girth_at(ball, girth, {Vec3(500, 1, 2)});
  std::size_t nearest = 0;
  for (std::size_t v = 0; v < girth.size(); ++v) {
    if ((ball.positions[v] - Vec3(500, 1, 2)).norm() <
        (ball.positions[nearest] - Vec3(500, 1, 2)).norm())
      nearest = v;
  }
  EXPECT_EQ(far[0], girth[nearest]);
}

}  // namespace
}  // namespace planner
