#include "planner/proxy/cross_field.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <string>

#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/shapes.hpp"
#include "planner/proxy/proxy.hpp"
#include "tests/planner/test_meshes.hpp"
#include "tests/test_support.hpp"

namespace planner {
namespace {

const double kPi = std::acos(-1.0);

// An open tube of `radius` along z, `length` long: n triangles round, m
// rows of them, the diagonals of alternate rows leaning alternate ways.
PolygonMesh tube(double radius, double length, int n, int m) {
  PolygonMesh mesh;
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i < n; ++i) {
      const double a = 2 * kPi * i / n;
      mesh.positions.emplace_back(radius * std::cos(a), radius * std::sin(a), length * j / m);
    }
  }
  auto id = [&](int i, int j) { return j * n + (i + n) % n; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      if (j % 2 == 0) {
        mesh.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        mesh.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        mesh.faces.push_back({id(i, j), id(i + 1, j), id(i, j + 1)});
        mesh.faces.push_back({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  }
  return mesh;
}

// The rotation of `mesh` by `angle` radians about `axis`.
PolygonMesh rotated(PolygonMesh mesh, double angle, const Vec3& axis) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  for (Vec3& p : mesh.positions) p = r * p;
  return mesh;
}

TEST(CrossFieldTest, AQuadWithAStraightCornerIsFannedFromThatCorner) {
  // A pentagon beside two quads: its corner 1 lies on the straight line
  // between its neighbours 0 and 2. Fanned from 0, the triangle (0, 1, 2)
  // would have no area; fanned from 1, none has.
  PolygonMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0},  {2, 0, 0},  {2, 1, 0},
                    {0, 1, 0}, {0, -1, 0}, {1, -1, 0}, {2, -1, 0}};
  mesh.faces = {{0, 1, 2, 3, 4}, {5, 6, 1, 0}, {6, 7, 2, 1}};
  const PolygonMesh triangles = fan_triangulated(mesh);
  ASSERT_EQ(triangles.faces.size(), 3U + 2U + 2U);
  for (const auto& f : triangles.faces) {
    const Vec3& a = triangles.positions[at(f[0])];
    const Vec3& b = triangles.positions[at(f[1])];
    const Vec3& c = triangles.positions[at(f[2])];
    EXPECT_GT((b - a).cross(c - a).norm(), 0.1) << f[0] << " " << f[1] << " " << f[2];
  }
}

TEST(CrossFieldTest, ASphereHasEightPlusOneSingularities) {
  const CrossField field = smoothest_cross_field(quad_ellipsoid(50.0, 1.0, 8), {});
  const FieldSingularities s = field_singularities(field);
  EXPECT_EQ(field.euler_characteristic, 2);
  EXPECT_EQ(s.index_sum, 8);
  EXPECT_EQ(s.count, 8);
  EXPECT_EQ(s.by_index, (std::map<int, int>{{1, 8}}));
}

TEST(CrossFieldTest, ATorusHasNoSingularity) {
  const CrossField field = smoothest_cross_field(test_meshes::torus(48, 16), {});
  const FieldSingularities s = field_singularities(field);
  EXPECT_EQ(field.euler_characteristic, 0);
  EXPECT_EQ(s.index_sum, 0);
  EXPECT_EQ(s.count, 0);
}

TEST(CrossFieldTest, AFlatPatchGetsOneConstantCross) {
  // A 10 x 10 grid with its inner vertices moved in the plane: triangles of
  // every shape, and frames that differ from triangle to triangle.
  PolygonMesh grid = test_meshes::grid(10, 10);
  for (std::size_t v = 0; v < grid.positions.size(); ++v) {
    Vec3& p = grid.positions[v];
    if (p.x() > 0 && p.x() < 10 && p.y() > 0 && p.y() < 10)
      p += 0.3 *
           Vec3(std::sin(7.0 * static_cast<double>(v)), std::cos(5.0 * static_cast<double>(v)), 0);
  }
  const CrossField field = smoothest_cross_field(grid, {});
  const FieldSingularities s = field_singularities(field);
  EXPECT_EQ(s.count, 0);
  EXPECT_EQ(field.boundary_loops, 1);
  // The fourth power of the direction's angle in the plane's own frame is
  // the same in every triangle.
  auto cross = [](const Vec3& d) { return std::polar(1.0, 4.0 * std::atan2(d.y(), d.x())); };
  ASSERT_FALSE(field.direction.empty());
  const std::complex<double> first = cross(field.direction[0]);
  for (std::size_t f = 0; f < field.direction.size(); ++f) {
    EXPECT_NEAR(std::abs(cross(field.direction[f]) - first), 0.0, 1e-6) << "triangle " << f;
    EXPECT_NEAR(field.direction[f].z(), 0.0, 1e-12);
  }
}

TEST(CrossFieldTest, MovingTheSurfaceRigidlyChangesNoSingularity) {
  const PolygonMesh egg = quad_ellipsoid(40.0, 1.6, 10);
  const CrossField field = smoothest_cross_field(egg, {});
  const CrossField moved = smoothest_cross_field(rotated(egg, 1.1, Vec3(1, 2, 3)), {});
  EXPECT_EQ(field_singularities(field).index_sum, 8);
  EXPECT_EQ(moved.index, field.index);
  EXPECT_EQ(field_singularities(moved).by_index, field_singularities(field).by_index);
}

TEST(CrossFieldTest, ScalingTheSurfaceAndItsScaleTogetherChangesNothing) {
  // Times 8, which floating point does exactly: the decimation makes the
  // same choices.
  const PolygonMesh egg = quad_ellipsoid(40.0, 1.6, 24);
  PolygonMesh big = egg;
  for (Vec3& p : big.positions) p *= 8.0;
  CrossFieldParams params;
  params.edge_mm = 12.0;
  const CrossField field = smoothest_cross_field(egg, params);
  params.edge_mm = 96.0;
  const CrossField scaled = smoothest_cross_field(big, params);
  EXPECT_LT(field.surface.faces.size(), egg.faces.size());  // it was decimated
  EXPECT_EQ(scaled.surface.faces.size(), field.surface.faces.size());
  EXPECT_EQ(scaled.index, field.index);
  EXPECT_EQ(field_singularities(field).index_sum, 8);
  EXPECT_NEAR(scaled.energy * 64.0, field.energy, 1e-9 * field.energy);
}

TEST(CrossFieldTest, CurvatureAlignmentTurnsTheCrossToATubesAxis) {
  // A tube is flat: every constant angle to its axis is equally smooth.
  // The curvature term picks the axis and the circumference.
  CrossFieldParams params;
  params.curvature_weight = 1.0;
  const CrossField field = smoothest_cross_field(tube(10.0, 40.0, 32, 20), params);
  EXPECT_EQ(field_singularities(field).count, 0);
  for (std::size_t f = 0; f < field.direction.size(); ++f) {
    const double c = field.direction[f].z();  // the cosine of the angle to the axis
    const double cos4 = 8 * c * c * c * c - 8 * c * c + 1;
    EXPECT_GT(cos4, 0.99) << "triangle " << f << " at " << std::acos(std::abs(c)) * 180 / kPi
                          << " degrees to the axis";
  }
}

TEST(CrossFieldTest, DetailFarBelowTheScaleMakesNoSingularity) {
  // A sphere of 2 mm edges whose vertices are pushed in and out by up to
  // 0.8 mm (fixed pseudo-random amounts): at its own edges the field turns
  // round the bumps; at 12 mm edges only the sphere's eight remain.
  PolygonMesh rough = quad_ellipsoid(50.0, 1.0, 32);
  for (std::size_t v = 0; v < rough.positions.size(); ++v) {
    Vec3& p = rough.positions[v];
    p *= 1.0 + 0.016 * std::sin(12.9898 * static_cast<double>(v) * 78.233);
  }
  const FieldSingularities fine = field_singularities(smoothest_cross_field(rough, {}));
  CrossFieldParams params;
  params.edge_mm = 12.0;
  const FieldSingularities coarse = field_singularities(smoothest_cross_field(rough, params));
  EXPECT_GT(fine.count, 8);
  EXPECT_EQ(fine.index_sum, 8);
  EXPECT_EQ(coarse.by_index, (std::map<int, int>{{1, 8}}));
}

TEST(CrossFieldTest, IndicesSumToFourChiOnEverySharedClosedMesh) {
  WEARKNIT_REQUIRE_SHARED(shared);
  int closed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(shared / "meshes")) {
    if (entry.path().extension() != ".obj") continue;
    knitout::DiagnosticSink sink;
    std::optional<PolygonMesh> mesh = load_mesh(entry.path().string(), {}, sink);
    ASSERT_TRUE(mesh) << entry.path();
    // As the cut stage takes it: 100 mm along its longest side, the field at
    // the edge length of a proxy of about 3000 quads.
    const Vec3 size = bounding_box_size(*mesh);
    for (Vec3& p : mesh->positions) p *= 100.0 / size.maxCoeff();
    const HalfedgeMesh input(*mesh);
    if (input.count_boundary_loops() > 0) continue;
    ++closed;
    CrossFieldParams params;
    params.edge_mm = std::sqrt(total_area(*mesh) / ProxyParams{}.auto_faces);
    const CrossField field = smoothest_cross_field(*mesh, params);
    const FieldSingularities s = field_singularities(field);
    EXPECT_EQ(field.euler_characteristic, input.euler_characteristic()) << entry.path();
    EXPECT_EQ(s.index_sum, 4 * input.euler_characteristic()) << entry.path();
    std::cout << entry.path().stem().string() << ": chi " << input.euler_characteristic() << ", "
              << s.count << " singularities at " << params.edge_mm << " mm\n";
  }
  EXPECT_GT(closed, 20);
}

}  // namespace
}  // namespace planner
