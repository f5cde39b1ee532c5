// §7.1: rows and patches of a Schedule (build_rows, build_patches).
#include <algorithm>
#include <map>
#include <unordered_map>

#include "planner/schedule/schedule.hpp"

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

// Where each side of the mesh is: (face, side index) pairs by the key of
// the side's two vertices.
class SideIndex {
 public:
  explicit SideIndex(const StitchMesh& mesh) : mesh_(mesh) {}

  void add(std::size_t f) {
    const StitchFace& face = mesh_.faces[f];
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      by_key_[side_key(face.vertices[i], face.vertices[(i + 1) % n])].emplace_back(
          static_cast<int>(f), static_cast<int>(i));
    }
  }

  // The face and side across side i of face f; (kNone, kNone) on the boundary.
  std::pair<int, int> other_side(int f, int i) {
    const StitchFace& face = mesh_.faces[static_cast<std::size_t>(f)];
    const std::size_t n = face.vertices.size();
    const auto& list = by_key_[side_key(face.vertices[static_cast<std::size_t>(i)],
                                        face.vertices[(static_cast<std::size_t>(i) + 1) % n])];
    if (list.size() > 2)
      throw ScheduleError(face_name(static_cast<std::size_t>(f)) + " side " + std::to_string(i) +
                          ": shared by more than two faces");
    for (const auto& p : list) {
      if (p.first != f || p.second != i) return p;
    }
    return {kNone, kNone};
  }

 private:
  const StitchMesh& mesh_;
  std::unordered_map<std::uint64_t, std::vector<std::pair<int, int>>> by_key_;
};

// Checks every face and sorts its sides by role.
std::vector<FaceSides> read_faces(const StitchMesh& mesh, SideIndex& index) {
  const std::size_t nf = mesh.faces.size();
  std::vector<FaceSides> sides(nf);
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
    index.add(f);
  }
  return sides;
}

// Course edges: one per CourseOut side (matched with a CourseIn side or on
// the boundary), then the unmatched CourseIn sides (cast on).
void link_course_edges(const StitchMesh& mesh, const std::vector<FaceSides>& sides,
                       SideIndex& index, Schedule& s) {
  const std::size_t nf = mesh.faces.size();
  std::map<std::pair<int, int>, int> edge_of_in;
  for (std::size_t f = 0; f < nf; ++f) {
    for (int side : sides[f].out) {
      auto [g, gs] = index.other_side(static_cast<int>(f), side);
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
      auto [g, gs] = index.other_side(static_cast<int>(f), side);
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
}

// Wale neighbours: a right wale side meets the left wale side of the next face.
void link_wale_sides(const std::vector<FaceSides>& sides, SideIndex& index, Schedule& s) {
  const std::size_t nf = sides.size();
  for (std::size_t f = 0; f < nf; ++f) {
    if (sides[f].right_wale == kNone) continue;
    auto [g, gs] = index.other_side(static_cast<int>(f), sides[f].right_wale);
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
    auto [g, gs] = index.other_side(static_cast<int>(f), sides[f].left_wale);
    if (g != kNone && s.faces[f].left != g && sides[static_cast<std::size_t>(g)].right_wale != gs &&
        static_cast<int>(f) < g)
      s.wale_seams.emplace_back(static_cast<int>(f), g);  // two left sides meet
  }
}

// §7.1, Fig. 8b: rows are maximal runs of wale-connected faces.
void walk_rows(Schedule& s) {
  const std::size_t nf = s.faces.size();
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

}  // namespace

void build_rows(const StitchMesh& mesh, Schedule& s) {
  s.faces.assign(mesh.faces.size(), FaceLinks{});
  s.edges.clear();
  s.wale_seams.clear();
  SideIndex index(mesh);
  const std::vector<FaceSides> sides = read_faces(mesh, index);
  link_course_edges(mesh, sides, index, s);
  link_wale_sides(sides, index, s);
  walk_rows(s);
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

}  // namespace planner
