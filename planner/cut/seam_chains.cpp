#include "planner/cut/seam_chains.hpp"

#include <algorithm>
#include <map>
#include <tuple>

#include "planner/common/index.hpp"

namespace planner {

namespace {

// Arc ends are numbered 2 a (arc a's first vertex) and 2 a + 1 (its last).
int vertex_of(const std::vector<ArcEnds>& arcs, int end) {
  const ArcEnds& arc = arcs[at(end / 2)];
  return end % 2 == 0 ? arc.first : arc.last;
}

}  // namespace

std::vector<SeamChain> chain_arcs(const std::vector<ArcEnds>& arcs) {
  const int n = static_cast<int>(arcs.size());
  // The arc ends at every vertex; a vertex with exactly two, of two
  // different arcs with one label, joins them.
  std::map<int, std::vector<int>> ends_at;
  for (int end = 0; end < 2 * n; ++end) ends_at[vertex_of(arcs, end)].push_back(end);
  std::vector<int> partner(at(2 * n), -1);
  for (const auto& [vertex, ends] : ends_at) {
    if (ends.size() != 2) continue;
    const int a = ends[0] / 2, b = ends[1] / 2;
    if (a == b || arcs[at(a)].label != arcs[at(b)].label) continue;
    partner[at(ends[0])] = ends[1];
    partner[at(ends[1])] = ends[0];
  }

  std::vector<bool> taken(at(n), false);
  std::vector<SeamChain> seams;
  // Walks from arc `a`, entered at its end `entry` (0 first, 1 last), across
  // joined ends until an end with no partner or the arc it started from.
  auto walk = [&](int a, int entry) {
    SeamChain seam;
    seam.label = arcs[at(a)].label;
    const int start_vertex = vertex_of(arcs, 2 * a + entry);
    int exit_end = 2 * a + 1 - entry;
    for (;;) {
      taken[at(a)] = true;
      seam.arcs.push_back(a);
      seam.reversed.push_back(entry == 1);
      exit_end = 2 * a + 1 - entry;
      const int next = partner[at(exit_end)];
      if (next < 0 || taken[at(next / 2)]) break;
      a = next / 2;
      entry = next % 2;
    }
    seam.closed = vertex_of(arcs, exit_end) == start_vertex;
    seams.push_back(std::move(seam));
  };
  // Open seams first, each from its end with the smaller arc index: the
  // first arc met in index order with an end that joins nothing.
  for (int a = 0; a < n; ++a) {
    if (taken[at(a)]) continue;
    if (partner[at(2 * a)] < 0)
      walk(a, 0);
    else if (partner[at(2 * a + 1)] < 0)
      walk(a, 1);
  }
  // What is left are loops in which every end joins another arc.
  for (int a = 0; a < n; ++a) {
    if (!taken[at(a)]) walk(a, 0);
  }
  auto key = [](const SeamChain& s) {
    return std::make_tuple(s.label, *std::min_element(s.arcs.begin(), s.arcs.end()));
  };
  std::sort(seams.begin(), seams.end(),
            [&](const SeamChain& x, const SeamChain& y) { return key(x) < key(y); });
  return seams;
}

std::vector<int> seam_of_arc(const std::vector<SeamChain>& seams, std::size_t arc_count) {
  std::vector<int> seam(arc_count, -1);
  for (std::size_t s = 0; s < seams.size(); ++s) {
    for (const int a : seams[s].arcs) {
      if (a >= 0 && at(a) < arc_count) seam[at(a)] = static_cast<int>(s);
    }
  }
  return seam;
}

}  // namespace planner
