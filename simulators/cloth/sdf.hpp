// The wearer as a signed distance field (§5, §8.2).
//
// Built once from a closed triangle (or polygon) mesh: every node of a
// regular grid that covers the mesh's bounding box (plus a margin) stores the
// exact distance to the surface (closest point on the nearest triangle, found
// through a bounding-volume hierarchy) with a sign from the generalised
// winding number (negative inside, where the winding number exceeds 1/2).
// The winding number makes the sign robust to small holes, slivers and
// inconsistent orientation, which ray parity is not. Queries interpolate the
// grid trilinearly and return the analytic gradient of that interpolant.
// Outside the grid the field continues as the distance to the grid box plus
// the value at the nearest box point, so far-away queries stay meaningful.
//
// Units are those of the mesh. The class is immutable after construction and
// safe to query from many threads at once.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace cloth {

using Vec3 = Eigen::Vector3d;

struct SdfParams {
  // Grid cells along the longest side of the padded box. 96 keeps the cell
  // below 1/60 of the wearer's size (about one collision clearance), which is
  // what vertex collision needs; build time grows with the cube of it.
  int resolution = 96;
  // Margin around the mesh's bounding box, as a fraction of its diagonal.
  double margin_fraction = 0.2;
  // Threads for building the grid (0: OMP_NUM_THREADS, else all hardware threads).
  int threads = 0;
};

// Exact queries on a triangle mesh: closest distance through a BVH and the
// fast (Barnes–Hut-style, dipole-approximated far field) generalised winding
// number.
class TriangleMeshQuery {
 public:
  TriangleMeshQuery(std::vector<Vec3> vertices, std::vector<std::array<int, 3>> triangles);
  ~TriangleMeshQuery();
  TriangleMeshQuery(TriangleMeshQuery&&) noexcept;
  TriangleMeshQuery& operator=(TriangleMeshQuery&&) noexcept;

  // Unsigned distance from `p` to the surface.
  double distance(const Vec3& p) const;
  // The point of the surface nearest to `p`.
  Vec3 closest_point(const Vec3& p) const;
  // How far along the unit `direction` from `origin` the ray first crosses a
  // triangle, counting crossings beyond `min_t` only (to step off the
  // surface the ray starts on); infinity when it crosses none. With
  // `facing` +1 only triangles whose (a, b, c) normal points along the ray
  // count, with -1 only those facing against it, with 0 all.
  double ray_hit(const Vec3& origin, const Vec3& direction, double min_t = 0.0,
                 int facing = 0) const;
  // Generalised winding number of the surface around `p` (1 inside a closed,
  // outward-oriented surface, 0 outside).
  double winding_number(const Vec3& p) const;
  // distance(p), negated when winding_number(p) > 0.5.
  double signed_distance(const Vec3& p) const;

  const std::vector<Vec3>& vertices() const { return vertices_; }
  const std::vector<std::array<int, 3>>& triangles() const { return triangles_; }

 private:
  struct Node;
  std::vector<Vec3> vertices_;
  std::vector<std::array<int, 3>> triangles_;
  std::vector<Node> nodes_;
  std::vector<int> order_;  // triangle indices in leaf order
  int build(int begin, int end);
};

class SignedDistanceField {
 public:
  // `faces` may be polygons; they are triangulated as fans. Throws
  // std::invalid_argument on an empty mesh or an out-of-range index.
  SignedDistanceField(const std::vector<Vec3>& vertices, const std::vector<std::vector<int>>& faces,
                      const SdfParams& params = {});

  // Interpolated signed distance at `p`.
  double value(const Vec3& p) const {
    return in_grid(p) ? interpolate(p, nullptr) : beyond_grid(p, nullptr);
  }
  // Interpolated signed distance at `p`; `gradient` receives the unit
  // direction of increasing distance (the interpolant's gradient,
  // normalised; +x when it vanishes).
  double value_and_gradient(const Vec3& p, Vec3& gradient) const {
    return in_grid(p) ? interpolate(p, &gradient) : beyond_grid(p, &gradient);
  }

  // The exact mesh queries the grid was built from.
  const TriangleMeshQuery& mesh() const { return *mesh_; }
  const Vec3& box_min() const { return origin_; }
  Vec3 box_max() const;
  double cell_size() const { return cell_; }
  std::array<int, 3> nodes() const { return {nx_, ny_, nz_}; }
  // Diagonal of the wearer's (unpadded) bounding box: the length unit of
  // every relative simulation parameter.
  double scale() const { return scale_; }

 private:
  std::shared_ptr<const TriangleMeshQuery> mesh_;
  Vec3 origin_;
  Vec3 high_;  // the last grid node (box_max), cached: every query clamps to it
  double cell_ = 1.0;
  int nx_ = 0, ny_ = 0, nz_ = 0;
  double scale_ = 1.0;
  std::vector<float> values_;
  // The queries are inline: the cloth step makes thousands of them, almost
  // all inside the grid.
  bool in_grid(const Vec3& p) const {
    return p.x() >= origin_.x() && p.y() >= origin_.y() && p.z() >= origin_.z() &&
           p.x() <= high_.x() && p.y() <= high_.y() && p.z() <= high_.z();
  }
  double interpolate(const Vec3& p, Vec3* gradient) const;
  double beyond_grid(const Vec3& p, Vec3* gradient) const;
};

// The trilinear interpolant at `p` (clamped into the grid's cells) and,
// when `gradient` is given, its normalised gradient.
inline double SignedDistanceField::interpolate(const Vec3& p, Vec3* gradient) const {
  const Vec3 g = (p - origin_) / cell_;
  // Truncation is the floor for g >= 0; a negative g clamps to cell 0
  // either way.
  const int i = std::clamp(static_cast<int>(g.x()), 0, nx_ - 2);
  const int j = std::clamp(static_cast<int>(g.y()), 0, ny_ - 2);
  const int k = std::clamp(static_cast<int>(g.z()), 0, nz_ - 2);
  const double u = std::clamp(g.x() - i, 0.0, 1.0);
  const double v = std::clamp(g.y() - j, 0.0, 1.0);
  const double w = std::clamp(g.z() - k, 0.0, 1.0);
  const float* c = values_.data() + (static_cast<std::size_t>(k) * ny_ + j) * nx_ + i;
  const std::size_t dy = nx_, dz = static_cast<std::size_t>(nx_) * ny_;
  const double c000 = c[0], c100 = c[1];
  const double c010 = c[dy], c110 = c[dy + 1];
  const double c001 = c[dz], c101 = c[dz + 1];
  const double c011 = c[dz + dy], c111 = c[dz + dy + 1];
  const double x00 = c000 + (c100 - c000) * u, x10 = c010 + (c110 - c010) * u;
  const double x01 = c001 + (c101 - c001) * u, x11 = c011 + (c111 - c011) * u;
  const double y0 = x00 + (x10 - x00) * v, y1 = x01 + (x11 - x01) * v;
  if (gradient != nullptr) {
    const double dx0 = (c100 - c000) + ((c110 - c010) - (c100 - c000)) * v;
    const double dx1 = (c101 - c001) + ((c111 - c011) - (c101 - c001)) * v;
    const double dy0 = x10 - x00, dy1 = x11 - x01;
    const Vec3 d(dx0 + (dx1 - dx0) * w, dy0 + (dy1 - dy0) * w, y1 - y0);
    const double n = d.norm();
    *gradient = n > 1e-300 ? Vec3(d / n) : Vec3::UnitX();
  }
  return y0 + (y1 - y0) * w;
}

}  // namespace cloth
