// Step 2 of the stitch mesher (stitch_mesher.hpp), before the slicing: the
// row time's critical points that would give strips no zip can fill well,
// interior extrema (levelled) and saddles (held on a level).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <unordered_set>
#include <utility>
#include <vector>

#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner::stitch_meshing {

std::vector<std::vector<int>> vertex_neighbours(const std::vector<Triangle>& tris, std::size_t n) {
  std::vector<std::vector<int>> adjacent(n);
  std::unordered_set<std::uint64_t> seen;
  for (const Triangle& tri : tris) {
    for (int i = 0; i < 3; ++i) {
      const int a = tri.v[at(i)];
      const int b = tri.v[at((i + 1) % 3)];
      if (!seen.insert(key(std::min(a, b), std::max(a, b))).second) continue;
      adjacent[at(a)].push_back(b);
      adjacent[at(b)].push_back(a);
    }
  }
  return adjacent;
}

std::vector<bool> on_disc_boundary(const LabelledDisc& disc) {
  std::unordered_set<std::uint64_t> sides;
  for (const std::vector<int>& face : disc.faces) {
    for (std::size_t i = 0; i < face.size(); ++i)
      sides.insert(key(face[i], face[(i + 1) % face.size()]));
  }
  std::vector<bool> on(disc.positions.size(), false);
  for (const std::vector<int>& face : disc.faces) {
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i];
      const int b = face[(i + 1) % face.size()];
      if (sides.count(key(b, a))) continue;
      on[at(a)] = on[at(b)] = true;
    }
  }
  return on;
}

int level_interior_extrema(const LabelledDisc& disc, const std::vector<Triangle>& tris,
                           Eigen::VectorXd& t) {
  const auto n = static_cast<std::size_t>(t.size());
  const std::vector<std::vector<int>> adjacent = vertex_neighbours(tris, n);
  std::vector<int> boundary;
  {
    const std::vector<bool> on = on_disc_boundary(disc);
    for (std::size_t v = 0; v < n; ++v) {
      if (on[v]) boundary.push_back(static_cast<int>(v));
    }
  }
  // One flood: `fill` raises pits (lowest first), otherwise peaks are cut
  // (highest first). Ties are taken by vertex index, so the result does not
  // depend on the heap's implementation.
  auto flood = [&](bool fill) {
    using Entry = std::pair<double, int>;
    auto later = [fill](const Entry& a, const Entry& b) {
      if (a.first != b.first) return fill ? a.first > b.first : a.first < b.first;
      return a.second > b.second;
    };
    std::priority_queue<Entry, std::vector<Entry>, decltype(later)> queue(later);
    std::vector<bool> closed(n, false);
    for (int v : boundary) {
      closed[at(v)] = true;
      queue.push({t[v], v});
    }
    int changed = 0;
    while (!queue.empty()) {
      const auto [value, v] = queue.top();
      queue.pop();
      for (int w : adjacent[at(v)]) {
        if (closed[at(w)]) continue;
        closed[at(w)] = true;
        if (fill ? t[w] < value : t[w] > value) {
          t[w] = value;
          ++changed;
        }
        queue.push({t[w], w});
      }
    }
    return changed;
  };
  const Eigen::VectorXd before = t;
  // Filling never lowers and cutting never raises a value, and both are
  // monotone, so the alternation converges (values are taken from a finite
  // set); the bound only guards against a bug.
  for (int round = 0; round < 1000; ++round) {
    const int raised = flood(true);
    const int lowered = flood(false);
    if (raised == 0 && lowered == 0) break;
    if (round == 999) throw std::logic_error("row time: levelling extrema does not converge");
  }
  int changed = 0;
  for (std::size_t v = 0; v < n; ++v)
    changed += t[static_cast<Eigen::Index>(v)] != before[static_cast<Eigen::Index>(v)] ? 1 : 0;
  return changed;
}

std::vector<int> pin_saddles(const LabelledDisc& disc, const std::vector<Triangle>& tris,
                             Eigen::VectorXd& rows, int bands, double inner_mm, double outer_mm,
                             const std::vector<bool>& candidates, int& pinned) {
  const auto n = static_cast<std::size_t>(rows.size());
  std::vector<int> pin(n, -1);
  pinned = 0;
  if (bands < 2 || !(outer_mm > inner_mm) || candidates.empty()) return pin;
  const std::vector<Vec3>& positions = disc.positions;
  std::vector<std::vector<std::pair<int, int>>> link(n);  // the side opposite v, per triangle
  for (const Triangle& tri : tris) {
    for (int i = 0; i < 3; ++i) {
      link[at(tri.v[at(i)])].push_back({tri.v[at((i + 1) % 3)], tri.v[at((i + 2) % 3)]});
    }
  }
  const std::vector<std::vector<int>> adjacent = vertex_neighbours(tris, n);
  const std::vector<bool> boundary = on_disc_boundary(disc);
  // Sign changes of the rows round v (ties broken by vertex index, as a
  // hair's shift would): 2 at a regular inner vertex, 0 or 1 on the
  // boundary; more at a saddle.
  auto above = [&](int a, int v) { return rows[a] != rows[v] ? rows[a] > rows[v] : a > v; };
  auto sign_changes = [&](int v) {
    int changes = 0;
    for (const auto& [a, b] : link[at(v)]) changes += above(a, v) != above(b, v) ? 1 : 0;
    return changes;
  };
  auto is_saddle = [&](int v) { return sign_changes(v) >= (boundary[at(v)] ? 2 : 4); };
  std::vector<double> dist(n, std::numeric_limits<double>::infinity());
  for (std::size_t v0 = 0; v0 < n; ++v0) {
    const int s = static_cast<int>(v0);
    const int k = static_cast<int>(std::lround(rows[s]));
    if (!candidates[v0] || k < 1 || k >= bands || !is_saddle(s)) continue;
    // Vertices within outer_mm along the edges; none held within inner_mm.
    std::vector<int> reached;
    using Entry = std::pair<double, int>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    dist[at(s)] = 0;
    queue.push({0.0, s});
    bool clear = true;
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > dist[at(v)]) continue;
      reached.push_back(v);
      if (pin[at(v)] >= 0 && d < inner_mm) clear = false;
      for (int w : adjacent[at(v)]) {
        const double e = d + (positions[at(w)] - positions[at(v)]).norm();
        if (e < outer_mm && e < dist[at(w)]) {
          dist[at(w)] = e;
          queue.push({e, w});
        }
      }
    }
    if (clear) {
      const double delta = k - rows[s];
      std::vector<double> before;
      for (int v : reached) {
        before.push_back(rows[v]);
        if (pin[at(v)] >= 0) continue;
        const double x = std::clamp((dist[at(v)] - inner_mm) / (outer_mm - inner_mm), 0.0, 1.0);
        rows[v] += delta * (1 - x * x * (3 - 2 * x));
      }
      rows[s] = k;
      pin[at(s)] = k;
      bool ok = true;
      for (int v : reached) {
        if (pin[at(v)] >= 0) {
          ok = ok && is_saddle(v);
          for (int w : adjacent[at(v)]) ok = ok && std::abs(rows[w] - pin[at(v)]) > 1e-6;
        }
        for (int w : adjacent[at(v)]) ok = ok && (boundary[at(w)] || sign_changes(w) > 0);
      }
      if (ok) {
        ++pinned;
      } else {
        pin[at(s)] = -1;
        for (std::size_t i = 0; i < reached.size(); ++i) rows[reached[i]] = before[i];
      }
    }
    for (int v : reached) dist[at(v)] = std::numeric_limits<double>::infinity();
  }
  return pin;
}

}  // namespace planner::stitch_meshing
