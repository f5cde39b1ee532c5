#include "planner/wearability/linking.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <functional>
#include <unordered_map>

#include "planner/common/union_find.hpp"
#include "planner/mesh/soup.hpp"
#include "planner/wearability/wearability.hpp"

namespace planner {

using cloth::Vec3;

std::vector<std::vector<int>> homology_cycles(int vertex_count,
                                              const std::vector<std::vector<int>>& faces,
                                              int max_loops) {
  struct Edge {
    int a = 0, b = 0;
    std::vector<int> faces;
    bool tree = false;
  };
  std::vector<Edge> edges;
  std::unordered_map<std::uint64_t, int> edge_of;
  std::vector<std::vector<std::pair<int, int>>> around(static_cast<std::size_t>(vertex_count));
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& face = faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      if (a == b) continue;
      const auto [lo, hi] = undirected_edge(a, b);
      const auto [it, inserted] = edge_of.emplace(pair_key(lo, hi), static_cast<int>(edges.size()));
      if (inserted) {
        edges.push_back({a, b, {}, false});
        around[static_cast<std::size_t>(a)].emplace_back(b, it->second);
        around[static_cast<std::size_t>(b)].emplace_back(a, it->second);
      }
      auto& incident = edges[static_cast<std::size_t>(it->second)].faces;
      if (incident.empty() || incident.back() != static_cast<int>(f))
        incident.push_back(static_cast<int>(f));
    }
  }
  // A breadth-first tree per component keeps the cycles short.
  std::vector<int> parent(static_cast<std::size_t>(vertex_count), -1);
  std::vector<int> depth(static_cast<std::size_t>(vertex_count), -1);
  for (int root = 0; root < vertex_count; ++root) {
    if (depth[static_cast<std::size_t>(root)] >= 0 ||
        around[static_cast<std::size_t>(root)].empty()) {
      continue;
    }
    depth[static_cast<std::size_t>(root)] = 0;
    std::deque<int> queue{root};
    while (!queue.empty()) {
      const int v = queue.front();
      queue.pop_front();
      for (const auto& [w, e] : around[static_cast<std::size_t>(v)]) {
        if (depth[static_cast<std::size_t>(w)] >= 0) continue;
        depth[static_cast<std::size_t>(w)] = depth[static_cast<std::size_t>(v)] + 1;
        parent[static_cast<std::size_t>(w)] = v;
        edges[static_cast<std::size_t>(e)].tree = true;
        queue.push_back(w);
      }
    }
  }
  // The cotree: faces joined across edges outside the tree, the boundary
  // one more face (index faces.size()) joined through its edges.
  const int outside = static_cast<int>(faces.size());
  UnionFind dual(faces.size() + 1);
  std::vector<int> left;
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const Edge& edge = edges[e];
    if (edge.tree) continue;
    int f = -1, g = -1;
    if (edge.faces.size() == 2) {
      f = edge.faces[0];
      g = edge.faces[1];
    } else if (edge.faces.size() == 1) {
      f = edge.faces[0];
      g = outside;
    }
    if (f >= 0 && dual.find(f) != dual.find(g)) {
      dual.unite(f, g);
    } else {
      left.push_back(static_cast<int>(e));
    }
  }
  std::vector<std::vector<int>> cycles;
  for (const int e : left) {
    if (static_cast<int>(cycles.size()) >= max_loops) break;
    int u = edges[static_cast<std::size_t>(e)].a, v = edges[static_cast<std::size_t>(e)].b;
    // u → … → the common ancestor → … → v, closed by the edge v-u.
    std::vector<int> up, down;
    while (u != v) {
      if (depth[static_cast<std::size_t>(u)] >= depth[static_cast<std::size_t>(v)]) {
        up.push_back(u);
        u = parent[static_cast<std::size_t>(u)];
      } else {
        down.push_back(v);
        v = parent[static_cast<std::size_t>(v)];
      }
    }
    up.push_back(u);
    up.insert(up.end(), down.rbegin(), down.rend());
    cycles.push_back(std::move(up));
  }
  return cycles;
}

std::optional<int> linking_number(const Loop& a, const Loop& b, const Vec3& view) {
  const Vec3 d = view.normalized();
  const Vec3 helper = std::abs(d.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = d.cross(helper).normalized();
  const Vec3 e2 = d.cross(e1);
  struct Point {
    double x, y, z;
  };
  auto project = [&](const Loop& loop) {
    std::vector<Point> points;
    points.reserve(loop.size());
    for (const Vec3& p : loop) points.push_back({p.dot(e1), p.dot(e2), p.dot(d)});
    return points;
  };
  const std::vector<Point> pa = project(a), pb = project(b);
  const std::size_t na = pa.size(), nb = pb.size();
  if (na < 3 || nb < 3) return 0;
  constexpr double kEnd = 1e-9;  // a crossing this near a vertex is degenerate
  int count = 0;
  for (std::size_t i = 0; i < na; ++i) {
    const Point& p = pa[i];
    const Point& p2 = pa[(i + 1) % na];
    const double rx = p2.x - p.x, ry = p2.y - p.y;
    const double ax0 = std::min(p.x, p2.x), ax1 = std::max(p.x, p2.x);
    const double ay0 = std::min(p.y, p2.y), ay1 = std::max(p.y, p2.y);
    for (std::size_t j = 0; j < nb; ++j) {
      const Point& q = pb[j];
      const Point& q2 = pb[(j + 1) % nb];
      if (std::max(q.x, q2.x) < ax0 || std::min(q.x, q2.x) > ax1 || std::max(q.y, q2.y) < ay0 ||
          std::min(q.y, q2.y) > ay1) {
        continue;
      }
      const double sx = q2.x - q.x, sy = q2.y - q.y;
      const double denom = rx * sy - ry * sx;
      const double scale = std::hypot(rx, ry) * std::hypot(sx, sy);
      const double qx = q.x - p.x, qy = q.y - p.y;
      if (std::abs(denom) <= 1e-12 * scale) {
        // Parallel in the projection: degenerate only when they overlap.
        if (std::abs(qx * ry - qy * rx) <= 1e-12 * scale + 1e-300) return std::nullopt;
        continue;
      }
      const double t = (qx * sy - qy * sx) / denom;
      const double u = (qx * ry - qy * rx) / denom;
      if (t < -kEnd || t > 1 + kEnd || u < -kEnd || u > 1 + kEnd) continue;
      if (t < kEnd || t > 1 - kEnd || u < kEnd || u > 1 - kEnd) return std::nullopt;
      const double za = p.z + t * (p2.z - p.z);
      const double zb = q.z + u * (q2.z - q.z);
      if (za == zb) return std::nullopt;  // the curves meet
      if (za > zb) count += denom > 0 ? 1 : -1;
    }
  }
  return count;
}

namespace {

Loop loop_of(const std::vector<Vec3>& positions, const std::vector<int>& cycle) {
  Loop loop;
  loop.reserve(cycle.size());
  for (const int v : cycle) loop.push_back(positions[static_cast<std::size_t>(v)]);
  return loop;
}

// Two generic directions: a linking number counts only when both give it.
const Vec3 kViews[2] = {Vec3(0.2673, 0.5345, 0.8018), Vec3(-0.6509, 0.2427, 0.7193)};

}  // namespace

LinkingTest::LinkingTest(const cloth::SignedDistanceField& wearer, int max_loops)
    : wearer_(&wearer), max_loops_(max_loops) {
  std::vector<Vec3> positions = wearer.mesh().vertices();
  std::vector<std::vector<int>> faces;
  faces.reserve(wearer.mesh().triangles().size());
  for (const auto& t : wearer.mesh().triangles()) faces.push_back({t[0], t[1], t[2]});
  // A mesh read as a triangle soup has its corners apart: weld them, or it
  // has no cycles at all.
  weld_vertices(positions, faces, 1e-9 * std::max(wearer.scale(), 1e-300));
  for (const auto& cycle : homology_cycles(static_cast<int>(positions.size()), faces, max_loops)) {
    loops_.push_back(loop_of(positions, cycle));
  }
}

std::optional<Loop> LinkingTest::outside_curve(const Loop& loop) const {
  const double spacing = wearer_->cell_size();
  const double target = 0.5 * spacing;
  // `point` moved out along the field's gradient to half a cell outside;
  // nothing when it lies deeper inside than `deepest`.
  auto pushed = [&](Vec3 point, double deepest) -> std::optional<Vec3> {
    Vec3 gradient;
    double value = wearer_->value_and_gradient(point, gradient);
    if (-value > deepest) return std::nullopt;
    for (int k = 0; k < 8 && value < target; ++k) {
      point += (target - value) * gradient;
      value = wearer_->value_and_gradient(point, gradient);
    }
    if (value <= 0) return std::nullopt;
    return point;
  };
  Loop curve;
  // Samples a quarter of a cell apart along the chord from `p` to `q`.
  auto chord_outside = [&](const Vec3& p, const Vec3& q) {
    const int samples = 1 + static_cast<int>(std::ceil((q - p).norm() / (0.25 * spacing)));
    for (int s = 1; s < samples; ++s) {
      if (wearer_->value(p + (q - p) * (static_cast<double>(s) / samples)) <= 0) return false;
    }
    return true;
  };
  // Appends the way from `p` (the curve's last point) to `q`: the chord
  // when it stays outside, else the ways to and from its middle, pushed out.
  // A curve that needs more points than `most` is given up.
  const std::size_t most = 16 * loop.size() + 256;
  std::function<bool(Vec3, Vec3, double, int)> run_to = [&](Vec3 p, Vec3 q, double deepest,
                                                            int levels) {
    if (curve.size() > most) return false;
    if (chord_outside(p, q)) {
      curve.push_back(q);
      return true;
    }
    if (levels == 0) return false;
    const auto out = pushed(0.5 * (p + q), deepest);
    return out && run_to(p, *out, deepest, levels - 1) && run_to(*out, q, deepest, levels - 1);
  };
  std::vector<Vec3> corners;
  for (const Vec3& p : loop) {
    const auto out = pushed(p, 0.0);
    if (!out) return std::nullopt;
    corners.push_back(*out);
  }
  curve.push_back(corners.front());
  for (std::size_t i = 0; i < corners.size(); ++i) {
    // A chord across a curved surface sags at most a quarter of its length
    // into it; one deeper in passes through a thin part of the wearer.
    const Vec3& p = loop[i];
    const Vec3& q = loop[(i + 1) % loop.size()];
    if (!run_to(curve.back(), corners[(i + 1) % corners.size()], 0.25 * (q - p).norm(), 12)) {
      return std::nullopt;
    }
  }
  curve.pop_back();  // the first corner again
  return curve;
}

std::optional<LinkingTest::Linked> LinkingTest::linked(const cloth::PolygonMesh& garment) const {
  if (loops_.empty()) return std::nullopt;
  const auto cycles =
      homology_cycles(static_cast<int>(garment.positions.size()), garment.faces, max_loops_);
  for (const auto& cycle : cycles) {
    const auto curve = outside_curve(loop_of(garment.positions, cycle));
    if (!curve) continue;
    for (const Loop& wearer_loop : loops_) {
      const auto first = linking_number(*curve, wearer_loop, kViews[0]);
      if (!first || *first == 0) continue;
      const auto second = linking_number(*curve, wearer_loop, kViews[1]);
      if (second && *second == *first) {
        return Linked{*first};
      }
    }
  }
  return std::nullopt;
}

}  // namespace planner
