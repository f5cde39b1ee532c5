#include "planner/schedule/schedule.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <numeric>
#include <random>
#include <thread>
#include <unordered_map>

namespace planner {
namespace {

std::string face_name(std::size_t f) {
  return "face " + std::to_string(f);
}

std::uint64_t side_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

// Sides of one face sorted by the role they play in the row (§6.3): course
// edges in, left to right; course edges out, left to right; the wale sides.
struct FaceSides {
  std::vector<int> in;   // side indices
  std::vector<int> out;  // side indices, left to right
  int left_wale = kNone;
  int right_wale = kNone;
};

FaceSides classify_sides(const StitchFace& face, std::size_t f) {
  const int n = static_cast<int>(face.roles.size());
  FaceSides sides;
  auto role = [&](int i) { return face.roles[static_cast<std::size_t>(((i % n) + n) % n)]; };
  // A run of one role, in counter-clockwise order, starting where it begins.
  auto run = [&](EdgeRole r) {
    std::vector<int> found;
    int start = kNone;
    for (int i = 0; i < n; ++i) {
      if (role(i) == r && role(i - 1) != r) {
        if (start != kNone)
          throw ScheduleError(face_name(f) + ": its " +
                              (r == EdgeRole::CourseIn ? "course-in" : "course-out") +
                              " sides are not contiguous");
        start = i;
      }
    }
    if (start == kNone) {
      if (r != EdgeRole::Wale && n > 0 && role(0) == r)
        throw ScheduleError(face_name(f) + ": every side has the same role");
      return found;
    }
    for (int i = start; role(i) == r && static_cast<int>(found.size()) < n; ++i)
      found.push_back(i % n);
    return found;
  };
  sides.in = run(EdgeRole::CourseIn);
  sides.out = run(EdgeRole::CourseOut);
  // Counter-clockwise seen from the front the top is walked right to left.
  std::reverse(sides.out.begin(), sides.out.end());
  if (sides.in.empty()) throw ScheduleError(face_name(f) + ": no course-in side");
  if (sides.out.empty()) throw ScheduleError(face_name(f) + ": no course-out side");
  for (int i = 0; i < n; ++i) {
    if (role(i) != EdgeRole::Wale) continue;
    int j = i + 1;
    while (role(j) == EdgeRole::Wale && j < i + n) ++j;
    // In, then the right side, then out; out, then the left side, then in.
    int& slot = role(j) == EdgeRole::CourseOut ? sides.right_wale : sides.left_wale;
    if (slot != kNone) throw ScheduleError(face_name(f) + ": more than one wale side per end");
    slot = i;
  }
  return sides;
}

std::uint64_t mix(std::uint64_t seed, std::uint64_t trial) {
  // splitmix64 of the pair: independent streams per trial.
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + trial + 0x632BE59BD9B4E019ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

int median_rounded(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return static_cast<int>(std::lround(values[(values.size() - 1) / 2]));
}

}  // namespace

void build_rows(const StitchMesh& mesh, Schedule& s) {
  const std::size_t nf = mesh.faces.size();
  s.faces.assign(nf, FaceLinks{});
  s.edges.clear();
  s.wale_seams.clear();
  std::vector<FaceSides> sides(nf);
  std::unordered_map<std::uint64_t, std::vector<std::pair<int, int>>> by_key;
  for (std::size_t f = 0; f < nf; ++f) {
    const StitchFace& face = mesh.faces[f];
    if (face.vertices.size() < 3) throw ScheduleError(face_name(f) + ": fewer than three vertices");
    if (face.roles.size() != face.vertices.size())
      throw ScheduleError(face_name(f) + ": " + std::to_string(face.roles.size()) +
                          " side roles for " + std::to_string(face.vertices.size()) + " vertices");
    for (std::uint32_t v : face.vertices) {
      if (v >= mesh.positions.size())
        throw ScheduleError(face_name(f) + ": vertex " + std::to_string(v) + " out of range");
    }
    sides[f] = classify_sides(face, f);
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      by_key[side_key(face.vertices[i], face.vertices[(i + 1) % n])].emplace_back(
          static_cast<int>(f), static_cast<int>(i));
    }
  }
  auto other_side = [&](int f, int i) -> std::pair<int, int> {
    const StitchFace& face = mesh.faces[static_cast<std::size_t>(f)];
    const std::size_t n = face.vertices.size();
    const auto& list = by_key[side_key(face.vertices[static_cast<std::size_t>(i)],
                                       face.vertices[(static_cast<std::size_t>(i) + 1) % n])];
    if (list.size() > 2)
      throw ScheduleError(face_name(static_cast<std::size_t>(f)) + " side " + std::to_string(i) +
                          ": shared by more than two faces");
    for (const auto& p : list) {
      if (p.first != f || p.second != i) return p;
    }
    return {kNone, kNone};
  };
  // Course edges: one per CourseOut side (matched with a CourseIn side or on
  // the boundary), then the unmatched CourseIn sides (cast on).
  std::map<std::pair<int, int>, int> edge_of_in;
  for (std::size_t f = 0; f < nf; ++f) {
    for (int side : sides[f].out) {
      auto [g, gs] = other_side(static_cast<int>(f), side);
      CourseEdge e;
      e.lower = static_cast<int>(f);
      if (g != kNone) {
        if (mesh.faces[static_cast<std::size_t>(g)].roles[static_cast<std::size_t>(gs)] !=
            EdgeRole::CourseIn)
          throw ScheduleError(face_name(f) + " side " + std::to_string(side) +
                              ": course-out side meets a side of " +
                              face_name(static_cast<std::size_t>(g)) + " that is not course-in");
        e.upper = g;
        edge_of_in[{g, gs}] = static_cast<int>(s.edges.size());
      }
      s.faces[f].out.push_back(static_cast<int>(s.edges.size()));
      s.edges.push_back(e);
    }
  }
  for (std::size_t f = 0; f < nf; ++f) {
    for (int side : sides[f].in) {
      auto it = edge_of_in.find({static_cast<int>(f), side});
      if (it != edge_of_in.end()) {
        s.faces[f].in.push_back(it->second);
        continue;
      }
      auto [g, gs] = other_side(static_cast<int>(f), side);
      if (g != kNone)
        throw ScheduleError(face_name(f) + " side " + std::to_string(side) +
                            ": course-in side meets a side of " +
                            face_name(static_cast<std::size_t>(g)) + " that is not course-out");
      CourseEdge e;
      e.upper = static_cast<int>(f);
      s.faces[f].in.push_back(static_cast<int>(s.edges.size()));
      s.edges.push_back(e);
    }
  }
  // Wale neighbours: a right wale side meets the left wale side of the next face.
  for (std::size_t f = 0; f < nf; ++f) {
    if (sides[f].right_wale == kNone) continue;
    auto [g, gs] = other_side(static_cast<int>(f), sides[f].right_wale);
    if (g == kNone) continue;
    if (sides[static_cast<std::size_t>(g)].left_wale != gs) {
      // Both faces see the side as their right (or the other's course runs
      // the other way): they cannot be knit in one row. The side is left
      // open, a seam to sew.
      const std::pair<int, int> seam{std::min(static_cast<int>(f), g),
                                     std::max(static_cast<int>(f), g)};
      if (std::find(s.wale_seams.begin(), s.wale_seams.end(), seam) == s.wale_seams.end())
        s.wale_seams.push_back(seam);
      continue;
    }
    s.faces[f].right = g;
    s.faces[static_cast<std::size_t>(g)].left = static_cast<int>(f);
  }
  for (std::size_t f = 0; f < nf; ++f) {
    if (sides[f].left_wale == kNone) continue;
    auto [g, gs] = other_side(static_cast<int>(f), sides[f].left_wale);
    if (g != kNone && s.faces[f].left != g && sides[static_cast<std::size_t>(g)].right_wale != gs &&
        static_cast<int>(f) < g)
      s.wale_seams.emplace_back(static_cast<int>(f), g);  // two left sides meet
  }
  // §7.1, Fig. 8b: rows are maximal runs of wale-connected faces.
  s.face_row.assign(nf, kNone);
  s.rows.clear();
  auto walk = [&](int start, bool cycle) {
    Row row;
    row.cycle_broken = cycle;
    for (int f = start; f != kNone && s.face_row[static_cast<std::size_t>(f)] == kNone;
         f = s.faces[static_cast<std::size_t>(f)].right) {
      s.face_row[static_cast<std::size_t>(f)] = static_cast<int>(s.rows.size());
      row.faces.push_back(f);
    }
    s.rows.push_back(std::move(row));
  };
  for (std::size_t f = 0; f < nf; ++f) {
    if (s.faces[f].left == kNone) walk(static_cast<int>(f), false);
  }
  // Faces left over sit on rows closed into rings: open each at its lowest face.
  for (std::size_t f = 0; f < nf; ++f) {
    if (s.face_row[f] != kNone) continue;
    const int start = static_cast<int>(f);
    const int prev = s.faces[f].left;
    s.faces[static_cast<std::size_t>(prev)].right = kNone;
    s.faces[f].left = kNone;
    walk(start, true);
  }
}

void build_patches(Schedule& s) {
  const std::size_t nr = s.rows.size();
  s.row_successors.assign(nr, {});
  for (const CourseEdge& e : s.edges) {
    if (e.lower == kNone || e.upper == kNone) continue;
    const int a = s.face_row[static_cast<std::size_t>(e.lower)];
    const int b = s.face_row[static_cast<std::size_t>(e.upper)];
    if (a == b)
      throw ScheduleError("face " + std::to_string(e.upper) + " is knit through a loop of face " +
                          std::to_string(e.lower) + " of its own row");
    s.row_successors[static_cast<std::size_t>(a)].push_back(b);
  }
  std::vector<int> indegree(nr, 0);
  for (auto& succ : s.row_successors) {
    std::sort(succ.begin(), succ.end());
    succ.erase(std::unique(succ.begin(), succ.end()), succ.end());
    for (int b : succ) ++indegree[static_cast<std::size_t>(b)];
  }
  // Topological order (Kahn, lowest row first so it is deterministic).
  std::vector<int> topo;
  std::vector<int> deg = indegree;
  std::vector<int> ready;
  for (std::size_t r = 0; r < nr; ++r) {
    if (deg[r] == 0) ready.push_back(static_cast<int>(r));
  }
  while (!ready.empty()) {
    std::pop_heap(ready.begin(), ready.end(), std::greater<>());
    const int r = ready.back();
    ready.pop_back();
    topo.push_back(r);
    for (int b : s.row_successors[static_cast<std::size_t>(r)]) {
      if (--deg[static_cast<std::size_t>(b)] == 0) {
        ready.push_back(b);
        std::push_heap(ready.begin(), ready.end(), std::greater<>());
      }
    }
  }
  if (topo.size() != nr)
    throw ScheduleError(
        "the row graph has a cycle: course directions of the stitch mesh disagree (" +
        std::to_string(nr - topo.size()) + " rows on cycles)");
  std::vector<int>& topo_index = s.row_topo_index;
  topo_index.assign(nr, 0);
  for (std::size_t i = 0; i < nr; ++i)
    topo_index[static_cast<std::size_t>(topo[i])] = static_cast<int>(i);
  // Fig. 8d: an edge u->v is redundant when v is reached from u another way
  // (the path through a short row makes the direct edge redundant).
  s.reduced_successors.assign(nr, {});
  std::vector<int> mark(nr, -1);
  std::vector<int> stack;
  for (std::size_t u = 0; u < nr; ++u) {
    for (int v : s.row_successors[u]) {
      bool other_path = false;
      stack.clear();
      const int stamp = static_cast<int>(u * nr) + v;
      for (int w : s.row_successors[u]) {
        if (w != v &&
            topo_index[static_cast<std::size_t>(w)] < topo_index[static_cast<std::size_t>(v)]) {
          stack.push_back(w);
          mark[static_cast<std::size_t>(w)] = stamp;
        }
      }
      while (!stack.empty() && !other_path) {
        const int x = stack.back();
        stack.pop_back();
        for (int y : s.row_successors[static_cast<std::size_t>(x)]) {
          if (y == v) {
            other_path = true;
            break;
          }
          if (topo_index[static_cast<std::size_t>(y)] < topo_index[static_cast<std::size_t>(v)] &&
              mark[static_cast<std::size_t>(y)] != stamp) {
            mark[static_cast<std::size_t>(y)] = stamp;
            stack.push_back(y);
          }
        }
      }
      if (!other_path) s.reduced_successors[u].push_back(v);
    }
  }
  // Fig. 8e: collapse serial chains; split (out-degree > 1) and merge
  // (in-degree > 1) edges stay between patches.
  std::vector<int> red_in(nr, 0);
  for (const auto& succ : s.reduced_successors) {
    for (int v : succ) ++red_in[static_cast<std::size_t>(v)];
  }
  std::vector<int> next(nr, kNone);
  std::vector<bool> has_prev(nr, false);
  for (std::size_t u = 0; u < nr; ++u) {
    if (s.reduced_successors[u].size() == 1) {
      const int v = s.reduced_successors[u][0];
      if (red_in[static_cast<std::size_t>(v)] == 1) {
        next[u] = v;
        has_prev[static_cast<std::size_t>(v)] = true;
      }
    }
  }
  s.patches.clear();
  for (int r : topo) {
    if (has_prev[static_cast<std::size_t>(r)]) continue;
    Patch p;
    for (int x = r; x != kNone; x = next[static_cast<std::size_t>(x)]) {
      p.rows.push_back(x);
      s.rows[static_cast<std::size_t>(x)].patch = static_cast<int>(s.patches.size());
    }
    s.patches.push_back(std::move(p));
  }
}

void assign_needles(const StitchMesh& mesh, Schedule& s) {
  const std::size_t ne = s.edges.size();
  std::vector<int> local_top(ne, 0), local_bottom(ne, 0);
  std::vector<bool> top_set(ne, false);
  auto row_of = [&](int f) { return s.face_row[static_cast<std::size_t>(f)]; };
  auto patch_of_face = [&](int f) { return s.rows[static_cast<std::size_t>(row_of(f))].patch; };
  for (std::size_t p = 0; p < s.patches.size(); ++p) {
    for (int r : s.patches[p].rows) {
      const Row& row = s.rows[static_cast<std::size_t>(r)];
      // Bottom edges: copied from the rows below in this patch (§7.2), the
      // others placed next to them.
      std::vector<int> ins;
      for (int f : row.faces) {
        for (int e : s.faces[static_cast<std::size_t>(f)].in) ins.push_back(e);
      }
      std::vector<int> b(ins.size(), 0);
      std::vector<bool> known(ins.size(), false);
      bool any = false;
      for (std::size_t i = 0; i < ins.size(); ++i) {
        const CourseEdge& e = s.edges[static_cast<std::size_t>(ins[i])];
        if (e.lower != kNone && patch_of_face(e.lower) == static_cast<int>(p) &&
            top_set[static_cast<std::size_t>(ins[i])]) {
          b[i] = local_top[static_cast<std::size_t>(ins[i])];
          known[i] = any = true;
        }
      }
      if (!any) {
        for (std::size_t i = 0; i < ins.size(); ++i) b[i] = static_cast<int>(i);
      } else {
        for (std::size_t i = 1; i < ins.size(); ++i) {
          if (!known[i] && known[i - 1]) {
            b[i] = b[i - 1] + 1;
            known[i] = true;
          }
        }
        for (std::size_t i = ins.size() - 1; i-- > 0;) {
          if (!known[i] && known[i + 1]) {
            b[i] = b[i + 1] - 1;
            known[i] = true;
          }
        }
      }
      for (std::size_t i = 0; i < ins.size(); ++i)
        local_bottom[static_cast<std::size_t>(ins[i])] = b[i];
      // Top edges on consecutive needles, shifted to make the total transfer
      // distance least; a row with a short-row face is aligned on it (§7.2).
      std::vector<double> diffs;
      int short_row_shift = 0;
      bool has_short_row = false;
      std::size_t bi = 0, ti = 0;
      for (int f : row.faces) {
        const FaceLinks& fl = s.faces[static_cast<std::size_t>(f)];
        double bm = 0, tm = 0;
        for (std::size_t k = 0; k < fl.in.size(); ++k) bm += b[bi + k];
        for (std::size_t k = 0; k < fl.out.size(); ++k) tm += static_cast<double>(ti + k);
        bm /= static_cast<double>(fl.in.size());
        tm /= static_cast<double>(fl.out.size());
        diffs.push_back(bm - tm);
        if (!has_short_row && mesh.faces[static_cast<std::size_t>(f)].type == FaceType::ShortRow) {
          has_short_row = true;
          short_row_shift = static_cast<int>(std::lround(bm - tm));
        }
        bi += fl.in.size();
        ti += fl.out.size();
      }
      const int shift = has_short_row ? short_row_shift : median_rounded(diffs);
      int t = 0;
      for (int f : row.faces) {
        for (int e : s.faces[static_cast<std::size_t>(f)].out) {
          local_top[static_cast<std::size_t>(e)] = t++ + shift;
          top_set[static_cast<std::size_t>(e)] = true;
        }
      }
    }
  }
  // §7.2: shift patches to agree along their boundaries, walking the patch
  // graph from patch 0; separate components side by side.
  const std::size_t np = s.patches.size();
  std::vector<std::vector<int>> edges_of_patch(np);
  for (std::size_t e = 0; e < ne; ++e) {
    const CourseEdge& ce = s.edges[e];
    if (ce.lower == kNone || ce.upper == kNone) continue;
    const int a = patch_of_face(ce.lower), c = patch_of_face(ce.upper);
    if (a == c) continue;
    edges_of_patch[static_cast<std::size_t>(a)].push_back(static_cast<int>(e));
    edges_of_patch[static_cast<std::size_t>(c)].push_back(static_cast<int>(e));
  }
  std::vector<int> offset(np, 0);
  std::vector<bool> placed(np, false);
  auto extent = [&](std::size_t p, int off, int& lo, int& hi) {
    for (int r : s.patches[p].rows) {
      for (int f : s.rows[static_cast<std::size_t>(r)].faces) {
        for (int e : s.faces[static_cast<std::size_t>(f)].out) {
          lo = std::min(lo, local_top[static_cast<std::size_t>(e)] + off);
          hi = std::max(hi, local_top[static_cast<std::size_t>(e)] + off);
        }
      }
    }
  };
  int right_end = 0;
  bool first_component = true;
  for (std::size_t root = 0; root < np; ++root) {
    if (placed[root]) continue;
    int lo = 1 << 30, hi = -(1 << 30);
    extent(root, 0, lo, hi);
    offset[root] = first_component ? 0 : right_end + 4 - lo;
    first_component = false;
    placed[root] = true;
    std::vector<std::size_t> queue{root};
    for (std::size_t qi = 0; qi < queue.size(); ++qi) {
      const std::size_t p = queue[qi];
      std::map<int, std::vector<double>> wanted;  // neighbour -> offsets it would need
      for (int e : edges_of_patch[p]) {
        const CourseEdge& ce = s.edges[static_cast<std::size_t>(e)];
        const int a = patch_of_face(ce.lower), c = patch_of_face(ce.upper);
        if (a == static_cast<int>(p) && !placed[static_cast<std::size_t>(c)]) {
          wanted[c].push_back(local_top[static_cast<std::size_t>(e)] + offset[p] -
                              local_bottom[static_cast<std::size_t>(e)]);
        } else if (c == static_cast<int>(p) && !placed[static_cast<std::size_t>(a)]) {
          wanted[a].push_back(local_bottom[static_cast<std::size_t>(e)] + offset[p] -
                              local_top[static_cast<std::size_t>(e)]);
        }
      }
      for (auto& [q, values] : wanted) {
        offset[static_cast<std::size_t>(q)] = median_rounded(values);
        placed[static_cast<std::size_t>(q)] = true;
        queue.push_back(static_cast<std::size_t>(q));
      }
    }
    for (std::size_t p : queue) extent(p, offset[p], lo, hi);
    right_end = std::max(right_end, hi);
  }
  for (std::size_t e = 0; e < ne; ++e) {
    CourseEdge& ce = s.edges[e];
    if (ce.lower != kNone) {
      ce.needle = local_top[e] + offset[static_cast<std::size_t>(patch_of_face(ce.lower))];
    } else {
      ce.needle = local_bottom[e] + offset[static_cast<std::size_t>(patch_of_face(ce.upper))];
    }
  }
}

namespace {

// The patch graph: successors of each patch (sorted, no repeats).
std::vector<std::vector<int>> patch_successors(const Schedule& s) {
  std::vector<std::vector<int>> succ(s.patches.size());
  for (std::size_t r = 0; r < s.rows.size(); ++r) {
    const int a = s.rows[r].patch;
    for (int v : s.row_successors[r]) {
      const int b = s.rows[static_cast<std::size_t>(v)].patch;
      if (a != b) succ[static_cast<std::size_t>(a)].push_back(b);
    }
  }
  for (auto& list : succ) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return succ;
}

}  // namespace

std::vector<int> random_patch_order(const Schedule& s, std::uint64_t seed, std::uint64_t trial) {
  const std::size_t np = s.patches.size();
  const std::vector<std::vector<int>> succ = patch_successors(s);
  std::vector<int> indeg(np, 0);
  for (const auto& list : succ) {
    for (int b : list) ++indeg[static_cast<std::size_t>(b)];
  }
  std::mt19937_64 rng(mix(seed, trial));
  std::vector<int> ready, order;
  for (std::size_t p = 0; p < np; ++p) {
    if (indeg[p] == 0) ready.push_back(static_cast<int>(p));
  }
  std::shuffle(ready.begin(), ready.end(), rng);
  // Two rules, mixed in a proportion drawn per trial so the trials spread
  // from one extreme to the other: depth first (the patch the last one just
  // unlocked is knit next, so a branch is finished before another starts and
  // its loops are held briefly) and lowest first (the ready patch lowest in
  // the row graph's topological order, so the branches beside a merge climb
  // together).
  std::bernoulli_distribution depth_first(std::uniform_real_distribution<double>(0, 1)(rng));
  while (!ready.empty()) {
    std::size_t i = ready.size() - 1;
    if (!depth_first(rng)) {
      i = 0;
      auto height = [&](int q) {
        const auto first = s.patches[static_cast<std::size_t>(q)].rows.front();
        return s.row_topo_index[static_cast<std::size_t>(first)];
      };
      for (std::size_t k = 1; k < ready.size(); ++k) {
        if (height(ready[k]) < height(ready[i])) i = k;
      }
    }
    const int p = ready[i];
    ready.erase(ready.begin() + static_cast<std::ptrdiff_t>(i));
    order.push_back(p);
    std::vector<int> unlocked;
    for (int b : succ[static_cast<std::size_t>(p)]) {
      if (--indeg[static_cast<std::size_t>(b)] == 0) unlocked.push_back(b);
    }
    std::shuffle(unlocked.begin(), unlocked.end(), rng);
    ready.insert(ready.end(), unlocked.begin(), unlocked.end());
  }
  if (order.size() != np) throw std::logic_error("random_patch_order: the patch graph has a cycle");
  return order;
}

std::vector<std::pair<int, int>> simulate_order(const Schedule& s, const std::vector<int>& order,
                                                int max_shift, std::vector<int>* patch_shift,
                                                int max_aside, std::vector<AsideMove>* asides) {
  // §7.3: knit the rows patch by patch on a needle bed that keeps every loop
  // whose consumer is not knit yet. A row that needs a needle holding a loop
  // meant for another row overlaps it: cut the rows that loop joins.
  if (asides != nullptr) asides->clear();
  if (s.edges.empty()) return {};
  int lo = 1 << 30, hi = -(1 << 30);
  for (const CourseEdge& e : s.edges) {
    lo = std::min(lo, e.needle);
    hi = std::max(hi, e.needle);
  }
  max_shift = std::max(0, max_shift);
  max_aside = std::max(0, max_aside);
  lo -= max_shift + max_aside;
  hi += max_shift + max_aside;
  std::vector<int> shift(s.patches.size(), 0);
  // Needles each held loop was moved aside since it was made.
  std::vector<int> aside(s.edges.size(), 0);
  std::vector<std::vector<int>> held(static_cast<std::size_t>(hi - lo + 1));
  std::vector<std::pair<int, int>> cuts;
  auto row_of = [&](int f) { return s.face_row[static_cast<std::size_t>(f)]; };
  auto is_cut = [&](int a, int b) {
    return std::find(cuts.begin(), cuts.end(), std::make_pair(a, b)) != cuts.end();
  };
  // Where edge e's loop is made: its needle, moved with the patch that makes
  // it (or, cast on, with the patch that knits it).
  auto owner = [&](const CourseEdge& ce) {
    return s.rows[static_cast<std::size_t>(row_of(ce.lower != kNone ? ce.lower : ce.upper))].patch;
  };
  auto needle_of = [&](int e) {
    const CourseEdge& ce = s.edges[static_cast<std::size_t>(e)];
    return ce.needle + shift[static_cast<std::size_t>(owner(ce))];
  };
  // Where a made loop is now.
  auto held_at = [&](int e) { return needle_of(e) + aside[static_cast<std::size_t>(e)]; };
  auto bucket_at = [&](int n) -> std::vector<int>& {
    return held[static_cast<std::size_t>(n - lo)];
  };
  // The needles row r needs: its top needles and those its loops come from.
  auto span = [&](int r, int& rlo, int& rhi) {
    rlo = 1 << 30;
    rhi = -(1 << 30);
    for (int f : s.rows[static_cast<std::size_t>(r)].faces) {
      const FaceLinks& fl = s.faces[static_cast<std::size_t>(f)];
      for (int e : fl.out) {
        rlo = std::min(rlo, needle_of(e));
        rhi = std::max(rhi, needle_of(e));
      }
      for (int e : fl.in) {
        const CourseEdge& ce = s.edges[static_cast<std::size_t>(e)];
        if (ce.lower == kNone || is_cut(row_of(ce.lower), r)) continue;
        rlo = std::min(rlo, held_at(e));
        rhi = std::max(rhi, held_at(e));
      }
    }
  };
  // Each row's place in its patch (rows of a patch are knit in that order).
  std::vector<int> place(s.rows.size(), 0);
  for (const Patch& patch : s.patches) {
    for (std::size_t i = 0; i < patch.rows.size(); ++i)
      place[static_cast<std::size_t>(patch.rows[i])] = static_cast<int>(i);
  }
  // The row pairs whose loops, held now, the rows of patch p would cover
  // (a loop for a row of p that is knit by then is not in the way), and the
  // needles p's rows need (`in_patch`, from `lo`).
  std::vector<std::pair<int, int>> covered;
  std::vector<char> in_patch(held.size(), 0);
  auto count_covered = [&](int p) {
    covered.clear();
    std::fill(in_patch.begin(), in_patch.end(), 0);
    for (int r : s.patches[static_cast<std::size_t>(p)].rows) {
      int rlo = 0, rhi = 0;
      span(r, rlo, rhi);
      for (int n = rlo; n <= rhi; ++n) {
        in_patch[static_cast<std::size_t>(n - lo)] = 1;
        for (int e : bucket_at(n)) {
          const CourseEdge& ce = s.edges[static_cast<std::size_t>(e)];
          const int b = row_of(ce.upper);
          if (s.rows[static_cast<std::size_t>(b)].patch == p &&
              place[static_cast<std::size_t>(b)] <= place[static_cast<std::size_t>(r)])
            continue;
          covered.emplace_back(row_of(ce.lower), b);
        }
      }
    }
    std::sort(covered.begin(), covered.end());
    covered.erase(std::unique(covered.begin(), covered.end()), covered.end());
    return static_cast<int>(covered.size());
  };
  // The held loops that join rows a and b.
  auto held_between = [&](int a, int b) {
    std::vector<int> edges;
    for (int f : s.rows[static_cast<std::size_t>(a)].faces) {
      for (int e : s.faces[static_cast<std::size_t>(f)].out) {
        const CourseEdge& ce = s.edges[static_cast<std::size_t>(e)];
        if (ce.upper == kNone || row_of(ce.upper) != b) continue;
        const auto& bucket = bucket_at(held_at(e));
        if (std::find(bucket.begin(), bucket.end(), e) != bucket.end()) edges.push_back(e);
      }
    }
    return edges;
  };
  // The move (in needles) that takes every loop of `edges` off the needles
  // of the patch counted last (`in_patch`) onto needles that hold no other
  // loop, at most max_aside from where each was made; the fewest needles,
  // away from the patch's middle first. 0 when none does.
  auto aside_move = [&](const std::vector<int>& edges, int middle) {
    if (edges.empty()) return 0;
    const int away = held_at(edges.front()) >= middle ? 1 : -1;
    for (int k = 1; k <= 2 * max_aside; ++k) {
      const int d = (k % 2 == 1 ? away : -away) * ((k + 1) / 2);
      bool fits = true;
      for (int e : edges) {
        const int n = held_at(e) + d;
        if (std::abs(aside[static_cast<std::size_t>(e)] + d) > max_aside ||
            in_patch[static_cast<std::size_t>(n - lo)] != 0 ||
            !std::all_of(bucket_at(n).begin(), bucket_at(n).end(), [&](int other) {
              return std::find(edges.begin(), edges.end(), other) != edges.end();
            })) {
          fits = false;
          break;
        }
      }
      if (fits) return d;
    }
    return 0;
  };
  // The middle of the needles patch p needs (after count_covered).
  auto patch_middle = [&] {
    int first = -1, last = -1;
    for (std::size_t i = 0; i < in_patch.size(); ++i) {
      if (in_patch[i] == 0) continue;
      if (first < 0) first = static_cast<int>(i);
      last = static_cast<int>(i);
    }
    return lo + (first + last) / 2;
  };
  // Row pairs patch p would cover that no move aside clears (after
  // count_covered).
  auto left_covered = [&] {
    if (max_aside == 0) return static_cast<int>(covered.size());
    const int middle = patch_middle();
    int left = 0;
    for (const auto& [a, b] : covered) {
      if (aside_move(held_between(a, b), middle) == 0) ++left;
    }
    return left;
  };
  for (int p : order) {
    // A patch that would cover loops held for other rows is moved sideways
    // as a whole (Fig. 9c, but by one transfer at the patch's start rather
    // than one needle per row): by the fewest needles, within
    // ±max_shift, that leaves the fewest row pairs to cut once the loops
    // that can be are moved aside.
    const auto& rows = s.patches[static_cast<std::size_t>(p)].rows;
    int best = 0, best_count = count_covered(p);
    int best_left = best_count > 0 ? left_covered() : 0;
    for (int d = 1; d <= 2 * max_shift && best_count > 0; ++d) {
      shift[static_cast<std::size_t>(p)] = d % 2 == 1 ? (d + 1) / 2 : -(d / 2);
      const int c = count_covered(p);
      const int left = c > 0 ? left_covered() : 0;
      if (left < best_left || (left == best_left && c < best_count)) {
        best = shift[static_cast<std::size_t>(p)];
        best_count = c;
        best_left = left;
      }
    }
    shift[static_cast<std::size_t>(p)] = best;
    // Then the held loops it would cover are moved out of its way, one row
    // pair at a time, where that clears them.
    if (best_count > 0 && max_aside > 0) {
      count_covered(p);
      const int middle = patch_middle();
      const std::vector<std::pair<int, int>> pairs = covered;
      for (const auto& [a, b] : pairs) {
        const std::vector<int> edges = held_between(a, b);
        const int d = aside_move(edges, middle);
        if (d == 0) continue;
        for (int e : edges) {
          auto& from = bucket_at(held_at(e));
          from.erase(std::remove(from.begin(), from.end(), e), from.end());
        }
        for (int e : edges) {
          aside[static_cast<std::size_t>(e)] += d;
          bucket_at(held_at(e)).push_back(e);
          if (asides != nullptr) asides->push_back({rows.front(), e, held_at(e)});
        }
      }
    }
    for (int r : rows) {
      const Row& row = s.rows[static_cast<std::size_t>(r)];
      int rlo = 0, rhi = 0;
      span(r, rlo, rhi);
      for (int n = rlo; n <= rhi; ++n) {
        auto& bucket = bucket_at(n);
        for (std::size_t k = 0; k < bucket.size(); ++k) {
          const CourseEdge& ce = s.edges[static_cast<std::size_t>(bucket[k])];
          const int a = row_of(ce.lower), b = row_of(ce.upper);
          if (b == r) continue;
          cuts.emplace_back(a, b);
          // Every loop joining the two rows is bound off: none stays held.
          for (int e : held_between(a, b)) {
            auto& other = bucket_at(held_at(e));
            other.erase(std::remove(other.begin(), other.end(), e), other.end());
          }
          k = static_cast<std::size_t>(-1);  // the bucket changed: look again
        }
      }
      for (int f : row.faces) {
        const FaceLinks& fl = s.faces[static_cast<std::size_t>(f)];
        for (int e : fl.in) {
          const CourseEdge& ce = s.edges[static_cast<std::size_t>(e)];
          if (ce.lower == kNone) continue;
          auto& bucket = bucket_at(held_at(e));
          bucket.erase(std::remove(bucket.begin(), bucket.end(), e), bucket.end());
        }
        for (int e : fl.out) {
          const CourseEdge& ce = s.edges[static_cast<std::size_t>(e)];
          if (ce.upper == kNone) continue;
          bucket_at(held_at(e)).push_back(e);
        }
      }
    }
  }
  if (patch_shift != nullptr) *patch_shift = std::move(shift);
  return cuts;
}

int improve_order(const Schedule& s, std::vector<int>& order, int max_shift, int max_moves,
                  int max_aside) {
  const std::vector<std::vector<int>> succ = patch_successors(s);
  std::vector<std::vector<int>> pred(succ.size());
  for (std::size_t a = 0; a < succ.size(); ++a) {
    for (int b : succ[a]) pred[static_cast<std::size_t>(b)].push_back(static_cast<int>(a));
  }
  // `p` taken out of `order` and put back at the earliest place its
  // predecessors allow (`earliest`), or the latest its successors allow.
  const auto moved = [&](const std::vector<int>& from, int p, bool earliest) {
    std::vector<int> out;
    out.reserve(from.size());
    for (int q : from) {
      if (q != p) out.push_back(q);
    }
    std::vector<int> pos(succ.size());
    for (std::size_t i = 0; i < out.size(); ++i)
      pos[static_cast<std::size_t>(out[i])] = static_cast<int>(i);
    std::size_t at = earliest ? 0 : out.size();
    if (earliest) {
      for (int q : pred[static_cast<std::size_t>(p)])
        at = std::max(at, static_cast<std::size_t>(pos[static_cast<std::size_t>(q)]) + 1);
    } else {
      for (int q : succ[static_cast<std::size_t>(p)])
        at = std::min(at, static_cast<std::size_t>(pos[static_cast<std::size_t>(q)]));
    }
    out.insert(out.begin() + static_cast<std::ptrdiff_t>(at), p);
    return out;
  };
  std::vector<std::pair<int, int>> cuts = simulate_order(s, order, max_shift, nullptr, max_aside);
  int moves = 0;
  // Moves patch `p`; keeps the order when it leaves fewer cuts.
  const auto improves = [&](int p, bool earliest) {
    if (moves >= max_moves) return false;
    std::vector<int> candidate = moved(order, p, earliest);
    if (candidate == order) return false;
    ++moves;
    std::vector<std::pair<int, int>> fewer =
        simulate_order(s, candidate, max_shift, nullptr, max_aside);
    if (fewer.size() >= cuts.size()) return false;
    order = std::move(candidate);
    cuts = std::move(fewer);
    return true;
  };
  bool improved = true;
  while (improved && moves < max_moves && !cuts.empty()) {
    improved = false;
    // The loops of a cut's lower row were covered before its upper row
    // took them: knit the consumer as early as it can go, or the producer
    // as late.
    for (const auto& [lower, upper] : std::vector<std::pair<int, int>>(cuts)) {
      improved = improves(s.rows[static_cast<std::size_t>(upper)].patch, true) ||
                 improves(s.rows[static_cast<std::size_t>(lower)].patch, false);
      if (improved) break;
    }
    // No move of a cut's own patches helps: try every patch.
    for (std::size_t i = 0; !improved && i < order.size(); ++i) {
      const int p = order[i];
      improved = improves(p, true) || improves(p, false);
    }
  }
  return static_cast<int>(cuts.size());
}

void choose_order(Schedule& s, const ScheduleParams& params) {
  const auto start = std::chrono::steady_clock::now();
  const bool by_time = params.time_budget_s > 0;
  const std::uint64_t limit = by_time ? std::numeric_limits<std::uint64_t>::max()
                                      : static_cast<std::uint64_t>(std::max(1, params.trials));
  unsigned threads = params.threads > 0 ? static_cast<unsigned>(params.threads)
                                        : std::max(1u, std::thread::hardware_concurrency());
  std::atomic<std::uint64_t> next{0};
  std::mutex mutex;
  std::vector<TrialResult> results;
  auto worker = [&] {
    std::vector<TrialResult> mine;
    for (;;) {
      if (by_time) {
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // At least one order, whatever the budget.
        if (elapsed >= params.time_budget_s && next.load() > 0) break;
      }
      const std::uint64_t t = next.fetch_add(1);
      if (t >= limit) break;
      const auto order = random_patch_order(s, params.seed, t);
      const auto cuts = [&](int max_aside) {
        return static_cast<int>(
            simulate_order(s, order, params.max_patch_shift, nullptr, max_aside).size());
      };
      TrialResult result;
      result.trial = t;
      result.cuts_in_place = cuts(0);
      result.cuts_aside = params.max_aside > 0 ? cuts(params.max_aside) : result.cuts_in_place;
      result.cuts = std::min(result.cuts_in_place, result.cuts_aside);
      mine.push_back(result);
    }
    std::lock_guard<std::mutex> lock(mutex);
    results.insert(results.end(), mine.begin(), mine.end());
  };
  std::vector<std::thread> pool;
  for (unsigned i = 1; i < threads; ++i) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
  std::sort(results.begin(), results.end(),
            [](const TrialResult& a, const TrialResult& b) { return a.trial < b.trial; });
  s.trials = results;
  const auto best =
      std::min_element(results.begin(), results.end(),
                       [](const TrialResult& a, const TrialResult& b) { return a.cuts < b.cuts; });
  s.best_trial = best->trial;
  bool aside = best->cuts_aside < best->cuts_in_place;
  s.patch_order = random_patch_order(s, params.seed, best->trial);
  s.random_cuts = best->cuts;
  // Local search (improve_order) from the best random orders, in parallel;
  // the result depends only on the ranking, not on the threads. The
  // params.improve best orders with held loops in place are refined so,
  // then (when loops may be set aside) the params.improve best with them
  // set aside; the first job of the fewest cuts wins, so where setting
  // aside does not help the schedule is the one without it.
  const std::size_t keep = static_cast<std::size_t>(std::max(0, params.improve));
  struct Job {
    std::uint64_t trial = 0;
    bool aside = false;
  };
  std::vector<Job> jobs;
  for (const bool set_aside : {false, true}) {
    if (set_aside && params.max_aside == 0) continue;
    std::vector<TrialResult> ranked = results;
    std::stable_sort(ranked.begin(), ranked.end(), [&](const TrialResult& a, const TrialResult& b) {
      return set_aside ? a.cuts_aside < b.cuts_aside : a.cuts_in_place < b.cuts_in_place;
    });
    for (std::size_t i = 0; i < std::min(keep, ranked.size()); ++i)
      jobs.push_back({ranked[i].trial, set_aside});
  }
  std::vector<std::vector<int>> improved(jobs.size());
  std::vector<int> improved_cuts(jobs.size(), 0);
  std::atomic<std::size_t> next_order{0};
  auto refine = [&] {
    for (std::size_t j = next_order.fetch_add(1); j < jobs.size(); j = next_order.fetch_add(1)) {
      improved[j] = random_patch_order(s, params.seed, jobs[j].trial);
      improved_cuts[j] = improve_order(s, improved[j], params.max_patch_shift, params.improve_moves,
                                       jobs[j].aside ? params.max_aside : 0);
    }
  };
  pool.clear();
  for (unsigned i = 1; i < threads && i < jobs.size(); ++i) pool.emplace_back(refine);
  refine();
  for (auto& th : pool) th.join();
  // The fewest cuts (ties: the earlier job). The first start of each kind
  // is the best random order of that kind, which the search never makes
  // worse.
  if (!jobs.empty()) {
    const auto j = static_cast<std::size_t>(
        std::min_element(improved_cuts.begin(), improved_cuts.end()) - improved_cuts.begin());
    s.patch_order = std::move(improved[j]);
    s.best_trial = jobs[j].trial;
    aside = jobs[j].aside;
  }
  std::vector<int> shift;
  s.cut_rows = simulate_order(s, s.patch_order, params.max_patch_shift, &shift,
                              aside ? params.max_aside : 0, &s.aside_moves);
  s.cuts = static_cast<int>(s.cut_rows.size());
  s.patch_shift = shift;
  // The kept order's patch shifts become the needles the emitter uses.
  for (CourseEdge& e : s.edges) {
    const int f = e.lower != kNone ? e.lower : e.upper;
    e.needle += shift[static_cast<std::size_t>(
        s.rows[static_cast<std::size_t>(s.face_row[static_cast<std::size_t>(f)])].patch)];
  }
  for (CourseEdge& e : s.edges) {
    if (e.lower == kNone || e.upper == kNone) continue;
    const std::pair<int, int> rows{s.face_row[static_cast<std::size_t>(e.lower)],
                                   s.face_row[static_cast<std::size_t>(e.upper)]};
    e.cut = std::find(s.cut_rows.begin(), s.cut_rows.end(), rows) != s.cut_rows.end();
  }
}

void make_pieces(Schedule& s) {
  const std::size_t nr = s.rows.size();
  std::vector<int> parent(nr);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[static_cast<std::size_t>(x)] != x) {
      parent[static_cast<std::size_t>(x)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
      x = parent[static_cast<std::size_t>(x)];
    }
    return x;
  };
  for (const CourseEdge& e : s.edges) {
    if (e.lower == kNone || e.upper == kNone || e.cut) continue;
    const int a = find(s.face_row[static_cast<std::size_t>(e.lower)]);
    const int b = find(s.face_row[static_cast<std::size_t>(e.upper)]);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
  s.pieces.clear();
  std::map<int, std::size_t> piece_of_root;
  for (int p : s.patch_order) {
    for (int r : s.patches[static_cast<std::size_t>(p)].rows) {
      const int root = find(r);
      auto [it, added] = piece_of_root.emplace(root, s.pieces.size());
      if (added) s.pieces.emplace_back();
      s.pieces[it->second].rows.push_back(r);
    }
  }
}

Schedule schedule(const StitchMesh& mesh, const ScheduleParams& params) {
  Schedule s;
  build_rows(mesh, s);
  build_patches(s);
  assign_needles(mesh, s);
  if (!s.patches.empty()) choose_order(s, params);
  make_pieces(s);
  return s;
}

}  // namespace planner
