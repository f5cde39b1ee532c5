#include "planner/mesh/surface_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "planner/common/index.hpp"

namespace planner {

double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  // The closest point by the Voronoi regions of the triangle's corners,
  // sides and face, in barycentric terms.
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return (p - (b + w * (c - b))).norm();
  }
  const double sum = va + vb + vc;
  if (!(sum > 0)) return std::min({ap.norm(), bp.norm(), cp.norm()});  // degenerate
  return (p - (a + ab * (vb / sum) + ac * (vc / sum))).norm();
}

SurfaceLocator::SurfaceLocator(const PolygonMesh& surface) {
  for (const auto& face : surface.faces) {
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      triangles_.push_back({surface.positions[at(face[0])], surface.positions[at(face[i])],
                            surface.positions[at(face[i + 1])]});
    }
  }
  if (triangles_.empty()) return;
  Vec3 lo = triangles_[0][0], hi = lo;
  double edges = 0.0;
  for (const auto& t : triangles_) {
    for (const Vec3& p : t) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    edges += (t[1] - t[0]).norm() + (t[2] - t[1]).norm() + (t[0] - t[2]).norm();
  }
  // Cells of about two mean edges, at most 256 along the longest side.
  const double longest = (hi - lo).maxCoeff();
  cell_ = std::max(
      {2.0 * edges / (3.0 * static_cast<double>(triangles_.size())), longest / 256.0, 1e-9});
  origin_ = lo;
  for (int k = 0; k < 3; ++k)
    extent_[at(k)] = static_cast<int>(std::floor((hi[k] - lo[k]) / cell_)) + 1;
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    const auto& t = triangles_[i];
    const std::array<int, 3> a = cell_of(t[0].cwiseMin(t[1]).cwiseMin(t[2]));
    const std::array<int, 3> b = cell_of(t[0].cwiseMax(t[1]).cwiseMax(t[2]));
    for (int x = a[0]; x <= b[0]; ++x) {
      for (int y = a[1]; y <= b[1]; ++y) {
        for (int z = a[2]; z <= b[2]; ++z) cells_[key({x, y, z})].push_back(static_cast<int>(i));
      }
    }
  }
}

std::array<int, 3> SurfaceLocator::cell_of(const Vec3& p) const {
  std::array<int, 3> cell{};
  for (int k = 0; k < 3; ++k) {
    const double c = std::floor((p[k] - origin_[k]) / cell_);
    cell[at(k)] = static_cast<int>(std::clamp(c, -1.0, static_cast<double>(extent_[at(k)])));
  }
  return cell;
}

std::int64_t SurfaceLocator::key(const std::array<int, 3>& cell) const {
  return ((static_cast<std::int64_t>(cell[0]) + 2) * (extent_[1] + 4) + cell[1] + 2) *
             (extent_[2] + 4) +
         cell[2] + 2;
}

double SurfaceLocator::distance(const Vec3& p) const {
  if (triangles_.empty()) return 0.0;
  double best = std::numeric_limits<double>::infinity();
  // The point's distance to the grid's box: rings nearer than that are empty.
  const Vec3 lo = origin_;
  const Vec3 hi = origin_ + cell_ * Vec3(extent_[0], extent_[1], extent_[2]);
  const double outside = (p - p.cwiseMax(lo).cwiseMin(hi)).norm();
  const std::array<int, 3> c = cell_of(p);
  const int rings = std::max({extent_[0], extent_[1], extent_[2]}) + 2;
  for (int r = 0; r <= rings; ++r) {
    for (int x = c[0] - r; x <= c[0] + r; ++x) {
      for (int y = c[1] - r; y <= c[1] + r; ++y) {
        for (int z = c[2] - r; z <= c[2] + r; ++z) {
          // The ring's shell only.
          if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != r) continue;
          const auto it = cells_.find(key({x, y, z}));
          if (it == cells_.end()) continue;
          for (const int i : it->second) {
            const auto& t = triangles_[at(i)];
            best = std::min(best, point_triangle_distance(p, t[0], t[1], t[2]));
          }
        }
      }
    }
    // Triangles not yet seen lie in cells beyond ring r: more than r cells
    // from p's (clamped) cell, and no nearer than the grid's box.
    if (best <= std::max(outside, r * cell_)) break;
  }
  return best;
}

SurfaceDistance distance_to_surface(const PolygonMesh& from, const PolygonMesh& to) {
  const SurfaceLocator locator(to);
  SurfaceDistance d;
  double sum = 0.0;
  auto sample = [&](const Vec3& p) {
    const double x = locator.distance(p);
    d.max_mm = std::max(d.max_mm, x);
    sum += x;
    ++d.samples;
  };
  for (const Vec3& p : from.positions) sample(p);
  for (const auto& face : from.faces) {
    Vec3 centre = Vec3::Zero();
    for (const int v : face) centre += from.positions[at(v)];
    if (!face.empty()) sample(centre / static_cast<double>(face.size()));
  }
  d.mean_mm = d.samples > 0 ? sum / d.samples : 0.0;
  return d;
}

}  // namespace planner
