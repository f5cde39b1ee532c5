#include "planner/cut/vanishing.hpp"

#include <algorithm>
#include <array>
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/successive_shortest_path_nonnegative_weights.hpp>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <numbers>
#include <stdexcept>
#include <string>

#include "planner/common/union_find.hpp"

namespace planner {

namespace {

// The angle cost of a vanishing corner: how much wider it is than its
// triangle's most acute corner, in steps of pi / kAngleSteps (0 to
// kAngleSteps).
constexpr int kAngleSteps = 10000;

// The flow network. Costs are whole numbers held in doubles: Boost's
// successive shortest paths adds Dijkstra's "infinite" distance to the
// potential of every node the residual graph no longer reaches, which is
// infinity for a double and an overflow for a signed integer. Every cost,
// potential and path length here is a whole number below 2^53, so the
// double arithmetic is exact (checked where the scale is chosen).
using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
using Arc = Traits::edge_descriptor;
using FlowGraph = boost::adjacency_list<
    boost::vecS, boost::vecS, boost::directedS, boost::no_property,
    boost::property<
        boost::edge_capacity_t, int,
        boost::property<boost::edge_residual_capacity_t, int,
                        boost::property<boost::edge_reverse_t, Arc,
                                        boost::property<boost::edge_weight_t, double>>>>>;

class FlowNetwork {
 public:
  explicit FlowNetwork(int nodes) : graph_(at(nodes)) {}

  // An arc and its residual twin (capacity 0, opposite cost).
  Arc add_arc(int from, int to, int capacity, double cost) {
    const Arc arc = boost::add_edge(at(from), at(to), graph_).first;
    const Arc twin = boost::add_edge(at(to), at(from), graph_).first;
    boost::put(boost::edge_capacity, graph_, arc, capacity);
    boost::put(boost::edge_capacity, graph_, twin, 0);
    boost::put(boost::edge_weight, graph_, arc, cost);
    boost::put(boost::edge_weight, graph_, twin, -cost);
    boost::put(boost::edge_reverse, graph_, arc, twin);
    boost::put(boost::edge_reverse, graph_, twin, arc);
    return arc;
  }

  // Sends as much flow as the arcs allow from source to sink at least cost
  // (all costs must be non-negative).
  void solve(int source, int sink) {
    boost::successive_shortest_path_nonnegative_weights(graph_, at(source), at(sink));
  }

  int flow(Arc arc) const {
    return boost::get(boost::edge_capacity, graph_, arc) -
           boost::get(boost::edge_residual_capacity, graph_, arc);
  }

 private:
  FlowGraph graph_;
};

// Per vertex: all face corners around it (quads' and triangles').
std::vector<int> corners_around(const HalfedgeMesh& q) {
  std::vector<int> corners(at(q.num_vertices()), 0);
  for (int h = 0; h < q.num_halfedges(); ++h) ++corners[at(q.from(h))];
  return corners;
}

// Per triangle corner, its angle cost (see kAngleSteps).
std::array<int, 3> angle_costs(const HalfedgeMesh& q, int f) {
  std::array<double, 3> angle{};
  for (int i = 0; i < 3; ++i) angle[at(i)] = q.corner_angle(q.face_start(f) + i);
  const double smallest = *std::min_element(angle.begin(), angle.end());
  std::array<int, 3> cost{};
  for (int i = 0; i < 3; ++i) {
    cost[at(i)] =
        static_cast<int>(std::lround((angle[at(i)] - smallest) / std::numbers::pi * kAngleSteps));
  }
  return cost;
}

// The vanishing corners of one group of triangles (no vertex of theirs is
// a corner of a triangle outside it), written into `vanishing`.
//
// The network: source -> each triangle (capacity 1) -> each of its three
// corner vertices (capacity 1) -> sink. A vertex's misfit with k of its
// corners vanishing is |n - k - 4| for an interior vertex with n corners,
// convex in k: its marginal changes are -1 while n - k >= 4 and +1 after.
// So the vertex reaches the sink through an arc of cost -1 per unit and
// capacity clamp(n - 4, 0, t), then one of cost +1 for the rest of its t
// triangle corners; a boundary vertex through one arc of cost 0. Every
// triangle sends exactly one unit through exactly one vertex-to-sink arc, so
// adding 1 to those costs adds the same constant to every assignment and
// makes all costs non-negative, as successive shortest paths needs.
//
// Main and angle costs in one number: main * scale + angle, with
// scale = kAngleSteps * t + 1 for the group's t triangles. The angle costs
// of an assignment sum to between 0 and kAngleSteps * t < scale. Two
// assignments whose misfits differ differ by at least 1 in main, so their
// totals differ by at least scale - kAngleSteps * t >= 1 in favour of the
// smaller misfit, whatever their angles: the least total has the least
// misfit, and among those the least angle cost.
void solve_group(const HalfedgeMesh& q, const std::vector<int>& triangles,
                 const std::vector<int>& corners, std::vector<int>& vanishing) {
  const int t = static_cast<int>(triangles.size());
  const double scale = static_cast<double>(kAngleSteps) * t + 1.0;
  std::vector<int> local(at(q.num_vertices()), -1);
  std::vector<int> vertices;
  for (int f : triangles) {
    for (int i = 0; i < 3; ++i) {
      const int v = q.from(q.face_start(f) + i);
      if (local[at(v)] < 0) {
        local[at(v)] = static_cast<int>(vertices.size());
        vertices.push_back(v);
      }
    }
  }
  std::vector<int> triangle_corners(vertices.size(), 0);
  for (int f : triangles) {
    for (int i = 0; i < 3; ++i) ++triangle_corners[at(local[at(q.from(q.face_start(f) + i))])];
  }

  const int source = 0, sink = 1, first_triangle = 2, first_vertex = 2 + t;
  const int nodes = first_vertex + static_cast<int>(vertices.size());
  // No arc costs more than 2 * scale, so no simple path, potential or
  // reduced cost reaches 6 * nodes * scale: below 2^53 all are exact.
  if (6.0 * nodes * scale >= 9007199254740992.0) {
    throw std::logic_error("optimal_vanishing_corners: " + std::to_string(t) +
                           " triangles sharing vertices are too many for exact costs");
  }
  FlowNetwork network(nodes);
  std::vector<std::array<Arc, 3>> corner_arcs(at(t));
  for (int k = 0; k < t; ++k) {
    const int f = triangles[at(k)];
    network.add_arc(source, first_triangle + k, 1, 0.0);
    const std::array<int, 3> angle = angle_costs(q, f);
    for (int i = 0; i < 3; ++i) {
      const int v = q.from(q.face_start(f) + i);
      corner_arcs[at(k)][at(i)] =
          network.add_arc(first_triangle + k, first_vertex + local[at(v)], 1, angle[at(i)]);
    }
  }
  for (std::size_t j = 0; j < vertices.size(); ++j) {
    const int v = vertices[j];
    const int node = first_vertex + static_cast<int>(j);
    const int available = triangle_corners[j];
    if (q.is_boundary_vertex(v)) {
      network.add_arc(node, sink, available, scale);
      continue;
    }
    const int fewer = std::clamp(corners[at(v)] - 4, 0, available);
    if (fewer > 0) network.add_arc(node, sink, fewer, 0.0);
    if (available > fewer) network.add_arc(node, sink, available - fewer, 2.0 * scale);
  }
  network.solve(source, sink);

  for (int k = 0; k < t; ++k) {
    int chosen = -1;
    for (int i = 0; i < 3; ++i) {
      if (network.flow(corner_arcs[at(k)][at(i)]) == 1) chosen = i;
    }
    if (chosen < 0) {
      throw std::logic_error("optimal_vanishing_corners: face " + std::to_string(triangles[at(k)]) +
                             " got no vanishing corner");
    }
    vanishing[at(triangles[at(k)])] = chosen;
  }
}

// Singular vertices where the misfit allows fewer (step 3 of the contract).
//
// Moving vanishing corners along a chain of triangles t1 .. tk, where t1
// vanishes at a, t(i+1) at the corner ti moves to, and tk moves to b, gives
// a one corner more and b one fewer and leaves every other vertex's count as
// it was. Such a chain is kept when it leaves the misfit as it is and
// lowers the number of singular vertices: e.g. two vertices of 3 corners
// become one of 4 and one of 2. Breadth-first from each a in turn, the
// first b found that gains, until a sweep over every a finds none.
void reduce_singular(const HalfedgeMesh& q, const std::vector<int>& corners,
                     std::vector<int>& vanishing) {
  const int nv = q.num_vertices();
  std::vector<int> count = corners;
  std::vector<std::vector<int>> vanishing_at(at(nv));  // triangles vanishing at each vertex
  for (int f = 0; f < q.num_faces(); ++f) {
    if (vanishing[at(f)] < 0) continue;
    const int v = q.from(q.face_start(f) + vanishing[at(f)]);
    --count[at(v)];
    vanishing_at[at(v)].push_back(f);
  }
  auto misfit = [&](int v, int c) { return q.is_boundary_vertex(v) ? 0 : std::abs(c - 4); };
  auto singular = [&](int v, int c) { return q.is_boundary_vertex(v) ? 0 : (c % 4 != 0 ? 1 : 0); };
  // What a vertex's count changing by `step` does to the misfit and to the
  // number of singular vertices.
  auto change = [&](int v, int step) {
    const int c = count[at(v)];
    return std::array<int, 2>{misfit(v, c + step) - misfit(v, c),
                              singular(v, c + step) - singular(v, c)};
  };

  struct Step {
    int from = -1;      // the vertex the chain came from
    int triangle = -1;  // the triangle that moves its vanishing corner off `from`
    int corner = -1;    // to this corner of it
  };
  std::vector<Step> reached(at(nv));
  std::vector<int> seen(at(nv), 0);  // the last search that reached each vertex
  int search = 0;
  bool moved = true;
  while (moved) {
    moved = false;
    for (int a = 0; a < nv; ++a) {
      if (q.is_boundary_vertex(a) || vanishing_at[at(a)].empty()) continue;
      const std::array<int, 2> gain_a = change(a, +1);
      ++search;
      std::deque<int> queue{a};
      seen[at(a)] = search;
      int found = -1;
      while (!queue.empty() && found < 0) {
        const int u = queue.front();
        queue.pop_front();
        for (int f : vanishing_at[at(u)]) {
          for (int i = 0; i < 3 && found < 0; ++i) {
            const int w = q.from(q.face_start(f) + i);
            if (seen[at(w)] == search) continue;
            seen[at(w)] = search;
            reached[at(w)] = {u, f, i};
            const std::array<int, 2> gain_b = change(w, -1);
            if (gain_a[0] + gain_b[0] == 0 && gain_a[1] + gain_b[1] < 0) found = w;
            queue.push_back(w);
          }
          if (found >= 0) break;
        }
      }
      if (found < 0) continue;
      ++count[at(a)];
      --count[at(found)];
      for (int w = found; w != a; w = reached[at(w)].from) {
        const Step& s = reached[at(w)];
        auto& list = vanishing_at[at(s.from)];
        list.erase(std::find(list.begin(), list.end(), s.triangle));
        vanishing_at[at(w)].push_back(s.triangle);
        vanishing[at(s.triangle)] = s.corner;
      }
      moved = true;
    }
  }
}

}  // namespace

std::vector<int> optimal_vanishing_corners(const HalfedgeMesh& q) {
  const int nf = q.num_faces();
  std::vector<int> vanishing(at(nf), -1);
  // Groups of triangles joined by shared vertices: each vertex's misfit
  // depends on its own group only, so each group is solved on its own.
  UnionFind groups(at(nf));
  std::vector<int> triangle_at(at(q.num_vertices()), -1);  // a triangle with a corner there
  for (int f = 0; f < nf; ++f) {
    if (q.degree(f) != 3) continue;
    for (int i = 0; i < 3; ++i) {
      const int v = q.from(q.face_start(f) + i);
      if (triangle_at[at(v)] < 0) {
        triangle_at[at(v)] = f;
      } else {
        groups.unite(f, triangle_at[at(v)]);
      }
    }
  }
  std::vector<std::vector<int>> members(at(nf));
  for (int f = 0; f < nf; ++f) {
    if (q.degree(f) == 3) members[at(groups.find(f))].push_back(f);
  }
  const std::vector<int> corners = corners_around(q);
  for (const std::vector<int>& triangles : members) {
    if (!triangles.empty()) solve_group(q, triangles, corners, vanishing);
  }
  reduce_singular(q, corners, vanishing);
  return vanishing;
}

int corner_misfit(const HalfedgeMesh& q, const std::vector<int>& vanishing_corner) {
  std::vector<int> count = corners_around(q);
  for (int f = 0; f < q.num_faces(); ++f) {
    if (vanishing_corner[at(f)] >= 0)
      --count[at(q.from(q.face_start(f) + vanishing_corner[at(f)]))];
  }
  int misfit = 0;
  for (int v = 0; v < q.num_vertices(); ++v) {
    if (!q.is_boundary_vertex(v)) misfit += std::abs(count[at(v)] - 4);
  }
  return misfit;
}

}  // namespace planner
