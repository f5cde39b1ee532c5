#include "planner/proxy/field_proxy.hpp"

#include <lemon/list_graph.h>
#include <lemon/network_simplex.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include "planner/common/index.hpp"
#include "planner/mesh/soup.hpp"
#include "planner/proxy/cross_field.hpp"
#include "planner/proxy/remesh.hpp"
#include "simulators/cloth/parallel.hpp"

namespace planner {

namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

std::uint64_t edge_key(int a, int b) {
  const auto [lo, hi] = undirected_edge(a, b);
  return pair_key(lo, hi);
}

// The smallest corner of triangle a, b, c, radians.
double smallest_corner(const Vec3& a, const Vec3& b, const Vec3& c) {
  return std::min(
      {angle_between(b - a, c - a), angle_between(c - b, a - b), angle_between(a - c, b - c)});
}

// Triangles and the two faces of every edge (-1 where there is one), kept
// up to date through flips.
class FlipMesh {
 public:
  explicit FlipMesh(PolygonMesh& mesh) : mesh_(mesh), valence_(mesh.positions.size(), 0) {
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      if (mesh.faces[f].size() != 3)
        throw std::logic_error("equalize_valences: face " + std::to_string(f) +
                               " is not a triangle");
      for (int i = 0; i < 3; ++i) {
        const std::uint64_t key = edge_key(corner(f, i), corner(f, i + 1));
        auto [it, inserted] = faces_.try_emplace(key, std::array<int, 2>{static_cast<int>(f), -1});
        if (!inserted) it->second[1] = static_cast<int>(f);
      }
    }
    boundary_.assign(mesh.positions.size(), false);
    for (const auto& [key, faces] : faces_) {
      const int a = static_cast<int>(key >> 32);
      const int b = static_cast<int>(key & 0xffffffffU);
      ++valence_[at(a)];
      ++valence_[at(b)];
      if (faces[1] < 0) boundary_[at(a)] = boundary_[at(b)] = true;
    }
  }

  // Flips the edge of `key` when the rules of equalize_valences allow it.
  bool try_flip(std::uint64_t key, double bend, double min_corner) {
    const auto it = faces_.find(key);
    if (it == faces_.end() || it->second[1] < 0) return false;
    const int f1 = it->second[0];
    const int f2 = it->second[1];
    // f1 holds p -> q, f2 holds q -> p; c and d are across.
    int i1 = 0;
    while (edge_key(corner(f1, i1), corner(f1, i1 + 1)) != key) ++i1;
    const int p = corner(f1, i1), q = corner(f1, i1 + 1), c = corner(f1, i1 + 2);
    int i2 = 0;
    while (corner(f2, i2) != q) ++i2;
    if (corner(f2, i2 + 1) != p) return false;  // inconsistent orientation
    const int d = corner(f2, i2 + 2);
    if (c == d || faces_.count(edge_key(c, d)) || valence_[at(p)] <= 3 || valence_[at(q)] <= 3)
      return false;
    const int before = deviation(p, 0) + deviation(q, 0) + deviation(c, 0) + deviation(d, 0);
    const int after = deviation(p, -1) + deviation(q, -1) + deviation(c, 1) + deviation(d, 1);
    if (after >= before) return false;
    const Vec3& P = mesh_.positions[at(p)];
    const Vec3& Q = mesh_.positions[at(q)];
    const Vec3& C = mesh_.positions[at(c)];
    const Vec3& D = mesh_.positions[at(d)];
    const Vec3 old_normal = (Q - P).cross(C - P).normalized() + (P - Q).cross(D - Q).normalized();
    const Vec3 n1 = (D - P).cross(C - P);
    const Vec3 n2 = (Q - D).cross(C - D);
    if (n1.norm() <= 0.0 || n2.norm() <= 0.0 || n1.dot(old_normal) <= 0.0 ||
        n2.dot(old_normal) <= 0.0 || angle_between(n1, n2) > bend ||
        smallest_corner(P, D, C) < min_corner || smallest_corner(D, Q, C) < min_corner)
      return false;
    mesh_.faces[at(f1)] = {p, d, c};
    mesh_.faces[at(f2)] = {d, q, c};
    faces_.erase(it);
    faces_[edge_key(c, d)] = {f1, f2};
    replace(edge_key(p, d), f2, f1);
    replace(edge_key(q, c), f1, f2);
    --valence_[at(p)];
    --valence_[at(q)];
    ++valence_[at(c)];
    ++valence_[at(d)];
    return true;
  }

  std::vector<std::uint64_t> edges() const {
    std::vector<std::uint64_t> keys;
    keys.reserve(faces_.size());
    for (const auto& entry : faces_) keys.push_back(entry.first);
    std::sort(keys.begin(), keys.end());
    return keys;
  }

 private:
  int corner(std::size_t f, int i) const { return mesh_.faces[f][at(i % 3)]; }
  int corner(int f, int i) const { return corner(at(f), i); }

  // Squared distance of v's valence, changed by `change`, from its ideal.
  int deviation(int v, int change) const {
    const int ideal = boundary_[at(v)] ? 4 : 6;
    const int off = valence_[at(v)] + change - ideal;
    return off * off;
  }

  void replace(std::uint64_t key, int from, int to) {
    auto& faces = faces_.at(key);
    for (int& f : faces) {
      if (f == from) f = to;
    }
  }

  PolygonMesh& mesh_;
  std::vector<int> valence_;
  std::vector<bool> boundary_;
  std::unordered_map<std::uint64_t, std::array<int, 2>> faces_;
};

// The share of w, projected on the plane of normal n, that misses the
// nearest direction of the cross (d, n x d): 0 along it, 1 at 45 degrees.
double cross_miss(const Vec3& w, const Vec3& d, const Vec3& n) {
  const Vec3 wp = w - n * n.dot(w);
  const double length = wp.norm();
  if (length <= 0.0) return 1.0;
  const double along = std::max(std::abs(wp.dot(d)), std::abs(wp.dot(n.cross(d)))) / length;
  return std::clamp((1.0 - along) / (1.0 - std::sqrt(0.5)), 0.0, 1.0);
}

}  // namespace

int equalize_valences(PolygonMesh& triangles, double bend_deg, double min_corner_deg) {
  FlipMesh mesh(triangles);
  int flips = 0;
  for (int sweep = 0; sweep < 100; ++sweep) {
    int made = 0;
    for (const std::uint64_t key : mesh.edges()) {
      made += mesh.try_flip(key, bend_deg * kDegree, min_corner_deg * kDegree) ? 1 : 0;
    }
    flips += made;
    if (made == 0) break;
  }
  return flips;
}

double vanishing_misalignment(const PolygonMesh& mesh, int f, int corner, const Vec3& direction) {
  const auto& face = mesh.faces[at(f)];
  const Vec3& a = mesh.positions[at(face[at(corner)])];
  const Vec3& b = mesh.positions[at(face[at((corner + 1) % 3)])];
  const Vec3& c = mesh.positions[at(face[at((corner + 2) % 3)])];
  Vec3 n = (b - a).cross(c - a);
  if (n.norm() <= 0.0) return 1.0;
  n.normalize();
  Vec3 d = direction - n * n.dot(direction);
  if (d.norm() <= 0.0) return 1.0;
  d.normalize();
  return 0.5 * (cross_miss(c - b, d, n) + cross_miss(0.5 * (b + c) - a, d, n));
}

namespace {

// Costs are scaled to integers: 100 per unit of the parameters.
constexpr long long kCostScale = 100;

// One min-cost flow of vanishing corners (field_proxy.hpp): `corner_cost`
// per face and corner (the alignment), `pair_penalty` per vertex a cost per
// quarter turn of index.
std::vector<int> solve_corner_flow(const HalfedgeMesh& q, const std::vector<int>& valence,
                                   const std::vector<int>& field_index,
                                   const std::vector<std::array<long long, 3>>& corner_cost,
                                   const FieldProxyParams& params,
                                   const std::vector<long long>& pair_penalty) {
  using Graph = lemon::ListDigraph;
  const int nf = q.num_faces();
  const int nv = q.num_vertices();
  Graph graph;
  std::vector<Graph::Node> face_node(at(nf)), vertex_node(at(nv));
  for (auto& n : face_node) n = graph.addNode();
  for (auto& n : vertex_node) n = graph.addNode();
  const Graph::Node sink = graph.addNode();
  Graph::ArcMap<long long> cost(graph);
  Graph::NodeMap<int> supply(graph, 0);
  std::vector<std::array<Graph::Arc, 3>> corner_arc(at(nf));
  for (int f = 0; f < nf; ++f) {
    supply[face_node[at(f)]] = 1;
    for (int i = 0; i < 3; ++i) {
      const int v = q.from(q.face_start(f) + i);
      const Graph::Arc arc = graph.addArc(face_node[at(f)], vertex_node[at(v)]);
      cost[arc] = corner_cost[at(f)][at(i)];
      corner_arc[at(f)][at(i)] = arc;
    }
  }
  supply[sink] = -nf;
  // Vertex v with x vanishing corners keeps c = valence - x corners; each
  // further unit is one arc to the sink costing the rise of the convex cost.
  for (int v = 0; v < nv; ++v) {
    const bool interior = !q.is_boundary_vertex(v);
    const int target = 4 - field_index[at(v)];
    auto vertex_cost = [&](int x) -> long long {
      if (!interior) return 0;
      const int c = valence[at(v)] - x;
      return kCostScale * (static_cast<long long>(params.misfit_cost) * std::abs(c - target) +
                           static_cast<long long>(params.singular_cost) * (c - 4) * (c - 4)) +
             pair_penalty[at(v)] * std::abs(c - 4);
    };
    for (int x = 1; x <= valence[at(v)]; ++x) {
      const Graph::Arc arc = graph.addArc(vertex_node[at(v)], sink);
      cost[arc] = vertex_cost(x) - vertex_cost(x - 1);
    }
  }
  lemon::NetworkSimplex<Graph, int, long long> flow(graph);
  flow.costMap(cost).supplyMap(supply).upperMap(Graph::ArcMap<int>(graph, 1));
  if (flow.run() != lemon::NetworkSimplex<Graph, int, long long>::OPTIMAL)
    throw std::logic_error("field_vanishing_corners: the corner flow has no solution");
  std::vector<int> vanishing(at(nf), -1);
  for (int f = 0; f < nf; ++f) {
    for (int i = 0; i < 3; ++i) {
      if (flow.flow(corner_arc[at(f)][at(i)]) > 0) vanishing[at(f)] = i;
    }
    if (vanishing[at(f)] < 0)
      throw std::logic_error("field_vanishing_corners: face " + std::to_string(f) +
                             " got no vanishing corner");
  }
  return vanishing;
}

// The index the vanishing corners leave at every vertex (0 on the boundary).
std::vector<int> corner_index(const HalfedgeMesh& q, const std::vector<int>& valence,
                              const std::vector<int>& vanishing) {
  std::vector<int> index(at(q.num_vertices()), 0);
  for (int v = 0; v < q.num_vertices(); ++v) {
    index[at(v)] = q.is_boundary_vertex(v) ? 0 : 4 - valence[at(v)];
  }
  for (int f = 0; f < q.num_faces(); ++f) {
    const int v = q.from(q.face_start(f) + vanishing[at(f)]);
    if (!q.is_boundary_vertex(v)) ++index[at(v)];
  }
  return index;
}

// The vertices within `rings` edges of v, v first.
std::vector<int> ball(const HalfedgeMesh& q, int v, int rings) {
  std::vector<int> found{v};
  std::unordered_map<int, int> depth{{v, 0}};
  for (std::size_t i = 0; i < found.size(); ++i) {
    const int u = found[i];
    const int next = depth[u] + 1;
    if (next > rings) continue;
    for (const int h : q.outgoing(u)) {
      if (depth.emplace(q.to(h), next).second) found.push_back(q.to(h));
    }
  }
  return found;
}

// Per vertex, whether it lies within `rings` edges of a +1 and a -1 vertex
// at most `rings` edges apart (pairs taken greedily in vertex order); empty
// when there is no such pair.
std::vector<bool> near_pairs(const HalfedgeMesh& q, const std::vector<int>& index, int rings) {
  std::vector<bool> near(at(q.num_vertices()), false);
  std::vector<bool> paired(at(q.num_vertices()), false);
  bool any = false;
  for (int v = 0; v < q.num_vertices(); ++v) {
    if (paired[at(v)] || std::abs(index[at(v)]) != 1) continue;
    for (const int w : ball(q, v, rings)) {
      if (paired[at(w)] || index[at(w)] != -index[at(v)]) continue;
      paired[at(v)] = paired[at(w)] = true;
      any = true;
      for (const int end : {v, w}) {
        for (const int u : ball(q, end, rings)) near[at(u)] = true;
      }
      break;
    }
  }
  return any ? near : std::vector<bool>{};
}

}  // namespace

std::vector<int> field_vanishing_corners(const PolygonMesh& triangles,
                                         const std::vector<int>& field_index,
                                         const std::vector<Vec3>& field_direction,
                                         const FieldProxyParams& params) {
  const HalfedgeMesh q(triangles);
  const int nf = q.num_faces();
  const int nv = q.num_vertices();
  if (field_index.size() != at(nv) || field_direction.size() != at(nf))
    throw std::logic_error("field_vanishing_corners: field does not match the mesh");
  std::vector<int> valence(at(nv), 0);
  std::vector<std::array<long long, 3>> corner_cost(at(nf));
  for (int f = 0; f < nf; ++f) {
    if (q.degree(f) != 3)
      throw std::logic_error("field_vanishing_corners: face " + std::to_string(f) +
                             " is not a triangle");
    for (int i = 0; i < 3; ++i) {
      ++valence[at(q.from(q.face_start(f) + i))];
      corner_cost[at(f)][at(i)] =
          std::llround(static_cast<double>(kCostScale * params.alignment_cost) *
                       vanishing_misalignment(triangles, f, i, field_direction[at(f)]));
    }
  }
  std::vector<long long> pair_penalty(at(nv), 0);
  auto solve = [&] {
    return solve_corner_flow(q, valence, field_index, corner_cost, params, pair_penalty);
  };
  std::vector<int> vanishing = solve();
  // A +1/-1 pair within pair_rings edges that the alignment kept is two
  // ends of cut-arcs the surface does not need: every vertex within
  // pair_rings of it costs more to be singular, so the pair can neither stay
  // nor step a few edges apart, and the flow runs again, until no such pair
  // is left or the rounds are spent.
  for (int round = 0; round < params.pair_rounds; ++round) {
    const std::vector<bool> near =
        near_pairs(q, corner_index(q, valence, vanishing), params.pair_rings);
    if (near.empty()) break;
    for (int v = 0; v < nv; ++v) {
      if (near[at(v)]) pair_penalty[at(v)] += kCostScale * params.pair_cost;
    }
    vanishing = solve();
  }
  return vanishing;
}

namespace {

// One proxy at one target edge: steps 1-4 of docs/cutting.md, "The
// field-guided proxy".
FieldProxy proxy_at(const PolygonMesh& triangles, double edge_mm, const FieldProxyParams& params) {
  FieldProxy result;
  result.edge_mm = edge_mm;
  result.mesh = resample(triangles, edge_mm);
  result.valence_flips =
      equalize_valences(result.mesh, params.flip_bend_deg, params.min_corner_deg);
  CrossFieldParams field_params;
  field_params.edge_mm = 0.0;  // on the triangles as they are
  const CrossField field = smoothest_cross_field(result.mesh, field_params);
  if (field.surface.faces != result.mesh.faces)
    throw std::logic_error("field_guided_proxy: the field's triangles are not the proxy's");
  result.field_singularities = field_singularities(field).count;
  result.vanishing_corner =
      field_vanishing_corners(result.mesh, field.index, field.direction, params);
  const HalfedgeMesh q(result.mesh);
  std::vector<int> corners(result.mesh.positions.size(), 0);
  double alignment = 0.0;
  for (int f = 0; f < q.num_faces(); ++f) {
    for (int i = 0; i < 3; ++i) {
      if (i != result.vanishing_corner[at(f)]) ++corners[at(q.from(q.face_start(f) + i))];
    }
    alignment += vanishing_misalignment(result.mesh, f, result.vanishing_corner[at(f)],
                                        field.direction[at(f)]);
  }
  for (int v = 0; v < q.num_vertices(); ++v) {
    if (q.is_boundary_vertex(v)) continue;
    result.misfit += std::abs(corners[at(v)] - (4 - field.index[at(v)]));
    if (corners[at(v)] % 4 != 0) ++result.singular_vertices;
  }
  result.mean_alignment = q.num_faces() > 0 ? alignment / q.num_faces() : 0.0;
  return result;
}

}  // namespace

FieldProxy field_guided_proxy(const PolygonMesh& surface, const FieldProxyParams& params) {
  const PolygonMesh triangles = fan_triangulated(surface);
  std::vector<double> edges{params.edge_mm};
  for (double factor : params.edge_factors) {
    // A target of no length would subdivide without end.
    if (!(factor > 0.0))
      throw std::invalid_argument("field_guided_proxy: edge factors must be positive");
    edges.push_back(factor * params.edge_mm);
  }
  // Each candidate on whichever thread comes free; the choice reads them in
  // order, so it does not depend on the threads.
  std::vector<std::optional<FieldProxy>> made(edges.size());
  cloth::parallel_tasks(static_cast<int>(edges.size()), params.threads,
                        [&](int i) { made[at(i)] = proxy_at(triangles, edges[at(i)], params); });
  FieldProxy best = std::move(*made.front());
  for (std::size_t i = 1; i < made.size(); ++i) {
    if (made[i]->singular_vertices < best.singular_vertices) best = std::move(*made[i]);
  }
  best.candidates = static_cast<int>(edges.size());
  return best;
}

}  // namespace planner
