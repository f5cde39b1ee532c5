// Step 4 of the stitch mesher (stitch_mesher.hpp), §6.3: each strip brought
// to one bottom and one top chain with segment counts the zip can use, then
// zipped; strips around saddles are split, and rows below are given more
// stitches where the row above needs them.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner::stitch_meshing {

namespace {

// A saddle split (split_folds) takes a splitting edge up to this many wales
// longer to make strips whose bottom and top lengths differ by one unit of
// |ln(bottom / top)| less. 1 left the fans of `teddy-quad`; 2 and 4 gave the
// same stitch meshes on the 38 shared meshes (docs/stitch-mesh.md, "Saddle
// splits").
constexpr double kSplitBalance = 2.0;

int first_vertex(const BandSlices& slices, const Chain& c) {
  return slices.from(c.runs.front().halfedges.front());
}
int last_vertex(const BandSlices& slices, const Chain& c) {
  return slices.to(c.runs.back().halfedges.back());
}

// A loop of course chains, bottom and top alternating, each with the wale
// chain after it (empty where there is none).
struct FoldedLoop {
  std::vector<Chain> courses;
  std::vector<Chain> sides;    // side chain after each course chain
  std::vector<bool> has_side;  // a boundary side, or an edge made by an earlier split
};

// The loop as a FoldedLoop starting with a bottom chain; nullopt unless its
// course chains alternate, none is empty, no two wale chains are neighbours
// and there are m >= 2 pairs of them.
std::optional<FoldedLoop> alternating_chains(std::vector<Chain> loop) {
  while (loop.front().side != Side::Low) std::rotate(loop.begin(), loop.begin() + 1, loop.end());
  FoldedLoop f;
  for (Chain& c : loop) {
    if (c.side == Side::Wale) {
      if (f.courses.empty() || f.has_side.back()) return std::nullopt;
      f.sides.back() = std::move(c);
      f.has_side.back() = true;
    } else {
      if (!f.courses.empty() && f.courses.back().side == c.side) return std::nullopt;
      if (c.runs.empty()) return std::nullopt;
      f.courses.push_back(std::move(c));
      Chain none;
      none.side = Side::Wale;
      f.sides.push_back(std::move(none));
      f.has_side.push_back(false);
    }
  }
  const std::size_t n = f.courses.size();
  if (n < 4 || n % 2 != 0) return std::nullopt;
  return f;
}

// The course chain k after whose corner the splitting edge of split_folds
// starts (it ends at the corner after chain k + 2), or nullopt when no edge
// can be made.
std::optional<std::size_t> pick_fold_split(const FoldedLoop& f, const BandSlices& slices,
                                           const StitchMeshParams& params) {
  const std::vector<Chain>& courses = f.courses;
  const std::vector<Chain>& sides = f.sides;
  const std::size_t n = courses.size();
  // An edge of an earlier split cannot join a bottom chain.
  auto usable = [&](std::size_t k) { return !f.has_side[k] || !sides[k].runs.empty(); };
  // Corner after course chain k once its side chain has joined a bottom chain.
  auto corner = [&](std::size_t k) {
    if (courses[k].side == Side::Low) {
      return sides[k].runs.empty() ? last_vertex(slices, courses[k])
                                   : last_vertex(slices, sides[k]);
    }
    return sides[k].runs.empty() ? first_vertex(slices, courses[(k + 1) % n])
                                 : first_vertex(slices, sides[k]);
  };
  // Bottom and top lengths of the cut-off strip (chains k+1, k+2) and the rest.
  auto imbalance = [&](std::size_t k) {
    std::array<double, 4> length{};  // part bottom, part top, rest bottom, rest top
    for (std::size_t j = 0; j < n; ++j) {
      const bool in_part = j == (k + 1) % n || j == (k + 2) % n;
      const bool top = courses[j].side == Side::High;
      length[at((in_part ? 0 : 2) + (top ? 1 : 0))] += chain_length(courses[j]);
    }
    const double floor = 1e-3 * params.course_mm;
    double sum = 0;
    for (int i : {0, 2}) {
      sum +=
          std::abs(std::log(std::max(length[at(i)], floor) / std::max(length[at(i + 1)], floor)));
    }
    return sum;
  };
  std::size_t pick = 0;
  double least = std::numeric_limits<double>::infinity();
  bool found = false;
  for (std::size_t k = 0; k < n; ++k) {
    if (!usable(k) || !usable((k + 2) % n)) continue;
    found = true;
    const double cost = (slices.position(corner(k)) - slices.position(corner((k + 2) % n))).norm() +
                        kSplitBalance * params.wale_mm * imbalance(k);
    if (cost < least) {
      least = cost;
      pick = k;
    }
  }
  if (!found) return std::nullopt;
  return pick;
}

// Whether the zip can make only valid faces from a bottom chain of a and a
// top chain of b segments (after the end triangles of shared ends, neither
// more than twice the other).
bool zippable(int a, int b, bool left_shared, bool right_shared, const Chain& high,
              const std::vector<int>& high_counts) {
  if (left_shared && right_shared && a == 1 && b == 2 && high.runs.size() == 2 &&
      high_counts[0] == 1 && high.runs[0].level != high.runs[1].level) {
    return true;  // a short-row triangle with a boundary wale side
  }
  if (left_shared && right_shared && a == 1 && b == 1) return true;  // a lens
  const auto [left, right] = end_triangles(a, b, left_shared, right_shared);
  // A shared end without its triangle would give the face there a wale
  // side of no length.
  if ((left_shared && !left) || (right_shared && !right)) return false;
  const int na = a - left - right;
  const int nb = b - left - right;
  return (na == 0 && nb == 0) || (na > 0 && nb > 0 && na <= 2 * nb && nb <= 2 * na);
}

// Moves the longer boundary run at an end of the top chain (loop starts
// with its bottom chain) into the wale side beside it. False when neither
// end of the top chain is a boundary run or it has only one run.
bool boundary_end_to_side(std::vector<Chain>& loop) {
  std::size_t hi = 0;
  while (hi < loop.size() && loop[hi].side != Side::High) ++hi;
  if (hi == loop.size() || loop[hi].runs.size() < 2) return false;
  std::vector<Run>& runs = loop[hi].runs;
  const bool front = !runs.front().level;
  const bool back = !runs.back().level;
  if (!front && !back) return false;
  if (front && (!back || runs.front().length >= runs.back().length)) {
    Run run = std::move(runs.front());
    runs.erase(runs.begin());
    if (loop[hi - 1].side == Side::Wale) {
      loop[hi - 1].runs.push_back(std::move(run));
    } else {
      Chain side;
      side.side = Side::Wale;
      side.runs.push_back(std::move(run));
      loop.insert(loop.begin() + static_cast<std::ptrdiff_t>(hi), std::move(side));
    }
    return true;
  }
  Run run = std::move(runs.back());
  runs.pop_back();
  if (hi + 1 < loop.size() && loop[hi + 1].side == Side::Wale) {
    loop[hi + 1].runs.insert(loop[hi + 1].runs.begin(), std::move(run));
  } else {
    Chain side;
    side.side = Side::Wale;
    side.runs.push_back(std::move(run));
    loop.insert(loop.begin() + static_cast<std::ptrdiff_t>(hi) + 1, std::move(side));
  }
  return true;
}

// A loop of one course chain all round: a level curve closed by boundary
// that faces the same way, or by a stretch of boundary too short to face
// either way (the row begins or ends at a tip of the boundary, which
// happens where rows are tall against the cut's features).
bool is_one_chain_loop(const std::vector<Chain>& loop) {
  return loop.size() == 1 && loop.front().side != Side::Wale && !boundary_only(loop.front()) &&
         std::any_of(loop.front().runs.begin(), loop.front().runs.end(),
                     [](const Run& r) { return !r.level; });
}

// Makes the longest stretch of boundary of a one-chain loop the other chain.
void close_one_chain_loop(std::vector<Chain>& loop) {
  Chain& only = loop.front();
  const Side other = only.side == Side::Low ? Side::High : Side::Low;
  const std::size_t n = only.runs.size();
  std::size_t best_end = n;  // the run after the longest stretch
  double best = -1;
  for (std::size_t end = 0; end < n; ++end) {
    if (only.runs[end].level) continue;
    const std::size_t next = (end + 1) % n;
    if (!only.runs[next].level) continue;  // not the stretch's last run
    double length = 0;
    for (std::size_t k = end; !only.runs[k].level; k = (k + n - 1) % n) {
      length += only.runs[k].length;
    }
    if (length > best) {
      best = length;
      best_end = next;
    }
  }
  // The stretch ends the chain.
  std::rotate(only.runs.begin(), only.runs.begin() + static_cast<std::ptrdiff_t>(best_end),
              only.runs.end());
  Chain rest;
  rest.side = other;
  while (!only.runs.back().level) {
    rest.runs.insert(rest.runs.begin(), std::move(only.runs.back()));
    only.runs.pop_back();
  }
  loop.push_back(std::move(rest));
}

// The loop's chains as kind and length, for a problem: " L12.3 H11.0 S2.87".
std::string chain_pattern(const std::vector<Chain>& loop) {
  std::string pattern;
  for (const Chain& c : loop) {
    const double len = chain_length(c);
    pattern += std::string(" ") +
               (c.side == Side::Low    ? "L"
                : c.side == Side::High ? "H"
                                       : "S") +
               std::to_string(static_cast<int>(len * 10) / 10.0).substr(0, 4);
  }
  return pattern;
}

int sum(const std::vector<int>& counts) {
  return std::accumulate(counts.begin(), counts.end(), 0);
}

}  // namespace

StripMesher::StripMesher(const LabelledDisc& disc, const StitchMeshParams& params,
                         const BandSlices& slices)
    : disc_(disc), params_(params), slices_(slices) {
  mesh_.course_mm = params.course_mm;
  mesh_.wale_mm = params.wale_mm;
}

void StripMesher::strip(const std::string& where, std::vector<Chain> loop) {
  if (!one_bottom_and_top(where, loop)) return;
  while (loop.front().side != Side::Low) std::rotate(loop.begin(), loop.begin() + 1, loop.end());
  const Chain* right_wale = nullptr;
  const Chain* left_wale = nullptr;
  const Chain* high = nullptr;
  for (std::size_t i = 1; i < loop.size(); ++i) {
    if (loop[i].side == Side::High) {
      high = &loop[i];
    } else if (high == nullptr) {
      right_wale = &loop[i];
    } else {
      left_wale = &loop[i];
    }
  }
  const int shared = (left_wale == nullptr ? 1 : 0) + (right_wale == nullptr ? 1 : 0);
  std::vector<int> low_counts = run_counts(loop.front());
  std::vector<int> high_counts = run_counts(*high);
  fit_counts(loop.front(), *high, shared, low_counts, high_counts);
  const bool zips = zippable(sum(low_counts), sum(high_counts), left_wale == nullptr,
                             right_wale == nullptr, *high, high_counts);
  if (!zips && boundary_end_to_side(loop)) {
    // A top chain of bind-off boundary around a short fixed bottom (the
    // boundary runs almost along the rows): more stitches above than the
    // row below can feed even by increasing every stitch. The bind-off
    // stretch at the top chain's end becomes the row's wale side instead,
    // and the strip is zipped again.
    ++stats_.boundary_sides;
    strip(where, std::move(loop));
    return;
  }
  // Still too many stitches above a fixed bottom: split a bottom side whose
  // stitch below is a knit stitch (it becomes an increase), and fit the
  // counts again.
  if (!zips && split_side_below(loop.front())) {
    strip(where, std::move(loop));
    return;
  }
  zip_strip(loop.front(), *high, left_wale, right_wale, low_counts, high_counts);
}

bool StripMesher::one_bottom_and_top(const std::string& where, std::vector<Chain>& loop) {
  int lows = 0;
  int highs = 0;
  for (const Chain& c : loop) {
    lows += c.side == Side::Low;
    highs += c.side == Side::High;
  }
  if (lows == 0 || highs == 0) {
    // A course chain and a wale chain: the wale chain is the missing kind.
    const Side missing = lows == 0 ? Side::Low : Side::High;
    int walesides = 0;
    for (Chain& c : loop) walesides += c.side == Side::Wale;
    if (walesides == 1 && loop.size() == 2) {
      for (Chain& c : loop) {
        if (c.side == Side::Wale) c.side = missing;
      }
      lows = highs = 1;
    }
  }
  if (is_one_chain_loop(loop)) {
    close_one_chain_loop(loop);
    lows = highs = 1;
  }
  if (lows == 1 && highs == 1) return true;
  if (lows >= 2 && lows == highs && split_folds(where, loop)) return false;
  problems_.push_back(where + chain_pattern(loop) + ": " + std::to_string(lows) + " bottom and " +
                      std::to_string(highs) +
                      " top chains (expected one each); the row time folds here");
  return false;
}

void StripMesher::fit_counts(const Chain& low, const Chain& high, int shared,
                             std::vector<int>& low_counts, std::vector<int>& high_counts) const {
  const std::vector<bool> low_fixed = fixed_runs(low);
  const std::vector<bool> high_fixed = fixed_runs(high);
  int high_min = 0;
  for (const Run& run : high.runs) high_min += minimum(run);
  for (int attempt = 0; attempt < 2; ++attempt) {
    const int a = sum(low_counts);
    const int b = sum(high_counts);
    if (shared == 2 && a == 1 && b == 1) break;  // a lens
    const int na = a - shared;
    int lo = 0;
    int hi = 0;
    if (shared == 2 && a == 1) {
      lo = hi = 1;  // a lens: the edges below and above are glued
    } else if (na <= 0) {
      lo = hi = shared;  // only end triangles
    } else {
      lo = (na + 1) / 2 + shared;
      hi = 2 * na + shared;
    }
    lo = std::max(lo, high_min);
    if (lo <= hi) {
      rescale(high, high_fixed, high_counts, std::clamp(b, lo, hi));
      break;
    }
    // The top chain cannot shrink enough: lengthen the bottom one.
    rescale(low, low_fixed, low_counts,
            std::max(1, shared + (std::max(0, high_min - shared) + 1) / 2));
  }
}

bool StripMesher::split_folds(const std::string& where, std::vector<Chain> loop) {
  std::optional<FoldedLoop> folded = alternating_chains(std::move(loop));
  if (!folded) return false;
  const std::optional<std::size_t> picked = pick_fold_split(*folded, slices_, params_);
  if (!picked) return false;
  const std::size_t pick = *picked;
  std::vector<Chain>& courses = folded->courses;
  std::vector<Chain>& sides = folded->sides;
  std::vector<bool>& has_side = folded->has_side;
  const std::size_t n = courses.size();
  for (std::size_t k : {pick, (pick + 2) % n}) {
    if (!has_side[k]) continue;
    has_side[k] = false;
    if (courses[k].side == Side::Low) {
      for (Run& r : sides[k].runs) courses[k].runs.push_back(std::move(r));
    } else {
      Chain& next = courses[(k + 1) % n];
      next.runs.insert(next.runs.begin(), sides[k].runs.begin(), sides[k].runs.end());
    }
    sides[k].runs.clear();
  }
  for (Chain& c : courses) join_boundary_runs(c);
  Chain edge;  // the splitting wale edge: no boundary runs
  edge.side = Side::Wale;
  auto with_side = [&](std::vector<Chain>& out, std::size_t k) {
    out.push_back(courses[k]);
    if (has_side[k]) out.push_back(sides[k]);
  };
  // Cut off: course chains pick+1 and pick+2 with the edge; the rest keeps
  // the edge on its other side.
  std::vector<Chain> part;
  with_side(part, (pick + 1) % n);
  part.push_back(courses[(pick + 2) % n]);  // its side was joined or is empty
  part.push_back(edge);
  std::vector<Chain> rest;
  for (std::size_t k = (pick + 3) % n; k != (pick + 1) % n; k = (k + 1) % n) {
    if (k == pick) {
      rest.push_back(courses[k]);
      rest.push_back(edge);
    } else {
      with_side(rest, k);
    }
  }
  ++stats_.saddles_split;
  strip(where + " (fold)", std::move(part));
  strip(where + " (rest)", std::move(rest));
  return true;
}

void StripMesher::split_decrease(std::size_t index, int middle) {
  const StitchFace old = mesh_.faces[index];
  const std::size_t n = old.vertices.size();
  std::size_t corner = n;  // the vertex between the two course-in sides
  std::size_t top = n;
  for (std::size_t i = 0; i < n; ++i) {
    if (old.roles[i] == EdgeRole::CourseIn && old.roles[(i + n - 1) % n] == EdgeRole::CourseIn) {
      corner = i;
    }
    if (static_cast<int>(old.vertices[i]) == middle) top = i;
  }
  if (corner == n || top == n) {
    throw std::logic_error("stitch meshing: a split decrease has no corner to join");
  }
  auto part = [&](std::size_t from, std::size_t to) {
    StitchFace f;
    for (std::size_t i = from; i != to; i = (i + 1) % n) {
      f.vertices.push_back(old.vertices[i]);
      f.roles.push_back(old.roles[i]);
      f.arcs.push_back(old.arcs[i]);
    }
    f.vertices.push_back(old.vertices[to]);
    f.roles.push_back(EdgeRole::Wale);
    f.arcs.push_back(kNoArc);
    const std::optional<FaceType> type = classify_roles(f.roles);
    if (type != FaceType::Knit) {
      throw std::logic_error("stitch meshing: a split decrease did not give knit stitches");
    }
    f.type = FaceType::Knit;
    return f;
  };
  mesh_.faces[index] = part(corner, top);
  mesh_.faces.push_back(part(top, corner));
  for (std::size_t f : {index, mesh_.faces.size() - 1}) {
    const StitchFace& face = mesh_.faces[f];
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      if (face.roles[i] == EdgeRole::CourseOut) {
        face_below_[key(static_cast<int>(face.vertices[(i + 1) % face.vertices.size()]),
                        static_cast<int>(face.vertices[i]))] = f;
      }
    }
  }
}

bool StripMesher::split_side_below(const Chain& low) {
  constexpr std::size_t kNoFace = std::numeric_limits<std::size_t>::max();
  double longest = 0;
  std::size_t best_curve = 0;
  std::size_t best_index = 0;
  std::size_t best_face = 0;
  bool found = false;
  for (const Run& run : low.runs) {
    if (!run.level) continue;
    auto it = curve_of_edge_.find(undirected(run.halfedges.front()));
    if (it == curve_of_edge_.end()) continue;
    const std::vector<int>& samples = curve_samples_[at(it->second)];
    for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
      const int u = samples[k];
      const int v = samples[k + 1];
      const double length = (mesh_.positions[at(u)] - mesh_.positions[at(v)]).norm();
      auto below = face_below_.find(key(u, v));
      if (below == face_below_.end()) below = face_below_.find(key(v, u));
      if (below == face_below_.end()) {
        // Nothing below: the side was cast on (directly, or through
        // lenses glued onto a cast-on side), and casting on one more
        // stitch there changes no face.
        if (length > longest) {
          longest = length;
          best_curve = at(it->second);
          best_index = k;
          best_face = kNoFace;
          found = true;
        }
        continue;
      }
      const FaceType type = mesh_.faces[below->second].type;
      if (type != FaceType::Knit && type != FaceType::Decrease) continue;
      if (length > longest) {
        longest = length;
        best_curve = at(it->second);
        best_index = k;
        best_face = below->second;
        found = true;
      }
    }
  }
  if (!found) return false;
  std::vector<int>& samples = curve_samples_[best_curve];
  const int u = samples[best_index];
  const int v = samples[best_index + 1];
  const int middle = static_cast<int>(mesh_.positions.size());
  mesh_.positions.push_back(0.5 * (mesh_.positions[at(u)] + mesh_.positions[at(v)]));
  samples.insert(samples.begin() + static_cast<std::ptrdiff_t>(best_index) + 1, middle);
  if (best_face == kNoFace) {
    ++stats_.sides_split_below;
    return true;
  }
  StitchFace& face = mesh_.faces[best_face];
  const std::size_t n = face.vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    const int a = static_cast<int>(face.vertices[i]);
    const int b = static_cast<int>(face.vertices[(i + 1) % n]);
    if (face.roles[i] != EdgeRole::CourseOut || !((a == u && b == v) || (a == v && b == u))) {
      continue;
    }
    face.vertices.insert(face.vertices.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                         static_cast<std::uint32_t>(middle));
    face.roles.insert(face.roles.begin() + static_cast<std::ptrdiff_t>(i) + 1, EdgeRole::CourseOut);
    face.arcs.insert(face.arcs.begin() + static_cast<std::ptrdiff_t>(i) + 1, face.arcs[i]);
    face_below_.erase(key(b, a));
    ++stats_.sides_split_below;
    if (face.type == FaceType::Decrease) {
      // Two sides in, two out: a wale edge from the corner between the
      // course-in sides to the new vertex makes two knit stitches.
      shaped_below_.erase(key(b, a));
      split_decrease(best_face, middle);
      return true;
    }
    face.type = FaceType::Increase;
    face_below_[key(middle, a)] = best_face;
    face_below_[key(b, middle)] = best_face;
    shaped_below_.insert(key(middle, a));
    shaped_below_.insert(key(b, middle));
    return true;
  }
  throw std::logic_error("stitch meshing: a course-out side is not in its face");
}

}  // namespace planner::stitch_meshing
