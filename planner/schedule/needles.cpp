// §7.2: needles of the course edges of a Schedule (assign_needles).
#include <algorithm>
#include <cmath>
#include <map>

#include "planner/schedule/schedule.hpp"

namespace planner {
namespace {

int median_rounded(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return static_cast<int>(std::lround(values[(values.size() - 1) / 2]));
}

int patch_of_face(const Schedule& s, int f) {
  return s.rows[static_cast<std::size_t>(s.face_row[static_cast<std::size_t>(f)])].patch;
}

// Needles of each course edge within its patch: `top` where the loop sits
// once its lower face is knit, `bottom` where its upper face takes it.
struct LocalNeedles {
  std::vector<int> top, bottom;
  std::vector<bool> top_set;
};

// Bottom edges of a row of patch p (`ins`, left to right): copied from the
// rows below in this patch (§7.2), the others placed next to them.
std::vector<int> bottom_needles(const Schedule& s, std::size_t p, const std::vector<int>& ins,
                                const LocalNeedles& local) {
  std::vector<int> b(ins.size(), 0);
  std::vector<bool> known(ins.size(), false);
  bool any = false;
  for (std::size_t i = 0; i < ins.size(); ++i) {
    const CourseEdge& e = s.edges[static_cast<std::size_t>(ins[i])];
    if (e.lower != kNone && patch_of_face(s, e.lower) == static_cast<int>(p) &&
        local.top_set[static_cast<std::size_t>(ins[i])]) {
      b[i] = local.top[static_cast<std::size_t>(ins[i])];
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
  return b;
}

// Top edges on consecutive needles, shifted to make the total transfer
// distance least; a row with a short-row face is aligned on it (§7.2).
// `b`: the bottom needles of the row's course edges in, left to right.
int top_shift(const StitchMesh& mesh, const Schedule& s, const Row& row,
              const std::vector<int>& b) {
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
  return has_short_row ? short_row_shift : median_rounded(diffs);
}

LocalNeedles local_needles(const StitchMesh& mesh, const Schedule& s) {
  const std::size_t ne = s.edges.size();
  LocalNeedles local;
  local.top.assign(ne, 0);
  local.bottom.assign(ne, 0);
  local.top_set.assign(ne, false);
  for (std::size_t p = 0; p < s.patches.size(); ++p) {
    for (int r : s.patches[p].rows) {
      const Row& row = s.rows[static_cast<std::size_t>(r)];
      std::vector<int> ins;
      for (int f : row.faces) {
        for (int e : s.faces[static_cast<std::size_t>(f)].in) ins.push_back(e);
      }
      const std::vector<int> b = bottom_needles(s, p, ins, local);
      for (std::size_t i = 0; i < ins.size(); ++i)
        local.bottom[static_cast<std::size_t>(ins[i])] = b[i];
      const int shift = top_shift(mesh, s, row, b);
      int t = 0;
      for (int f : row.faces) {
        for (int e : s.faces[static_cast<std::size_t>(f)].out) {
          local.top[static_cast<std::size_t>(e)] = t++ + shift;
          local.top_set[static_cast<std::size_t>(e)] = true;
        }
      }
    }
  }
  return local;
}

// §7.2: shift patches to agree along their boundaries, walking the patch
// graph from patch 0; separate components side by side. Returns the
// offset of each patch.
std::vector<int> patch_offsets(const Schedule& s, const LocalNeedles& local) {
  const std::size_t ne = s.edges.size();
  const std::size_t np = s.patches.size();
  std::vector<std::vector<int>> edges_of_patch(np);
  for (std::size_t e = 0; e < ne; ++e) {
    const CourseEdge& ce = s.edges[e];
    if (ce.lower == kNone || ce.upper == kNone) continue;
    const int a = patch_of_face(s, ce.lower), c = patch_of_face(s, ce.upper);
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
          lo = std::min(lo, local.top[static_cast<std::size_t>(e)] + off);
          hi = std::max(hi, local.top[static_cast<std::size_t>(e)] + off);
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
        const int a = patch_of_face(s, ce.lower), c = patch_of_face(s, ce.upper);
        if (a == static_cast<int>(p) && !placed[static_cast<std::size_t>(c)]) {
          wanted[c].push_back(local.top[static_cast<std::size_t>(e)] + offset[p] -
                              local.bottom[static_cast<std::size_t>(e)]);
        } else if (c == static_cast<int>(p) && !placed[static_cast<std::size_t>(a)]) {
          wanted[a].push_back(local.bottom[static_cast<std::size_t>(e)] + offset[p] -
                              local.top[static_cast<std::size_t>(e)]);
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
  return offset;
}

}  // namespace

void assign_needles(const StitchMesh& mesh, Schedule& s) {
  const LocalNeedles local = local_needles(mesh, s);
  const std::vector<int> offset = patch_offsets(s, local);
  for (std::size_t e = 0; e < s.edges.size(); ++e) {
    CourseEdge& ce = s.edges[e];
    if (ce.lower != kNone) {
      ce.needle = local.top[e] + offset[static_cast<std::size_t>(patch_of_face(s, ce.lower))];
    } else {
      ce.needle = local.bottom[e] + offset[static_cast<std::size_t>(patch_of_face(s, ce.upper))];
    }
  }
}

}  // namespace planner
