// The remesher's extraction (remesh.hpp, after Instant Meshes): samples whose
// lattice points coincide become one output vertex, samples one lattice
// step apart an output edge, and faces are traced around the edges in
// their angular order.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <tuple>

#include "planner/common/index.hpp"
#include "planner/common/union_find.hpp"
#include "planner/proxy/remesh.hpp"
#include "planner/proxy/remesh_internal.hpp"

namespace planner::remesh_detail {

namespace {

// The graph the extraction builds and then traces: its vertices are
// lattice points, its edges lattice steps.
struct LatticeGraph {
  std::vector<Vec3> position;
  std::vector<Vec3> normal;    // unit
  std::vector<Vec3> axis;      // the orientation field at the vertex: its angular reference
  std::vector<bool> boundary;  // made from a sample on the input's boundary
  std::vector<std::vector<int>> adjacent;
};

// The vertices of `fine` grouped into classes, root[v] naming v's class;
// classes are numbered in the order of their first vertex. A class sits at
// the mean of its vertices' positions, with the normalised sum of their
// normals and its first vertex's axis, on the boundary when one of its
// vertices is. Returns each vertex's class; `merged` gets the classes, with
// no adjacency yet.
std::vector<int> merge_classes(const LatticeGraph& fine, const std::vector<int>& root,
                               LatticeGraph& merged) {
  const std::size_t n = fine.position.size();
  std::vector<int> class_of_root(n, -1);
  std::vector<int> class_of(n, -1);
  std::vector<int> count;
  merged = LatticeGraph{};
  for (std::size_t v = 0; v < n; ++v) {
    int& c = class_of_root[at(root[v])];
    if (c < 0) {
      c = static_cast<int>(merged.position.size());
      merged.position.push_back(Vec3::Zero());
      merged.normal.push_back(Vec3::Zero());
      merged.axis.push_back(fine.axis[v]);
      merged.boundary.push_back(false);
      count.push_back(0);
    }
    class_of[v] = c;
    merged.position[at(c)] += fine.position[v];
    merged.normal[at(c)] += fine.normal[v];
    merged.boundary[at(c)] = merged.boundary[at(c)] || fine.boundary[v];
    ++count[at(c)];
  }
  for (std::size_t c = 0; c < merged.position.size(); ++c) {
    merged.position[c] /= count[c];
    merged.normal[c].normalize();
  }
  merged.adjacent.resize(merged.position.size());
  return class_of;
}

// Along every sample edge, the integer lattice offset between the lattice
// points of its two ends: ends at offset 0 are one output vertex
// (`same_point` joins them), ends one step apart make an output edge.
struct LatticeLinks {
  UnionFind same_point;
  std::vector<std::pair<int, int>> unit_edges;
};

LatticeLinks lattice_links(const HalfedgeMesh& mesh, const LatticeFields& fields, double s) {
  const std::vector<Vec3>& normals = fields.normal;
  const std::vector<Vec3>& q = fields.orientation;
  const std::vector<Vec3>& origin = fields.origin;
  LatticeLinks links{UnionFind(at(mesh.num_vertices())), {}};
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    const int i = mesh.from(h);
    const int j = mesh.to(h);
    if (mesh.twin(h) >= 0 && i > j) continue;
    const Vec3& ni = normals[at(i)];
    const Vec3& qi = q[at(i)];
    const Vec3 qj = closest_representative(q[at(j)], normals[at(j)], qi);
    const auto [a, b] =
        compatible_positions(mesh.position(i), ni, qi, origin[at(i)], mesh.position(j),
                             normals[at(j)], qj, origin[at(j)], s);
    const Vec3 ti = ni.cross(qi);
    const Vec3 tj = normals[at(j)].cross(qj);
    const long di0 = std::lround(qi.dot(a - origin[at(i)]) / s);
    const long di1 = std::lround(ti.dot(a - origin[at(i)]) / s);
    const long dj0 = std::lround(qj.dot(b - origin[at(j)]) / s);
    const long dj1 = std::lround(tj.dot(b - origin[at(j)]) / s);
    const long du = di0 - dj0;
    const long dv = di1 - dj1;
    const long manhattan = std::labs(du) + std::labs(dv);
    if (manhattan == 0)
      links.same_point.unite(i, j);
    else if (manhattan == 1)
      links.unit_edges.emplace_back(i, j);
  }
  return links;
}

// The output graph: one vertex per class of samples at one lattice point,
// at the mean of their lattice origins, an edge per pair of classes one
// lattice step apart.
LatticeGraph lattice_graph(const HalfedgeMesh& mesh, LatticeFields fields, double s) {
  LatticeLinks links = lattice_links(mesh, fields, s);
  const int nv = mesh.num_vertices();
  std::vector<int> root(at(nv));
  std::vector<bool> boundary(at(nv));
  for (int v = 0; v < nv; ++v) {
    root[at(v)] = links.same_point.find(v);
    boundary[at(v)] = mesh.is_boundary_vertex(v);
  }
  const LatticeGraph samples{std::move(fields.origin),
                             std::move(fields.normal),
                             std::move(fields.orientation),
                             std::move(boundary),
                             {}};
  LatticeGraph graph;
  const std::vector<int> cls = merge_classes(samples, root, graph);
  for (const auto& [i, j] : links.unit_edges) {
    const int a = cls[at(i)];
    const int b = cls[at(j)];
    if (a == b) continue;
    graph.adjacent[at(a)].push_back(b);
    graph.adjacent[at(b)].push_back(a);
  }
  for (auto& list : graph.adjacent) sort_unique(list);
  return graph;
}

// Lattice vertices joined by an edge shorter than `below` are one vertex
// (the extraction's rounding leaves such pairs where the position field
// bends, and they would become needle-thin faces). Pairs only: a vertex
// merged once is not merged again, so a row of short edges does not
// collapse into one point. Positions and normals are averaged; adjacency
// lists are renumbered, sorted and free of self-loops.
void merge_short_edges(double below, LatticeGraph& g) {
  const std::size_t n = g.position.size();
  std::vector<int> into(n, -1);
  std::vector<std::tuple<double, int, int>> short_edges;
  for (std::size_t a = 0; a < n; ++a) {
    for (int b : g.adjacent[a]) {
      const double length = (g.position[at(b)] - g.position[a]).norm();
      if (static_cast<int>(a) < b && length < below)
        short_edges.emplace_back(length, static_cast<int>(a), b);
    }
  }
  if (short_edges.empty()) return;
  std::sort(short_edges.begin(), short_edges.end());
  for (const auto& [length, a, b] : short_edges) {
    if (into[at(a)] >= 0 || into[at(b)] >= 0) continue;
    into[at(a)] = a;
    into[at(b)] = a;
  }
  std::vector<int> root(n);
  for (std::size_t v = 0; v < n; ++v) root[v] = into[v] >= 0 ? into[v] : static_cast<int>(v);
  LatticeGraph merged;
  const std::vector<int> index = merge_classes(g, root, merged);
  for (std::size_t v = 0; v < n; ++v) {
    for (int o : g.adjacent[v]) {
      if (index[v] != index[at(o)]) merged.adjacent[at(index[v])].push_back(index[at(o)]);
    }
  }
  for (auto& list : merged.adjacent) sort_unique(list);
  g = std::move(merged);
}

// Dangling edges bound no face: peel them off.
void peel_dangling_edges(LatticeGraph& g) {
  const int nc = static_cast<int>(g.position.size());
  for (bool changed = true; changed;) {
    changed = false;
    for (int c = 0; c < nc; ++c) {
      if (g.adjacent[at(c)].size() != 1) continue;
      const int other = g.adjacent[at(c)][0];
      g.adjacent[at(c)].clear();
      auto& list = g.adjacent[at(other)];
      list.erase(std::remove(list.begin(), list.end(), c), list.end());
      changed = true;
    }
  }
}

// Neighbours in counter-clockwise order around each vertex's normal,
// angles measured from its axis.
void sort_neighbours_by_angle(LatticeGraph& g) {
  for (std::size_t c = 0; c < g.position.size(); ++c) {
    const Vec3& n = g.normal[c];
    const Vec3 x = (g.axis[c] - n * n.dot(g.axis[c])).normalized();
    const Vec3 y = n.cross(x);
    auto angle = [&](int o) {
      const Vec3 d = g.position[at(o)] - g.position[c];
      return std::atan2(d.dot(y), d.dot(x));
    };
    std::sort(g.adjacent[c].begin(), g.adjacent[c].end(),
              [&](int a, int b) { return angle(a) < angle(b); });
  }
}

// A hole of an open surface is traced like a face along its rim; its
// centre lies in the opening, farther than 0.6 lattice steps `s` from
// every sample of the surface.
bool is_hole(const std::vector<int>& loop, const LatticeGraph& g, const HalfedgeMesh& samples,
             double s) {
  bool touches_boundary = false;
  Vec3 centre = Vec3::Zero();
  for (int v : loop) {
    touches_boundary = touches_boundary || g.boundary[at(v)];
    centre += g.position[at(v)];
  }
  if (!touches_boundary) return false;
  centre /= static_cast<double>(loop.size());
  double nearest = std::numeric_limits<double>::infinity();
  for (int v = 0; v < samples.num_vertices(); ++v)
    nearest = std::min(nearest, (samples.position(v) - centre).squaredNorm());
  return std::sqrt(nearest) > 0.6 * s;
}

// The walk that starts along a0 -> b0 and, arriving at b from a, leaves
// along the neighbour of b just clockwise of a; every step it takes is
// marked in `used`. Nothing when it has not closed after 64 steps.
std::optional<std::vector<int>> walk_face(const LatticeGraph& g, int a0, int b0,
                                          std::map<std::pair<int, int>, bool>& used) {
  std::vector<int> face;
  int a = a0;
  int b = b0;
  for (int steps = 0; steps < 64; ++steps) {
    used[{a, b}] = true;
    face.push_back(a);
    const auto& list = g.adjacent[at(b)];
    const auto it = std::find(list.begin(), list.end(), a);
    const std::size_t k = static_cast<std::size_t>(it - list.begin());
    const int next = list[(k + list.size() - 1) % list.size()];
    a = b;
    b = next;
    if (a == a0 && b == b0) return face;
  }
  return std::nullopt;
}

// A walk that meets a vertex twice runs round an island or along a bridge:
// its simple loops, without the two-corner spikes.
std::vector<std::vector<int>> simple_loops(const std::vector<int>& walk) {
  std::vector<std::vector<int>> loops;
  std::vector<int> stack;
  std::map<int, std::size_t> where;
  for (int v : walk) {
    auto found = where.find(v);
    if (found != where.end()) {
      std::vector<int> loop(stack.begin() + static_cast<std::ptrdiff_t>(found->second),
                            stack.end());
      for (std::size_t k = found->second + 1; k < stack.size(); ++k) where.erase(stack[k]);
      stack.resize(found->second + 1);
      if (loop.size() >= 3) loops.push_back(std::move(loop));
    } else {
      where[v] = stack.size();
      stack.push_back(v);
    }
  }
  if (stack.size() >= 3) loops.push_back(std::move(stack));
  return loops;
}

// The faces of the lattice graph: every directed edge not yet walked starts
// a walk; the simple loops of a closed walk are faces, except the holes of
// an open surface. Positions are the graph's, unused ones included.
PolygonMesh trace_faces(const LatticeGraph& g, const HalfedgeMesh& samples, double s) {
  std::map<std::pair<int, int>, bool> used;
  PolygonMesh out;
  out.positions = g.position;
  for (int a0 = 0; a0 < static_cast<int>(g.position.size()); ++a0) {
    for (int b0 : g.adjacent[at(a0)]) {
      if (used[{a0, b0}]) continue;
      const std::optional<std::vector<int>> walk = walk_face(g, a0, b0, used);
      if (!walk || walk->size() < 3) continue;
      for (auto& loop : simple_loops(*walk)) {
        if (!is_hole(loop, g, samples, s)) out.faces.push_back(std::move(loop));
      }
    }
  }
  return out;
}

}  // namespace

PolygonMesh extract_lattice(const HalfedgeMesh& samples, LatticeFields fields,
                            const RemeshParams& params) {
  const double s = params.edge_mm;
  LatticeGraph graph = lattice_graph(samples, std::move(fields), s);
  merge_short_edges(params.merge_below * s, graph);
  peel_dangling_edges(graph);
  sort_neighbours_by_angle(graph);
  return trace_faces(graph, samples, s);
}

}  // namespace planner::remesh_detail
