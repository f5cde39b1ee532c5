// How far one surface lies from another: the distance from sample points of
// one (its vertices and face centroids) to the nearest point of the other's
// triangles, through a uniform grid of the triangles. The cut stage reports
// it for the proxy Q against the garment: the stitch mesh is built on Q's
// disc, so its stitches lie no farther from the garment than Q does.
#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "planner/mesh/mesh.hpp"

namespace planner {

// Nearest distances to the triangles of a surface (polygons are fanned).
class SurfaceLocator {
 public:
  explicit SurfaceLocator(const PolygonMesh& surface);
  // Distance from p to the nearest point of the surface, mm; 0 for an
  // empty surface.
  double distance(const Vec3& p) const;

 private:
  std::int64_t key(const std::array<int, 3>& cell) const;
  std::array<int, 3> cell_of(const Vec3& p) const;

  std::vector<std::array<Vec3, 3>> triangles_;
  std::unordered_map<std::int64_t, std::vector<int>> cells_;
  Vec3 origin_ = Vec3::Zero();
  double cell_ = 1.0;
  std::array<int, 3> extent_{};  // cells along each axis
};

// Distance from point p to triangle a, b, c.
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

struct SurfaceDistance {
  double max_mm = 0.0;
  double mean_mm = 0.0;
  int samples = 0;
};

// From the vertices and face centroids of `from` to the surface `to`.
SurfaceDistance distance_to_surface(const PolygonMesh& from, const PolygonMesh& to);

}  // namespace planner
