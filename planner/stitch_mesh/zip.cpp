// Step 4 of the stitch mesher (stitch_mesher.hpp), §6.3: the faces between a
// strip's bottom and top chains.
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner::stitch_meshing {

void StripMesher::add_face(std::vector<int> vertices, std::vector<EdgeRole> roles,
                           std::vector<std::int32_t> arcs) {
  StitchFace face;
  face.vertices.assign(vertices.begin(), vertices.end());
  face.roles = std::move(roles);
  face.arcs = std::move(arcs);
  const std::optional<FaceType> type = classify_roles(face.roles);
  if (!type) ++stats_.invalid_faces;
  face.type = type.value_or(FaceType::Knit);
  for (std::size_t i = 0; i < face.vertices.size(); ++i) {
    if (face.roles[i] == EdgeRole::CourseOut) {
      face_below_[key(static_cast<int>(face.vertices[(i + 1) % face.vertices.size()]),
                      static_cast<int>(face.vertices[i]))] = mesh_.faces.size();
    }
  }
  if (face.type == FaceType::Increase || face.type == FaceType::Decrease) {
    // Remember the pentagon's top sides, as the row above walks them.
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (face.roles[i] == EdgeRole::CourseOut) {
        shaped_below_.insert(
            key(static_cast<int>(face.vertices[(i + 1) % n]), static_cast<int>(face.vertices[i])));
      }
    }
  }
  mesh_.faces.push_back(std::move(face));
}

std::int32_t StripMesher::wale_arc(const Chain& chain) const {
  std::vector<int> all;
  double total = 0;
  for (const Run& r : chain.runs) {
    for (int h : r.halfedges) {
      all.push_back(h);
      total += slices_.length(h);
    }
  }
  double walked = 0;
  for (int h : all) {
    walked += slices_.length(h);
    if (walked >= 0.5 * total) return arc_of(h);
  }
  return all.empty() ? kNoArc : arc_of(all.back());
}

std::vector<std::pair<int, int>> StripMesher::zip_steps(const std::vector<int>& l,
                                                        const std::vector<int>& t, int i0, int j0,
                                                        int i1, int j1, bool left_boundary,
                                                        bool right_boundary) const {
  const int na = i1 - i0;
  const int nb = j1 - j0;
  std::vector<std::pair<int, int>> steps;
  if (na > 2 * nb || nb > 2 * na) {
    const int faces = std::min(na, nb);
    for (int f = 0; f < faces; ++f) {
      const int cb = (f + 1) * na / faces - f * na / faces;
      const int ct = (f + 1) * nb / faces - f * nb / faces;
      steps.push_back({cb, ct});
    }
    return steps;
  }
  const double inf = std::numeric_limits<double>::infinity();
  const int width = nb + 1;
  // State: wale side (i, j) reached by move m (0 knit, 1 decrease, 2 increase).
  auto index = [&](int i, int j, int m) { return at(((i * width) + j) * 3 + m); };
  std::vector<double> cost(at((na + 1) * width * 3), inf);
  std::vector<std::int8_t> came(at((na + 1) * width * 3), -1);
  auto wale_cost = [&](int i, int j) {
    const double len =
        (mesh_.positions[at(l[at(i0 + i)])] - mesh_.positions[at(t[at(j0 + j)])]).norm();
    // A wale side more than kLengthTolerance (15%) off its target counts
    // against the mesh's sizes: one outside costs outside_cost more than its
    // squared error.
    return length_cost((len - params_.wale_mm) / params_.wale_mm, params_.outside_cost);
  };
  // Fig. 7 rules of thumb as costs (docs/stitch-mesh.md): no increase or
  // decrease at a row's end on the boundary, none on a bottom side made by
  // an increase or decrease of the row below, and no increase beside a
  // decrease.
  auto shaped = [&](int i, int count) {
    for (int k = 0; k < count; ++k) {
      if (shaped_below_.count(key(l[at(i0 + i + k)], l[at(i0 + i + k + 1)])) != 0) return true;
    }
    return false;
  };
  const std::array<std::pair<int, int>, 3> moves{{{1, 1}, {2, 1}, {1, 2}}};
  const double pentagon =
      params_.pentagon_cost;  // prefer knit stitches where rows keep their length
  const double rule = params_.stability_cost;
  cost[index(0, 0, 0)] = wale_cost(0, 0);
  for (int i = 0; i <= na; ++i) {
    for (int j = 0; j <= nb; ++j) {
      for (int last = 0; last < 3; ++last) {
        const double here = cost[index(i, j, last)];
        if (here == inf) continue;
        for (std::size_t m = 0; m < moves.size(); ++m) {
          const int ni = i + moves[m].first;
          const int nj = j + moves[m].second;
          if (ni > na || nj > nb) continue;
          // Stay where the end can still be reached.
          const int ra = na - ni;
          const int rb = nb - nj;
          if (ra > 2 * rb || rb > 2 * ra) continue;
          double c = here + wale_cost(ni, nj);
          if (m != 0) {
            c += pentagon;
            if ((i == 0 && j == 0 && left_boundary) || (ni == na && nj == nb && right_boundary)) {
              c += rule;  // rule 1: shaping at the edge of the fabric
            }
            if (shaped(i, moves[m].first)) c += rule;  // rule 2: stacked shaping
            if (last != 0 && last != static_cast<int>(m))
              c += rule;  // rule 3: increase by decrease
          }
          if (c < cost[index(ni, nj, static_cast<int>(m))]) {
            cost[index(ni, nj, static_cast<int>(m))] = c;
            came[index(ni, nj, static_cast<int>(m))] = static_cast<std::int8_t>(last);
          }
        }
      }
    }
  }
  int best = 0;
  for (int m = 1; m < 3; ++m) {
    if (cost[index(na, nb, m)] < cost[index(na, nb, best)]) best = m;
  }
  if (cost[index(na, nb, best)] == inf) {
    throw std::logic_error("stitch meshing: zip found no path although the chains allow one");
  }
  for (int i = na, j = nb, m = best; i > 0 || j > 0;) {
    const auto move = moves[at(m)];
    const int previous = came[index(i, j, m)];
    steps.push_back(move);
    i -= move.first;
    j -= move.second;
    m = previous;
  }
  std::reverse(steps.begin(), steps.end());
  return steps;
}

std::pair<bool, bool> end_triangles(int a, int b, bool left_shared, bool right_shared) {
  const bool room_for_both = a >= 2 && b >= 2;
  const bool left = left_shared && (room_for_both || !right_shared) && a >= 1 && b >= 1;
  const bool right = right_shared && (room_for_both || !left_shared) && a >= 1 && b >= 1 &&
                     !(left && (a < 2 || b < 2));
  return {left, right};
}

void StripMesher::zip_strip(const Chain& low, const Chain& high, const Chain* left_wale,
                            const Chain* right_wale, const std::vector<int>& low_counts,
                            const std::vector<int>& high_counts) {
  ZipSpan z;
  z.bottom = chain_vertices(low, low_counts, z.bottom_arcs);
  const bool left_shared = left_wale == nullptr;
  const bool right_shared = right_wale == nullptr;
  const int a = static_cast<int>(z.bottom.size()) - 1;
  const int b = std::accumulate(high_counts.begin(), high_counts.end(), 0);
  z.top_segments = b;
  const auto [left_triangle, right_triangle] = end_triangles(a, b, left_shared, right_shared);
  std::vector<bool> high_on_level;
  const std::vector<int> h = chain_vertices(high, high_counts, z.high_arcs, &high_on_level);
  z.top.assign(h.rbegin(), h.rend());
  const std::vector<int>& l = z.bottom;
  const std::vector<int>& t = z.top;
  if (left_shared != (t.front() == l.front()) || right_shared != (t.back() == l.back())) {
    throw std::logic_error("stitch meshing: chain ends disagree with the strip's sides");
  }
  if (left_shared && right_shared && a == 1 && b == 2 && high_on_level[0] != high_on_level[1]) {
    // One fixed bottom side, a top of a level-curve segment and a boundary
    // segment: the boundary segment is the wale side of a short-row triangle.
    const EdgeRole first = high_on_level[0] ? EdgeRole::CourseOut : EdgeRole::Wale;
    const EdgeRole second = high_on_level[1] ? EdgeRole::CourseOut : EdgeRole::Wale;
    add_face({l[0], l[1], t[1]}, {EdgeRole::CourseIn, first, second},
             {z.bottom_arcs[0], z.top_arc(1), z.top_arc(0)});
    return;
  }
  if (left_shared && right_shared && a == 1 && b == 1) {
    ++stats_.lenses_skipped;  // one edge below, one above, same ends: they are glued
    return;
  }
  using R = EdgeRole;
  z.i1 = a;
  z.j1 = b;
  z.left_arc = left_wale != nullptr ? wale_arc(*left_wale) : kNoArc;
  z.right_arc = right_wale != nullptr ? wale_arc(*right_wale) : kNoArc;
  if (left_triangle) {
    // §6.3 short row ending on the left: the strip narrows to a point.
    add_face({l[0], l[1], t[1]}, {R::CourseIn, R::Wale, R::CourseOut},
             {z.bottom_arcs[0], kNoArc, z.top_arc(0)});
    z.i0 = 1;
    z.j0 = 1;
    z.left_arc = kNoArc;
  }
  if (right_triangle) {
    add_face({l[at(a - 1)], l[at(a)], t[at(b - 1)]}, {R::CourseIn, R::CourseOut, R::Wale},
             {z.bottom_arcs[at(a - 1)], z.top_arc(b - 1), kNoArc});
    z.i1 = a - 1;
    z.j1 = b - 1;
    z.right_arc = kNoArc;
  }
  const int na = z.i1 - z.i0;
  const int nb = z.j1 - z.j0;
  if (na == 0 && nb == 0) return;
  if (na <= 0 || nb <= 0) {
    add_leftover_face(z);
    return;
  }
  add_zipped_faces(z, left_wale != nullptr && !left_wale->runs.empty(),
                   right_wale != nullptr && !right_wale->runs.empty());
}

void StripMesher::add_leftover_face(const ZipSpan& z) {
  using R = EdgeRole;
  const std::vector<int>& l = z.bottom;
  const std::vector<int>& t = z.top;
  std::vector<int> v;
  std::vector<R> roles;
  std::vector<std::int32_t> arcs;
  for (int i = z.i0; i < z.i1; ++i) {
    v.push_back(l[at(i)]);
    roles.push_back(R::CourseIn);
    arcs.push_back(z.bottom_arcs[at(i)]);
  }
  if (l[at(z.i1)] != t[at(z.j1)]) {
    v.push_back(l[at(z.i1)]);
    roles.push_back(R::Wale);
    arcs.push_back(z.right_arc);
  }
  for (int j = z.j1; j > z.j0; --j) {
    v.push_back(t[at(j)]);
    roles.push_back(R::CourseOut);
    arcs.push_back(z.top_arc(j - 1));
  }
  if (t[at(z.j0)] != l[at(z.i0)]) {
    v.push_back(t[at(z.j0)]);
    roles.push_back(R::Wale);
    arcs.push_back(z.left_arc);
  }
  add_face(std::move(v), std::move(roles), std::move(arcs));
}

void StripMesher::add_zipped_faces(const ZipSpan& z, bool left_boundary, bool right_boundary) {
  using R = EdgeRole;
  const std::vector<int>& l = z.bottom;
  const std::vector<int>& t = z.top;
  const std::vector<std::pair<int, int>> steps =
      zip_steps(l, t, z.i0, z.j0, z.i1, z.j1, left_boundary, right_boundary);
  int i = z.i0;
  int j = z.j0;
  for (std::size_t f = 0; f < steps.size(); ++f) {
    const int cb = steps[f].first;
    const int ct = steps[f].second;
    std::vector<int> v;
    std::vector<R> roles;
    std::vector<std::int32_t> arcs;
    for (int k = 0; k < cb; ++k) {
      v.push_back(l[at(i + k)]);
      roles.push_back(R::CourseIn);
      arcs.push_back(z.bottom_arcs[at(i + k)]);
    }
    v.push_back(l[at(i + cb)]);
    roles.push_back(R::Wale);
    arcs.push_back(f + 1 == steps.size() ? z.right_arc : kNoArc);
    for (int k = ct; k > 0; --k) {
      v.push_back(t[at(j + k)]);
      roles.push_back(R::CourseOut);
      arcs.push_back(z.top_arc(j + k - 1));
    }
    v.push_back(t[at(j)]);
    roles.push_back(R::Wale);
    arcs.push_back(f == 0 ? z.left_arc : kNoArc);
    add_face(std::move(v), std::move(roles), std::move(arcs));
    i += cb;
    j += ct;
  }
}

}  // namespace planner::stitch_meshing
