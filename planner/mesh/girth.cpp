#include "planner/mesh/girth.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <unordered_map>

#include "planner/common/index.hpp"
#include "planner/common/union_find.hpp"
#include "simulators/cloth/parallel.hpp"
#include "simulators/cloth/sdf.hpp"

namespace planner {

namespace {

std::vector<std::array<int, 3>> fan_triangles(const PolygonMesh& mesh) {
  std::vector<std::array<int, 3>> triangles;
  for (const auto& face : mesh.faces) {
    for (std::size_t i = 1; i + 1 < face.size(); ++i)
      triangles.push_back({face[0], face[i], face[i + 1]});
  }
  return triangles;
}

// Unit normals per vertex (sums of the faces' area vectors), pointing out of
// the solid: flipped when the faces enclose a negative volume; `sign` says
// whether they were (-1) or not (+1).
std::vector<Vec3> outward_normals(const PolygonMesh& mesh, int& sign) {
  std::vector<Vec3> normals(mesh.positions.size(), Vec3::Zero());
  double volume = 0;
  for (const auto& face : mesh.faces) {
    Vec3 area = Vec3::Zero();
    const Vec3& o = mesh.positions[at(face[0])];
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      const Vec3& b = mesh.positions[at(face[i])];
      const Vec3& c = mesh.positions[at(face[i + 1])];
      area += 0.5 * (b - o).cross(c - o);
      volume += o.dot(b.cross(c)) / 6.0;
    }
    for (const int v : face) normals[at(v)] += area;
  }
  sign = volume < 0 ? -1 : 1;
  for (Vec3& n : normals) {
    const double length = n.norm();
    n = length > 0 ? Vec3(sign * n / length) : Vec3::Zero();
  }
  return normals;
}

// The raw girth at one vertex (see girth.hpp), or kNoGirth. Rays from
// inside count only the faces they leave the solid through (`exit`: the
// facing of those faces for ray_hit), so a sheet inside the solid (a fold
// of a self-intersecting surface) does not make it look thin.
double vertex_girth(const cloth::TriangleMeshQuery& query, const Vec3& p, const Vec3& outward,
                    double step, int exit) {
  if (outward.isZero()) return kNoGirth;
  const Vec3 inward = -outward;
  const double thickness = query.ray_hit(p, inward, step, exit);
  if (!std::isfinite(thickness)) return kNoGirth;
  const Vec3 middle = p + 0.5 * thickness * inward;
  // Two tangent directions.
  const Vec3 helper = std::abs(inward.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 u = inward.cross(helper).normalized();
  const Vec3 v = inward.cross(u);
  double width = kNoGirth;
  for (int k = 0; k < 4; ++k) {
    const double angle = k * std::numbers::pi / 4;
    const Vec3 d = std::cos(angle) * u + std::sin(angle) * v;
    const double across =
        query.ray_hit(middle, d, 0.0, exit) + query.ray_hit(middle, -d, 0.0, exit);
    width = std::min(width, across);
  }
  if (!std::isfinite(width)) return kNoGirth;
  return std::numbers::pi * (thickness + width) / 2.0;
}

std::vector<std::vector<int>> vertex_neighbours(const PolygonMesh& mesh) {
  std::vector<std::vector<int>> neighbours(mesh.positions.size());
  for (const auto& face : mesh.faces) {
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i];
      const int b = face[(i + 1) % face.size()];
      neighbours[at(a)].push_back(b);
      neighbours[at(b)].push_back(a);
    }
  }
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return neighbours;
}

}  // namespace

std::vector<double> measure_girth(const PolygonMesh& mesh) {
  const std::size_t n = mesh.positions.size();
  std::vector<double> raw(n, kNoGirth);
  if (mesh.faces.empty()) return raw;
  const cloth::TriangleMeshQuery query(mesh.positions, fan_triangles(mesh));
  int sign = 1;
  const std::vector<Vec3> normals = outward_normals(mesh, sign);
  Eigen::AlignedBox3d box;
  for (const Vec3& p : mesh.positions) box.extend(p);
  // Crossings nearer than this are the faces the ray starts on.
  const double step = 1e-6 * box.diagonal().norm();
  cloth::parallel_for(static_cast<int>(n), 0, [&](int v) {
    raw[at(v)] = vertex_girth(query, mesh.positions[at(v)], normals[at(v)], step, sign);
  });
  const std::vector<std::vector<int>> neighbours = vertex_neighbours(mesh);
  std::vector<double> girth(n);
  std::vector<double> ring;
  for (std::size_t v = 0; v < n; ++v) {
    ring.assign(1, raw[v]);
    for (const int w : neighbours[v]) ring.push_back(raw[at(w)]);
    const auto middle = ring.begin() + static_cast<std::ptrdiff_t>(ring.size() / 2);
    std::nth_element(ring.begin(), middle, ring.end());
    girth[v] = *middle;
  }
  return girth;
}

std::vector<double> girth_at(const PolygonMesh& mesh, const std::vector<double>& girth,
                             const std::vector<Vec3>& points) {
  std::vector<double> out(points.size(), kNoGirth);
  if (mesh.positions.empty()) return out;
  // A uniform grid of about one vertex per cell; the search widens ring by
  // ring until the nearest vertex found is nearer than the next ring.
  Eigen::AlignedBox3d box;
  for (const Vec3& p : mesh.positions) box.extend(p);
  const double volume = std::max(box.volume(), 1e-12);
  const double cell =
      std::max(std::cbrt(volume / static_cast<double>(mesh.positions.size())), 1e-9);
  auto cell_of = [&](const Vec3& p) {
    const Vec3 c = ((p - box.min()) / cell).array().floor();
    return std::array<long, 3>{static_cast<long>(c.x()), static_cast<long>(c.y()),
                               static_cast<long>(c.z())};
  };
  auto key = [](long x, long y, long z) {
    return (static_cast<std::uint64_t>(x + (1L << 20)) << 42) ^
           (static_cast<std::uint64_t>(y + (1L << 20)) << 21) ^
           static_cast<std::uint64_t>(z + (1L << 20));
  };
  std::unordered_map<std::uint64_t, std::vector<int>> cells;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const auto c = cell_of(mesh.positions[v]);
    cells[key(c[0], c[1], c[2])].push_back(static_cast<int>(v));
  }
  const Vec3 span = box.sizes() / cell;
  const long max_ring = static_cast<long>(std::ceil(span.maxCoeff())) + 2;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    // The search starts from the box point nearest p. Every vertex lies in
    // the box, so a vertex r cells from there is at least sqrt(d0^2 + (r
    // cell)^2) from p (d0: p's distance to the box; the box is convex).
    const Vec3 inside = p.cwiseMax(box.min()).cwiseMin(box.max());
    const double d0 = (p - inside).squaredNorm();
    const auto c = cell_of(inside);
    double best = std::numeric_limits<double>::infinity();
    int nearest = -1;
    for (long ring = 0; ring <= max_ring; ++ring) {
      for (long x = c[0] - ring; x <= c[0] + ring; ++x) {
        for (long y = c[1] - ring; y <= c[1] + ring; ++y) {
          for (long z = c[2] - ring; z <= c[2] + ring; ++z) {
            const long shell =
                std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])});
            if (shell != ring) continue;
            const auto found = cells.find(key(x, y, z));
            if (found == cells.end()) continue;
            for (const int v : found->second) {
              const double d = (mesh.positions[at(v)] - p).squaredNorm();
              if (d < best) {
                best = d;
                nearest = v;
              }
            }
          }
        }
      }
      // Every cell beyond this ring is at least `ring` cells away.
      if (nearest >= 0 && best <= d0 + (ring * cell) * (ring * cell)) break;
    }
    if (nearest >= 0) out[i] = girth[at(nearest)];
  }
  return out;
}

std::vector<NarrowPart> narrow_parts(const PolygonMesh& mesh, const std::vector<double>& girth,
                                     double bound_mm) {
  const std::size_t n = mesh.positions.size();
  auto narrow = [&](int v) { return at(v) < girth.size() && girth[at(v)] < bound_mm; };
  UnionFind sets(n);
  for (const auto& face : mesh.faces) {
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i];
      const int b = face[(i + 1) % face.size()];
      if (narrow(a) && narrow(b)) sets.unite(a, b);
    }
  }
  std::unordered_map<int, std::size_t> part_of_root;
  std::vector<NarrowPart> parts;
  std::vector<std::vector<int>> members;
  for (std::size_t v = 0; v < n; ++v) {
    const int vertex = static_cast<int>(v);
    if (!narrow(vertex)) continue;
    const auto [it, added] = part_of_root.try_emplace(sets.find(vertex), parts.size());
    if (added) {
      parts.emplace_back();
      members.emplace_back();
    }
    NarrowPart& part = parts[it->second];
    members[it->second].push_back(vertex);
    ++part.vertices;
    part.centre += mesh.positions[v];
    if (part.narrowest_vertex < 0 || girth[v] < part.girth_mm) {
      part.narrowest_vertex = vertex;
      part.narrowest_at = mesh.positions[v];
      part.girth_mm = girth[v];
    }
  }
  for (std::size_t i = 0; i < parts.size(); ++i) {
    NarrowPart& part = parts[i];
    part.centre /= part.vertices;
    for (const int v : members[i])
      part.extent_mm = std::max(part.extent_mm, (mesh.positions[at(v)] - part.centre).norm());
  }
  std::sort(parts.begin(), parts.end(), [](const NarrowPart& a, const NarrowPart& b) {
    return a.girth_mm != b.girth_mm ? a.girth_mm < b.girth_mm
                                    : a.narrowest_vertex < b.narrowest_vertex;
  });
  return parts;
}

}  // namespace planner
