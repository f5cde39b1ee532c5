#include "planner/stitch_mesh_remesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "planner/stitch_mesh.hpp"
#include "tests/planner/stitch_discs.hpp"

namespace planner {
namespace {

namespace sd = stitch_discs;

// Everything issue 8 asks of a stitch mesh made from a disc of known area.
void expect_good_stitch_mesh(const LabelledDisc& disc, double area_mm2,
                             const AnisoRemeshParams& params, const std::string& name) {
  SCOPED_TRACE(name);
  const AnisoRemeshResult result = remesh_anisotropic(disc, params);
  const StitchMesh& mesh = result.mesh;
  for (const std::string& p : result.problems) ADD_FAILURE() << p;
  EXPECT_TRUE(check(mesh).empty());
  const StitchMeshFigures f = measure(mesh);
  // One disc.
  EXPECT_EQ(f.boundary_loops, 1);
  EXPECT_EQ(f.euler_characteristic, 1);
  // With the input's boundary: every boundary vertex lies on it, and the
  // boundary is as long (chords of the side runs are a little shorter).
  EXPECT_LT(sd::farthest_boundary_vertex(disc, mesh), 1e-6 * (1 + std::sqrt(area_mm2)));
  const double input_boundary = disc_boundary_length_mm(disc);
  EXPECT_NEAR(f.boundary_length_mm / input_boundary, 1.0, 0.05);
  // Sizes: mean lengths within 5%, 90% of edges within 15%.
  EXPECT_NEAR(f.course.mean_mm / params.course_mm, 1.0, 0.05);
  EXPECT_NEAR(f.wale.mean_mm / params.wale_mm, 1.0, 0.05);
  EXPECT_GE(f.course.within_15_percent, 0.9);
  EXPECT_GE(f.wale.within_15_percent, 0.9);
  // Stitch count within 10% of area / (course x wale).
  const double expected = area_mm2 / (params.course_mm * params.wale_mm);
  EXPECT_NEAR(f.faces / expected, 1.0, 0.10);
  std::printf(
      "[%s] faces %d (expected %.0f) knit %d inc %d dec %d short %d | course mean %.3f "
      "within %.3f | wale mean %.3f within %.3f | rows %d strips %d lenses %d | %.3f s\n",
      name.c_str(), f.faces, expected, f.knit, f.increase, f.decrease, f.short_row,
      f.course.mean_mm, f.course.within_15_percent, f.wale.mean_mm, f.wale.within_15_percent,
      result.stats.rows, result.stats.strips, result.stats.lenses_skipped,
      result.stats.total_seconds);
}

AnisoRemeshParams default_params() {
  return AnisoRemeshParams{};
}

TEST(StitchMeshRemeshTest, MeshesAFlatRectangleIntoKnitQuads) {
  const LabelledDisc disc = sd::rectangle(60, 40);
  expect_good_stitch_mesh(disc, sd::rectangle_area(60, 40), default_params(), "rectangle");
  const StitchMeshFigures f = measure(remesh_anisotropic(disc, default_params()).mesh);
  // Straight rows of equal length: nothing but knit stitches.
  EXPECT_EQ(f.knit, f.faces);
}

TEST(StitchMeshRemeshTest, MeshesAParallelogramWithSlantedSides) {
  // Rows horizontal, sides slanted 30 degrees: the rows end obliquely.
  const double shear = std::tan(30.0 * sd::kPi / 180.0);
  const LabelledDisc disc = sd::grid_disc(30, 20, [=](double s, double t) {
    return Eigen::Vector3d(50 * s + 40 * shear * t, 40 * t, 0.0);
  });
  expect_good_stitch_mesh(disc, 50.0 * 40.0, default_params(), "parallelogram");
}

TEST(StitchMeshRemeshTest, MeshesACylinderCutOpen) {
  expect_good_stitch_mesh(sd::cylinder(15, 40), sd::cylinder_area(15, 40), default_params(),
                          "cylinder");
}

TEST(StitchMeshRemeshTest, MeshesAConeWithDecreases) {
  const LabelledDisc disc = sd::cone(20, 10, 40);
  expect_good_stitch_mesh(disc, sd::cone_area(20, 10, 40), default_params(), "cone");
  const StitchMeshFigures f = measure(remesh_anisotropic(disc, default_params()).mesh);
  // Rows shrink from ~120 to ~60 stitches going up: decreases, no increases.
  EXPECT_GT(f.decrease, 40);
  EXPECT_EQ(f.increase, 0);
}

TEST(StitchMeshRemeshTest, MeshesAHemisphereCap) {
  expect_good_stitch_mesh(sd::hemisphere(20), sd::hemisphere_area(20), default_params(),
                          "hemisphere");
}

}  // namespace
}  // namespace planner
