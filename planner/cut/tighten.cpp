#include "planner/cut/tighten.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>
#include <utility>

#include "planner/common/index.hpp"
#include "planner/common/union_find.hpp"

namespace planner {

namespace {

// A turn of the cut costs up to this many mean edge lengths of Q
// (Tightener::turn). Over the 28 closed shared meshes at 100 mm, 1 against
// none: arcs 370 -> 360, mean chord / length 0.779 -> 0.787, cut length
// 13.0 -> 12.8 m; 2 straightens a little more (0.791) but splits camelhead's
// cut into more arcs (7 -> 10).
constexpr double kTurn = 1.0;

struct Path {
  std::vector<int> vertices;
  std::vector<int> edges;
  double cost = 0.0;  // the sum of its edges' and its turns' costs
};

class Tightener {
 public:
  Tightener(const HalfedgeMesh& q, const FieldLabels& labels, std::vector<bool>& cut_edge)
      : q_(q), labels_(labels), cut_edge_(cut_edge), degree_(at(q.num_vertices()), 0) {
    for (int e = 0; e < q_.num_edges(); ++e) {
      if (cut_edge_[at(e)]) add(e, 1);
    }
    // An edge costs its length, times 1 + kAcross sin²(2θ) for the angle θ
    // it makes with the labels' directions in its faces: along a course or
    // a wale it costs its length, at 45° four times that, so the new paths
    // run along the rows and wales of §4.1 where that is nearly as short.
    constexpr double kAcross = 3.0;
    cost_.assign(at(q_.num_edges()), 0.0);
    // Per face: its course direction, from the sides the labels put along it.
    std::vector<Vec3> axis(at(q_.num_faces()), Vec3::Zero());
    for (int f = 0; f < q_.num_faces(); ++f) {
      for (int i = 0; i < q_.degree(f); ++i) {
        const int h = q_.face_start(f) + i;
        const int d = halfedge_direction(q_, labels_, 0, h);
        const Vec3 v = q_.position(q_.to(h)) - q_.position(q_.from(h));
        if (d == 0) axis[at(f)] += v;
        if (d == 2) axis[at(f)] -= v;
      }
    }
    for (int e = 0; e < q_.num_edges(); ++e) {
      const int h = q_.edge_halfedge(e);
      const Vec3 v = q_.position(q_.to(h)) - q_.position(q_.from(h));
      double mis = 0.0;
      int n = 0;
      for (int x : {h, q_.twin(h)}) {
        if (x < 0) continue;
        const Vec3& a = axis[at(q_.face(x))];
        const double cos_sin = v.dot(a) * v.cross(a).norm();  // |v|²|a|² cos θ sin θ
        const double scale = v.squaredNorm() * a.squaredNorm();
        if (scale > 0.0) mis += 4.0 * cos_sin * cos_sin / (scale * scale);
        ++n;
      }
      cost_[at(e)] = v.norm() * (1.0 + kAcross * (n > 0 ? mis / n : 0.0));
      mean_edge_ += v.norm();
    }
    if (q_.num_edges() > 0) mean_edge_ /= q_.num_edges();
  }

  // The cost of a turn at v on the way u -> v -> w: kTurn mean edge
  // lengths times (θ / π)² for the angle θ between the two edges, so a cut
  // that goes straight on costs nothing more, a right angle a quarter of
  // that, one that doubles back all of it (docs/cutting.md, "Tightening").
  double turn(int u, int v, int w) const {
    const Vec3 a = q_.position(v) - q_.position(u);
    const Vec3 b = q_.position(w) - q_.position(v);
    const double na = a.norm();
    const double nb = b.norm();
    if (na <= 0.0 || nb <= 0.0) return 0.0;
    const double theta = std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0));
    const double x = theta / std::numbers::pi;
    return kTurn * mean_edge_ * x * x;
  }

  // A path's cost: its edges' and its turns'.
  double path_cost(const Path& path) const {
    double cost = 0.0;
    for (int e : path.edges) cost += cost_[at(e)];
    for (std::size_t i = 1; i + 1 < path.vertices.size(); ++i)
      cost += turn(path.vertices[i - 1], path.vertices[i], path.vertices[i + 1]);
    if (path.vertices.size() > 2 && path.vertices.front() == path.vertices.back())
      cost +=
          turn(path.vertices[path.vertices.size() - 2], path.vertices.front(), path.vertices[1]);
    return cost;
  }

  // One pass over the cut's paths between nodes, longest first; returns how
  // many were replaced by shorter ones.
  int pass() {
    std::vector<Path> paths = node_paths();
    std::sort(paths.begin(), paths.end(),
              [](const Path& a, const Path& b) { return a.cost > b.cost; });
    int replaced = 0;
    for (const Path& path : paths) replaced += replace(path) ? 1 : 0;
    return replaced;
  }

  // Branch nodes of the cut at vertices that need not be on it are ends of
  // arcs the surface does not ask for, and where they sit decides how long
  // the paths between them are. Each is moved, in turn, onto the far end of
  // one of its paths (the arc between them goes) when the cut grows by at
  // most `allowance` times that path's cost, or else to a vertex a
  // quarter or half along one of its paths, or one edge along, when the cut
  // gets shorter. Returns how many moved.
  int move_branches(double allowance) {
    int moved = 0;
    for (int x = 0; x < q_.num_vertices(); ++x) {
      if (degree_[at(x)] < 3 || q_.is_boundary_vertex(x) || singular(x)) continue;
      std::vector<Path> star;
      for (Path& path : node_paths()) {
        const bool starts = path.vertices.front() == x;
        const bool ends = path.vertices.back() == x;
        if (ends && !starts) {
          std::reverse(path.vertices.begin(), path.vertices.end());
          std::reverse(path.edges.begin(), path.edges.end());
        }
        if (starts || ends) star.push_back(std::move(path));
      }
      if (star.size() < 2) continue;
      std::vector<std::size_t> order(star.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
      std::sort(order.begin(), order.end(),
                [&](std::size_t a, std::size_t b) { return star[a].cost < star[b].cost; });
      bool done = false;
      for (std::size_t i : order) {  // onto a neighbouring node
        const Path& path = star[i];
        if (path.vertices.back() == x) continue;
        done = relocate(x, star, i, path.vertices.size() - 1, allowance * path.cost);
        if (done) break;
      }
      for (std::size_t i = 0; !done && i < star.size(); ++i) {  // along a path
        const std::size_t last = star[i].vertices.size() - 1;
        for (const std::size_t k : {last / 2, last / 4, std::size_t{1}}) {
          if (k == 0 || k >= last) continue;
          done = relocate(x, star, i, k, -1e-9 * star[i].cost);
          if (done) break;
        }
      }
      moved += done ? 1 : 0;
    }
    return moved;
  }

 private:
  bool singular(int v) const { return is_singular(labels_, v); }
  // A vertex the cut must keep: on the mesh boundary, singular, or where
  // other than two cut edges meet.
  bool node(int v) const { return q_.is_boundary_vertex(v) || singular(v) || degree_[at(v)] != 2; }
  // A vertex a new path may run through: interior, not singular, off the cut.
  bool free_vertex(int v) const {
    return !q_.is_boundary_vertex(v) && !singular(v) && degree_[at(v)] == 0;
  }

  void add(int e, int step) {
    cut_edge_[at(e)] = step > 0;
    const int h = q_.edge_halfedge(e);
    degree_[at(q_.from(h))] += step;
    degree_[at(q_.to(h))] += step;
  }

  // The cut split at its nodes into paths (a loop through no node starts and
  // ends at its first vertex).
  std::vector<Path> node_paths() const {
    std::vector<Path> paths;
    for (CutPath& stretch :
         split_cut(q_, cut_edge_, cut_edges_at(q_, cut_edge_), [&](int v) { return node(v); })) {
      Path path{std::move(stretch.vertices), std::move(stretch.edges), 0.0};
      path.cost = path_cost(path);
      paths.push_back(std::move(path));
    }
    return paths;
  }

  // Q cut along the cut edges, R: its vertices are classes of corners glued
  // across uncut edges, and each class on R's boundary knows its loop.
  struct Cutopen {
    UnionFind corners;
    std::vector<int> loop;  // per half-edge root: R's boundary loop, -1 inside
    int pieces = 0;
    int vertices = 0;
  };
  Cutopen cut_open() const {
    const int nh = q_.num_halfedges();
    Cutopen r{UnionFind(at(nh)), std::vector<int>(at(nh), -1)};
    UnionFind faces(at(q_.num_faces()));
    auto on_boundary = [&](int h) { return q_.twin(h) < 0 || cut_edge_[at(q_.edge(h))]; };
    for (int h = 0; h < nh; ++h) {
      const int t = q_.twin(h);
      if (t < h || on_boundary(h)) continue;
      r.corners.unite(h, q_.next(t));
      r.corners.unite(q_.next(h), t);
      faces.unite(q_.face(h), q_.face(t));
    }
    for (int h = 0; h < nh; ++h) r.vertices += r.corners.find(h) == h ? 1 : 0;
    for (int f = 0; f < q_.num_faces(); ++f) r.pieces += faces.find(f) == f ? 1 : 0;
    // R's boundary loops, walked half-edge by half-edge inside R's faces.
    std::vector<bool> seen(at(nh), false);
    int loops = 0;
    for (int h = 0; h < nh; ++h) {
      if (!on_boundary(h) || seen[at(h)]) continue;
      for (int x = h; !seen[at(x)];) {
        seen[at(x)] = true;
        r.loop[at(r.corners.find(x))] = loops;
        int y = q_.next(x);
        while (!on_boundary(y)) y = q_.next(q_.twin(y));
        x = y;
      }
      ++loops;
    }
    return r;
  }

  // Q cut along the cut edges is one piece with Euler characteristic 1: a
  // disc. On a closed Q a cut of one edge would leave a disc bounded by two
  // copies of one edge, which is no mesh: the cut keeps two at least.
  bool is_disc() const {
    const Cutopen r = cut_open();
    int cut_edges = 0;
    for (int e = 0; e < q_.num_edges(); ++e) cut_edges += cut_edge_[at(e)] ? 1 : 0;
    if (cut_edges == 1) return false;
    return r.pieces == 1 && r.vertices - (q_.num_edges() + cut_edges) + q_.num_faces() == 1;
  }

  // The shortest path from a corner class of a to one of b over uncut
  // interior edges through free vertices, such that cutting R along it keeps
  // a disc: its ends lie on two different boundary loops of R (R is an
  // annulus), or one end is inside R (the path is a slit). Empty when there
  // is none.
  Path shortest(int a, int b, Cutopen& r) const {
    Path best;
    best.cost = std::numeric_limits<double>::infinity();
    std::vector<int> sources;
    for (int h : q_.outgoing(a)) {
      const int c = r.corners.find(h);
      if (std::find(sources.begin(), sources.end(), c) == sources.end()) sources.push_back(c);
    }
    const int nh = q_.num_halfedges();
    for (int source : sources) {
      // Dijkstra over half-edges (the one a vertex was reached by), so a
      // turn's cost is known at each step.
      std::vector<double> dist(at(nh), std::numeric_limits<double>::infinity());
      std::vector<int> via(at(nh), -1);  // the half-edge before
      using Item = std::pair<double, int>;
      std::priority_queue<Item, std::vector<Item>, std::greater<>> heap;
      // Out of vertex v, reached by half-edge `in` (-1 at a) at cost d.
      auto relax = [&](int v, int in, double d) {
        for (int h : q_.outgoing(v)) {
          if (v == a && r.corners.find(h) != source) continue;
          if (q_.twin(h) < 0 || cut_edge_[at(q_.edge(h))]) continue;
          const int w = q_.to(h);
          const double nd = d + cost_[at(q_.edge(h))] + (in >= 0 ? turn(q_.from(in), v, w) : 0.0);
          if (w == b) {
            const int target = r.corners.find(q_.twin(h));
            const int from_loop = r.loop[at(source)];
            const int to_loop = r.loop[at(target)];
            if (from_loop >= 0 && to_loop >= 0 && from_loop == to_loop) continue;
            if (nd < best.cost) {
              best.cost = nd;
              best.edges.assign(1, q_.edge(h));
              best.vertices.assign(1, b);
              for (int x = in; x >= 0; x = via[at(x)]) {
                best.vertices.push_back(q_.to(x));
                best.edges.push_back(q_.edge(x));
              }
              best.vertices.push_back(a);
              std::reverse(best.vertices.begin(), best.vertices.end());
              std::reverse(best.edges.begin(), best.edges.end());
            }
            continue;
          }
          if (!free_vertex(w) || nd >= dist[at(h)]) continue;
          dist[at(h)] = nd;
          via[at(h)] = in;
          heap.push({nd, h});
        }
      };
      relax(a, -1, 0.0);
      while (!heap.empty()) {
        const auto [d, h] = heap.top();
        heap.pop();
        if (d > dist[at(h)] || d >= best.cost) continue;
        relax(q_.to(h), h, d);
      }
    }
    if (best.edges.empty()) best.cost = 0.0;
    return best;
  }

  double cut_cost() const {
    double cost = 0.0;
    // The turns where the cut runs through a vertex (two cut edges at it).
    for (int v = 0; v < q_.num_vertices(); ++v) {
      if (degree_[at(v)] != 2) continue;
      std::array<int, 2> ends{-1, -1};
      int k = 0;
      for (int h : q_.outgoing(v)) {
        if (cut_edge_[at(q_.edge(h))] && k < 2) ends[at(k++)] = q_.to(h);
      }
      if (k == 2) cost += turn(ends[0], v, ends[1]);
    }
    for (int e = 0; e < q_.num_edges(); ++e) {
      if (cut_edge_[at(e)]) cost += cost_[at(e)];
    }
    return cost;
  }

  // Moves branch node x to t = star[i].vertices[k]. Every other path of the
  // star is replaced by the shortest one from its far end to t that keeps a
  // disc (a loop at t where it was a loop at x or already ended at t); then
  // what is left of star[i] between x and t goes, and a loop through x
  // becomes the shortest loop through t. Kept when the cut grows by at most
  // `growth` in cost (negative: it must fall by that much).
  bool relocate(int x, const std::vector<Path>& star, std::size_t i, std::size_t k, double growth) {
    const std::vector<bool> saved_cut = cut_edge_;
    const std::vector<int> saved_degree = degree_;
    const double before = cut_cost();
    const Path& chosen = star[i];
    const int t = chosen.vertices[k];
    const bool chosen_loop = chosen.vertices.back() == x;
    auto reroute = [&](int from, int to) {
      Cutopen r = cut_open();
      const Path path = shortest(from, to, r);
      for (int e : path.edges) add(e, 1);
      return !path.edges.empty();
    };
    auto restore = [&] {
      cut_edge_ = saved_cut;
      degree_ = saved_degree;
      return false;
    };
    for (std::size_t j = 0; j < star.size(); ++j) {
      if (j == i) continue;
      for (int e : star[j].edges) {
        if (!cut_edge_[at(e)]) return restore();
        add(e, -1);
      }
      const int far = star[j].vertices.back();
      if (!reroute(far == x ? t : far, t)) return restore();
    }
    if (chosen_loop) {
      for (int e : chosen.edges) add(e, -1);
      if (!reroute(t, t)) return restore();
    } else {
      for (std::size_t e = 0; e < k; ++e) add(chosen.edges[e], -1);
    }
    if (is_disc() && cut_cost() <= before + growth) return true;
    return restore();
  }

  // Replaces `path` by the shortest one between its ends that keeps Q cut
  // into a disc, when that is shorter.
  bool replace(const Path& path) {
    for (int e : path.edges) {
      if (!cut_edge_[at(e)]) return false;  // an earlier replacement took it
    }
    const int a = path.vertices.front();
    const int b = path.vertices.back();
    for (int e : path.edges) add(e, -1);
    Cutopen r = cut_open();
    const Path shorter = shortest(a, b, r);
    if (!shorter.edges.empty() && shorter.cost < path.cost * (1.0 - 1e-6)) {
      for (int e : shorter.edges) add(e, 1);
      if (is_disc()) return true;
      for (int e : shorter.edges) add(e, -1);
    }
    for (int e : path.edges) add(e, 1);
    return false;
  }

  const HalfedgeMesh& q_;
  const FieldLabels& labels_;
  std::vector<bool>& cut_edge_;
  std::vector<int> degree_;   // per vertex: cut edges at it
  std::vector<double> cost_;  // per edge: its length, more across the labels
  double mean_edge_ = 0.0;
};

}  // namespace

int tighten_cut(const HalfedgeMesh& q, const FieldLabels& labels, std::vector<bool>& cut_edge) {
  Tightener tightener(q, labels, cut_edge);
  int changes = 0;
  // A branch node moves onto a neighbouring node when the cut grows by at
  // most the cost of the path between them (docs/cutting.md).
  constexpr double kMergeAllowance = 1.0;
  for (int round = 0; round < 8; ++round) {
    int now = tightener.pass();
    now += tightener.move_branches(kMergeAllowance);
    changes += now;
    if (now == 0) break;
  }
  return changes;
}

}  // namespace planner
