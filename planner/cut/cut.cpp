#include "planner/cut/cut.hpp"

#include <algorithm>
#include <cstdlib>
#include <deque>
#include <map>
#include <numbers>
#include <numeric>
#include <queue>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include "planner/common/index.hpp"
#include "planner/common/union_find.hpp"
#include "planner/cut/tighten.hpp"
#include "planner/cut/vanishing.hpp"
#include "planner/mesh/soup.hpp"

namespace planner {

namespace {

// Crossing a side of direction d leaves a counter-clockwise unit square
// through that side: the +u side is the bottom one, so the neighbour lies at
// -v; and so on round the square.
constexpr std::array<std::array<int, 2>, 4> kStep = {{{0, -1}, {1, 0}, {0, 1}, {-1, 0}}};

std::uint64_t cell_key(const std::array<int, 2>& uv) {
  return pair_key(uv[0], uv[1]);
}

bool is_vanishing(const HalfedgeMesh& q, const FieldLabels& labels, int h) {
  return labels.vanishing_corner[at(q.face(h))] == q.corner(h);
}

// Outgoing half-edges of interior vertex w, rotated to start at `first`.
std::vector<int> fan_from(const HalfedgeMesh& q, int w, int first) {
  std::vector<int> out = q.outgoing(w);
  auto it = std::find(out.begin(), out.end(), first);
  if (it == out.end()) throw std::logic_error("fan_from: half-edge not around its vertex");
  std::rotate(out.begin(), it, out.end());
  return out;
}

// The outgoing half-edges of w that continue `back` (an outgoing half-edge
// of w, the way we came) topologically straight: two non-vanishing corners
// away on the counter-clockwise side. w must be an interior vertex with 4
// non-vanishing corners. With a vanishing corner in between there are two.
std::vector<int> straight_continuations(const HalfedgeMesh& q, const FieldLabels& labels, int w,
                                        int back) {
  const std::vector<int> fan = fan_from(q, w, back);
  std::vector<int> result;
  int count = 0;
  for (std::size_t j = 1; j < fan.size(); ++j) {
    count += is_vanishing(q, labels, fan[j - 1]) ? 0 : 1;
    if (count == 2) result.push_back(fan[j]);
    if (count > 2) break;
  }
  return result;
}

// §4.2, Fig. 4: motorcycles leave every irregular vertex along each of its
// edges and run straight until they reach a vertex already visited or the
// mesh boundary. They advance in lock step so none is favoured by order.
std::vector<int> motorcycle_graph(const HalfedgeMesh& q, const FieldLabels& labels,
                                  std::mt19937_64& rng) {
  std::vector<int> crossings(at(q.num_edges()), 0);
  std::vector<bool> visited(at(q.num_vertices()), false);
  std::vector<int> riders;
  for (int v : labels.irregular_vertices) {
    visited[at(v)] = true;
    for (int h : q.outgoing(v)) riders.push_back(h);
  }
  while (!riders.empty()) {
    std::vector<int> next;
    for (int h : riders) {
      ++crossings[at(q.edge(h))];
      const int w = q.to(h);
      if (visited[at(w)] || q.is_boundary_vertex(w) || labels.corner_count[at(w)] != 4) {
        visited[at(w)] = true;
        continue;
      }
      visited[at(w)] = true;
      const std::vector<int> straight = straight_continuations(q, labels, w, q.twin(h));
      if (straight.empty()) continue;
      // At a vanishing corner either side is straight: pick one (§4.2).
      next.push_back(straight.size() == 1 ? straight[0] : straight[rng() % straight.size()]);
    }
    riders = std::move(next);
  }
  return crossings;
}

// The disc: corners glued across every edge that is neither cut nor boundary.
void build_disc(CutMesh& cut) {
  const HalfedgeMesh& q = cut.proxy;
  UnionFind corners(at(q.num_halfedges()));
  for (int h = 0; h < q.num_halfedges(); ++h) {
    const int t = q.twin(h);
    if (t < h || cut.cut_edge[at(q.edge(h))]) continue;
    corners.unite(h, q.next(t));
    corners.unite(q.next(h), t);
  }
  // The first copy of every vertex of Q keeps Q's index, so cut-mesh.obj
  // starts with proxy.obj's vertices in order and the copies made by the
  // cuts follow: cuts.json's indices are then valid in both files.
  const int nv = q.num_vertices();
  std::vector<int> id(at(q.num_halfedges()), -1);
  std::vector<bool> taken(at(nv), false);
  cut.disc = PolygonMesh{};
  cut.disc.positions.resize(at(nv));
  cut.disc_source.resize(at(nv));
  for (int v = 0; v < nv; ++v) {
    cut.disc.positions[at(v)] = q.position(v);
    cut.disc_source[at(v)] = v;
  }
  for (int h = 0; h < q.num_halfedges(); ++h) {
    const int root = corners.find(h);
    if (id[at(root)] >= 0) continue;
    const int v = q.from(h);
    if (!taken[at(v)]) {
      taken[at(v)] = true;
      id[at(root)] = v;
    } else {
      id[at(root)] = static_cast<int>(cut.disc_source.size());
      cut.disc_source.push_back(v);
      cut.disc.positions.push_back(q.position(v));
    }
  }
  cut.disc.faces.resize(at(q.num_faces()));
  for (int f = 0; f < q.num_faces(); ++f) {
    for (int i = 0; i < q.degree(f); ++i) {
      cut.disc.faces[at(f)].push_back(id[at(corners.find(q.face_start(f) + i))]);
    }
  }
}

// The outgoing half-edge of w along edge e.
int out_along(const HalfedgeMesh& q, int w, int e) {
  const int h = q.edge_halfedge(e);
  return q.from(h) == w ? h : q.twin(h);
}

// The vertex reached from w by following the cut `reach` edges along edge e
// (fewer where the next vertex is a node or the cut does not go on through it).
int edges_along(const HalfedgeMesh& q, const std::vector<std::vector<int>>& incident, int w, int e,
                int reach) {
  int v = q.to(out_along(q, w, e));
  for (int k = 1; k < reach; ++k) {
    const auto& list = incident[at(v)];
    if (list.size() != 2) break;
    e = list[0] == e ? list[1] : list[0];
    v = q.to(out_along(q, v, e));
  }
  return v;
}

// Cut-arcs: maximal paths of cut edges through interior vertices that are not
// singular, where exactly two cut edges meet and the cut turns by at most
// `turn_deg`. The turn is measured between the chords two edges back and two
// ahead, or one on a path between other nodes of under 8 edges, so that a
// small loop (a thin handle's cut) is one arc rather than split at every
// vertex.
std::vector<CutArc> find_arcs(const HalfedgeMesh& q, const FieldLabels& labels,
                              const std::vector<bool>& cut_edge, double turn_deg) {
  const std::vector<std::vector<int>> incident = cut_edges_at(q, cut_edge);
  auto structural = [&](int w) {
    return incident[at(w)].size() != 2 || q.is_boundary_vertex(w) || is_singular(labels, w);
  };
  // Per cut edge: the number of edges of the path between structural nodes it lies on.
  std::vector<int> path_edges(at(q.num_edges()), 0);
  for (const CutPath& path : split_cut(q, cut_edge, incident, structural)) {
    for (int e : path.edges) path_edges[at(e)] = static_cast<int>(path.edges.size());
  }
  const double max_turn = turn_deg * std::numbers::pi / 180.0;
  auto passes_through = [&](int w) {
    if (structural(w)) return false;
    const auto& list = incident[at(w)];
    const int reach = path_edges[at(list[0])] < 8 ? 1 : 2;
    const Vec3& p = q.position(w);
    const Vec3 back = p - q.position(edges_along(q, incident, w, list[0], reach));
    const Vec3 ahead = q.position(edges_along(q, incident, w, list[1], reach)) - p;
    return angle_between(back, ahead) <= max_turn;
  };
  std::vector<bool> node(at(q.num_vertices()), false);
  for (int v = 0; v < q.num_vertices(); ++v) {
    node[at(v)] = !incident[at(v)].empty() && !passes_through(v);
  }
  std::vector<CutArc> arcs;
  for (CutPath& path : split_cut(q, cut_edge, incident, [&](int v) { return node[at(v)]; })) {
    CutArc arc;
    for (int e : path.edges) arc.length_mm += q.edge_length(q.edge_halfedge(e));
    arc.vertices = std::move(path.vertices);
    arc.closed = arc.vertices.back() == arc.vertices.front();
    arcs.push_back(std::move(arc));
  }
  return arcs;
}

}  // namespace

const char* vanishing_name(VanishingRule::Method method) {
  switch (method) {
    case VanishingRule::Method::Optimal:
      return "optimal";
    case VanishingRule::Method::Acute:
      return "acute";
    case VanishingRule::Method::Regular:
      return "regular";
  }
  throw std::logic_error("vanishing_name: unknown method");
}

std::optional<VanishingRule::Method> vanishing_method(std::string_view name) {
  for (auto method : {VanishingRule::Method::Optimal, VanishingRule::Method::Acute,
                      VanishingRule::Method::Regular}) {
    if (name == vanishing_name(method)) return method;
  }
  return std::nullopt;
}

FieldLabels label_field(const HalfedgeMesh& q, const VanishingRule& rule) {
  for (int f = 0; f < q.num_faces(); ++f) {
    const int n = q.degree(f);
    if (n != 3 && n != 4) {
      throw std::logic_error("label_field: face " + std::to_string(f) + " has " +
                             std::to_string(n) + " corners (split polygons first)");
    }
  }
  if (rule.method == VanishingRule::Method::Optimal) {
    return labels_with_vanishing(q, optimal_vanishing_corners(q));
  }
  std::vector<int> acute_corner(at(q.num_faces()), -1);
  std::vector<std::array<bool, 3>> allowed(at(q.num_faces()), {false, false, false});
  for (int f = 0; f < q.num_faces(); ++f) {
    if (q.degree(f) != 3) continue;
    // §4.1: the most acute corner of a triangle vanishes.
    int best = 0;
    double smallest = 10.0;
    std::array<double, 3> angles{};
    for (int i = 0; i < 3; ++i) {
      angles[at(i)] = q.corner_angle(q.face_start(f) + i);
      if (angles[at(i)] < smallest) {
        smallest = angles[at(i)];
        best = i;
      }
    }
    acute_corner[at(f)] = best;
    for (int i = 0; i < 3; ++i) {
      allowed[at(f)][at(i)] = angles[at(i)] <= smallest + rule.slack_deg * std::numbers::pi / 180.0;
    }
  }
  FieldLabels acute = labels_with_vanishing(q, std::move(acute_corner));
  if (rule.method == VanishingRule::Method::Acute) return acute;
  // Regular: corners around each vertex, not counting vanishing ones; a
  // triangle moves its vanishing corner to another allowed corner when that
  // brings its three vertices closer to four corners each (sum of
  // |count - 4| over interior vertices), until no triangle can.
  std::vector<int>& count = acute.corner_count;
  std::vector<int>& vanishing = acute.vanishing_corner;
  auto misfit = [&](int v) { return q.is_boundary_vertex(v) ? 0 : std::abs(count[at(v)] - 4); };
  for (int sweep = 0; sweep < 100; ++sweep) {
    bool moved = false;
    for (int f = 0; f < q.num_faces(); ++f) {
      if (q.degree(f) != 3) continue;
      const int current = vanishing[at(f)];
      const int from = q.from(q.face_start(f) + current);
      int choice = current, choice_cost = 0;
      for (int i = 0; i < 3; ++i) {
        if (i == current || !allowed[at(f)][at(i)]) continue;
        const int to = q.from(q.face_start(f) + i);
        const int before = misfit(from) + misfit(to);
        ++count[at(from)];
        --count[at(to)];
        const int change = misfit(from) + misfit(to) - before;
        --count[at(from)];
        ++count[at(to)];
        if (change < choice_cost) {
          choice = i;
          choice_cost = change;
        }
      }
      if (choice != current) {
        ++count[at(from)];
        --count[at(q.from(q.face_start(f) + choice))];
        vanishing[at(f)] = choice;
        moved = true;
      }
    }
    if (!moved) break;
  }
  return labels_with_vanishing(q, std::move(vanishing));
}

FieldLabels labels_with_vanishing(const HalfedgeMesh& q, std::vector<int> vanishing_corner) {
  FieldLabels labels;
  labels.vanishing_corner = std::move(vanishing_corner);
  labels.corner_count.assign(at(q.num_vertices()), 0);
  for (int h = 0; h < q.num_halfedges(); ++h) {
    if (!is_vanishing(q, labels, h)) ++labels.corner_count[at(q.from(h))];
  }
  for (int v = 0; v < q.num_vertices(); ++v) {
    if (q.is_boundary_vertex(v)) continue;
    if (labels.corner_count[at(v)] != 4) labels.irregular_vertices.push_back(v);
    if (labels.corner_count[at(v)] % 4 != 0) labels.singular_vertices.push_back(v);
  }
  return labels;
}

int corner_turn(const HalfedgeMesh& q, const FieldLabels& labels, int h) {
  return is_vanishing(q, labels, h) ? 2 : 1;
}

int halfedge_direction(const HalfedgeMesh& q, const FieldLabels& labels, int frame, int h) {
  const int start = q.face_start(q.face(h));
  int d = frame;
  for (int i = start + 1; i <= h; ++i) d += corner_turn(q, labels, i);
  return d % 4;
}

namespace {

// The seed is an arbitrary quad (§4.1), picked by the random generator; a
// proxy without quads starts from any face.
int pick_seed_face(const HalfedgeMesh& q, std::mt19937_64& rng) {
  const int nf = q.num_faces();
  std::vector<int> quads;
  for (int f = 0; f < nf; ++f) {
    if (q.degree(f) == 4) quads.push_back(f);
  }
  return quads.empty() ? static_cast<int>(rng() % static_cast<std::uint64_t>(nf))
                       : quads[rng() % quads.size()];
}

// The seed face's frame: the wale direction (+v) along the side that runs
// closest to the longest side of Q's bounding box.
int seed_frame(const HalfedgeMesh& q, const FieldLabels& labels, int seed_face) {
  const Vec3 size = bounding_box_size(q.polygons());
  Vec3 axis = Vec3::Zero();
  int longest = 0;
  size.maxCoeff(&longest);
  axis[longest] = 1.0;
  int best_h = q.face_start(seed_face);
  double best = -2.0;
  for (int i = 0; i < q.degree(seed_face); ++i) {
    const int h = q.face_start(seed_face) + i;
    const Vec3 d = (q.position(q.to(h)) - q.position(q.from(h))).normalized();
    if (d.dot(axis) > best) {
      best = d.dot(axis);
      best_h = h;
    }
  }
  return ((1 - halfedge_direction(q, labels, 0, best_h)) % 4 + 4) % 4;
}

// The frame of the face of half-edge t, reached across the edge whose other
// half-edge has direction `direction`: the one that makes t's direction
// opposite to it.
int frame_across(const HalfedgeMesh& q, const FieldLabels& labels, int direction, int t) {
  return ((direction + 2 - halfedge_direction(q, labels, 0, t)) % 4 + 4) % 4;
}

// §4.1–4.2 patch growing. The patch starts as one face and grows over the
// half-edge of its boundary B with the lowest cuttability score
// c_s * (motorcycle crossings) + c_o * (overlap score), equal scores in the
// order of a random key. Every face reached gets a frame and an integer
// (u, v) cell; consecutive half-edges of B on the two sides of one edge
// fuse when their directions are opposite. B is kept as a doubly linked
// cycle of Q's half-edges; what is left of it at the end is the cut.
class PatchGrower {
 public:
  // Grows over cut.proxy with cut.labels and cut.motorcycle_edges; fills
  // cut.face_frame, cut.direction and cut.face_uv. `rng` draws the keys.
  PatchGrower(CutMesh& cut, const CutParams& params, std::mt19937_64& rng)
      : cut_(cut),
        q_(cut.proxy),
        labels_(cut.labels),
        params_(params),
        rng_(rng),
        overlap_score_(at(q_.num_faces()), 0.0),
        visited_(at(q_.num_faces()), false),
        in_b_(at(q_.num_halfedges()), false),
        next_b_(at(q_.num_halfedges()), -1),
        prev_b_(at(q_.num_halfedges()), -1) {
    cut_.face_frame.assign(at(q_.num_faces()), -1);
    cut_.direction.assign(at(q_.num_halfedges()), -1);
    cut_.face_uv.assign(at(q_.num_faces()), {0, 0});
  }

  // The patch is face `f` with its first half-edge in direction `frame`, at cell (0, 0).
  void start(int f, int frame) {
    place(f, frame, {0, 0}, 0.0);
    const int n = q_.degree(f);
    for (int i = 0; i < n; ++i) {
      const int h = q_.face_start(f) + i;
      in_b_[at(h)] = true;
      next_b_[at(h)] = q_.face_start(f) + (i + 1) % n;
      prev_b_[at(h)] = q_.face_start(f) + (i + n - 1) % n;
    }
    b_size_ = n;
    placed_ = 1;
    offer(f);
  }

  // Grows until no face can be reached; returns how many faces the patch holds.
  int grow() {
    while (!queue_.empty()) {
      const Entry entry = queue_.top();
      queue_.pop();
      const int h = entry.h;
      if (!in_b_[at(h)] || visited_[at(q_.face(q_.twin(h)))]) continue;
      const double score = score_of(h);
      if (score > entry.score + 1e-9) {  // stale: the grid filled up since it was offered
        queue_.push({score, ring_of(h), rng_(), h});
        continue;
      }
      expand(h);
    }
    return placed_;
  }

  // Half-edge h is on the patch's boundary.
  bool on_boundary(int h) const { return in_b_[at(h)]; }
  // How many faces of the patch are in cell `uv`.
  int faces_in_cell(const std::array<int, 2>& uv) { return grid_[cell_key(uv)]; }

 private:
  struct Entry {
    double score;
    int ring;  // square growth: the ring of the cell across; else 0
    std::uint64_t key;
    int h;
    bool operator>(const Entry& o) const {
      if (score != o.score) return score > o.score;
      if (ring != o.ring) return ring > o.ring;
      if (key != o.key) return key > o.key;
      return h > o.h;
    }
  };

  void place(int f, int frame, std::array<int, 2> uv, double score) {
    visited_[at(f)] = true;
    cut_.face_frame[at(f)] = frame;
    for (int i = 0; i < q_.degree(f); ++i) {
      const int h = q_.face_start(f) + i;
      cut_.direction[at(h)] = halfedge_direction(q_, labels_, frame, h);
    }
    cut_.face_uv[at(f)] = uv;
    overlap_score_[at(f)] = score;
    ++grid_[cell_key(uv)];
  }

  // The cell across half-edge h of a placed face.
  std::array<int, 2> cell_across(int h) const {
    const int f = q_.face(h);
    const auto& step = kStep[at(cut_.direction[at(h)])];
    return {cut_.face_uv[at(f)][0] + step[0], cut_.face_uv[at(f)][1] + step[1]};
  }

  // How many faces of the patch are in the cell across h.
  int count_across(int h) const {
    const auto it = grid_.find(cell_key(cell_across(h)));
    return it == grid_.end() ? 0 : it->second;
  }

  double score_of(int h) const {
    const int count = count_across(h);
    return params_.cs * cut_.motorcycle_edges[at(q_.edge(h))] +
           params_.co * (overlap_score_[at(q_.face(h))] + count);
  }

  // Square growth: the ring around the seed of the cell across h.
  int ring_of(int h) const {
    if (!params_.square_growth) return 0;
    const std::array<int, 2> uv = cell_across(h);
    return std::max(std::abs(uv[0]), std::abs(uv[1]));
  }

  // Queues the half-edges of f on B that lead to a face not yet reached.
  void offer(int f) {
    for (int i = 0; i < q_.degree(f); ++i) {
      const int h = q_.face_start(f) + i;
      const int t = q_.twin(h);
      if (in_b_[at(h)] && t >= 0 && !visited_[at(q_.face(t))])
        queue_.push({score_of(h), ring_of(h), rng_(), h});
    }
  }

  // §4.1 expansion over h: the face g across it joins with the frame that
  // makes its half-edge t opposite to h, and in B h is replaced by g's other
  // half-edges, in order.
  void expand(int h) {
    const int t = q_.twin(h);
    const int g = q_.face(t);
    const int f = q_.face(h);
    const int frame = frame_across(q_, labels_, cut_.direction[at(h)], t);
    place(g, frame, cell_across(h), overlap_score_[at(f)] + count_across(h));
    ++placed_;
    const int before = prev_b_[at(h)];
    const int after = next_b_[at(h)];
    in_b_[at(h)] = false;
    int last = before;
    for (int x = q_.next(t); x != t; x = q_.next(x)) {
      in_b_[at(x)] = true;
      next_b_[at(last)] = x;
      prev_b_[at(x)] = last;
      last = x;
    }
    next_b_[at(last)] = after;
    prev_b_[at(after)] = last;
    b_size_ += q_.degree(g) - 2;
    fuse({before, last});
    offer(g);
  }

  // §4.1 fusion: consecutive boundary elements on the two sides of one edge
  // dissolve, only when their directions are opposite; each fusion makes
  // the element before them a candidate for the next.
  void fuse(std::vector<int> pending) {
    while (!pending.empty()) {
      const int a = pending.back();
      pending.pop_back();
      if (!in_b_[at(a)]) continue;
      const int b = next_b_[at(a)];
      // The last two edges of a closed surface's cut stay: a cut of one
      // edge splits no vertex, and the surface would not open.
      if (b != q_.twin(a) || b_size_ <= 4) continue;
      if ((cut_.direction[at(a)] + 2) % 4 != cut_.direction[at(b)]) continue;
      const int before = prev_b_[at(a)];
      const int after = next_b_[at(b)];
      next_b_[at(before)] = after;
      prev_b_[at(after)] = before;
      in_b_[at(a)] = in_b_[at(b)] = false;
      b_size_ -= 2;
      // §4.2: both faces take the smaller overlap score, plus their own cell's extra layers.
      const int fa = q_.face(a);
      const int fb = q_.face(b);
      const double low = std::min(overlap_score_[at(fa)], overlap_score_[at(fb)]);
      overlap_score_[at(fa)] = low + grid_[cell_key(cut_.face_uv[at(fa)])] - 1;
      overlap_score_[at(fb)] = low + grid_[cell_key(cut_.face_uv[at(fb)])] - 1;
      offer(fa);
      offer(fb);
      pending.push_back(before);
    }
  }

  CutMesh& cut_;
  const HalfedgeMesh& q_;
  const FieldLabels& labels_;
  const CutParams& params_;
  std::mt19937_64& rng_;
  std::vector<double> overlap_score_;            // per face
  std::unordered_map<std::uint64_t, int> grid_;  // faces per (u, v) cell
  std::vector<bool> visited_;                    // per face: in the patch
  std::vector<bool> in_b_;                       // per half-edge: on B
  std::vector<int> next_b_;                      // per half-edge on B: the next one
  std::vector<int> prev_b_;
  int b_size_ = 0;
  int placed_ = 0;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue_;
};

// The disc's frames and (u, v) cells again, after the cut moved: faces are
// reached from the seed across uncut edges, each with the frame that makes
// its side opposite to the one it was reached over (as in patch growing).
void lay_out(CutMesh& cut) {
  const HalfedgeMesh& q = cut.proxy;
  const int seed = cut.seed_face;
  const int seed_frame = cut.face_frame[at(seed)];
  std::vector<bool> reached(at(q.num_faces()), false);
  auto place = [&](int f, int frame, std::array<int, 2> uv) {
    reached[at(f)] = true;
    cut.face_frame[at(f)] = frame;
    for (int i = 0; i < q.degree(f); ++i) {
      const int h = q.face_start(f) + i;
      cut.direction[at(h)] = halfedge_direction(q, cut.labels, frame, h);
    }
    cut.face_uv[at(f)] = uv;
  };
  place(seed, seed_frame, {0, 0});
  std::deque<int> queue{seed};
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop_front();
    for (int i = 0; i < q.degree(f); ++i) {
      const int h = q.face_start(f) + i;
      const int t = q.twin(h);
      if (t < 0 || cut.cut_edge[at(q.edge(h))] || reached[at(q.face(t))]) continue;
      const int frame = frame_across(q, cut.labels, cut.direction[at(h)], t);
      const auto& step = kStep[at(cut.direction[at(h)])];
      place(q.face(t), frame, {cut.face_uv[at(f)][0] + step[0], cut.face_uv[at(f)][1] + step[1]});
      queue.push_back(q.face(t));
    }
  }
  std::unordered_map<std::uint64_t, int> cells;
  for (const auto& uv : cut.face_uv) ++cells[cell_key(uv)];
  for (int f = 0; f < q.num_faces(); ++f) {
    cut.overlap_count[at(f)] = cells[cell_key(cut.face_uv[at(f)])];
  }
}

}  // namespace

CutMesh cut_surface(HalfedgeMesh proxy, const CutParams& params,
                    const std::vector<int>* vanishing_corner) {
  CutMesh cut;
  cut.proxy = std::move(proxy);
  const HalfedgeMesh& q = cut.proxy;
  const int nf = q.num_faces();
  if (nf == 0) throw std::logic_error("cut_surface: empty proxy");
  if (vanishing_corner != nullptr) {
    if (vanishing_corner->size() != at(nf))
      throw std::logic_error("cut_surface: vanishing corners do not match the proxy");
    cut.labels = labels_with_vanishing(q, *vanishing_corner);
  } else {
    cut.labels = label_field(q, params.vanishing);
  }
  std::mt19937_64 rng(params.seed);
  cut.seed_face = pick_seed_face(q, rng);
  cut.motorcycle_edges = motorcycle_graph(q, cut.labels, rng);
  PatchGrower patch(cut, params, rng);
  patch.start(cut.seed_face, seed_frame(q, cut.labels, cut.seed_face));
  const int placed = patch.grow();
  if (placed != nf) {
    throw std::logic_error("cut_surface: proxy is not connected (" + std::to_string(placed) +
                           " of " + std::to_string(nf) + " faces reached)");
  }
  cut.cut_edge.assign(at(q.num_edges()), false);
  for (int h = 0; h < q.num_halfedges(); ++h) {
    const int t = q.twin(h);
    if (t >= 0 && patch.on_boundary(h) && patch.on_boundary(t)) cut.cut_edge[at(q.edge(h))] = true;
  }
  cut.overlap_count.assign(at(nf), 0);
  for (int f = 0; f < nf; ++f) cut.overlap_count[at(f)] = patch.faces_in_cell(cut.face_uv[at(f)]);
  if (params.tighten && tighten_cut(q, cut.labels, cut.cut_edge) > 0) lay_out(cut);
  build_disc(cut);
  cut.arcs = find_arcs(q, cut.labels, cut.cut_edge, params.arc_turn_deg);
  return cut;
}

std::vector<std::vector<int>> cut_edges_at(const HalfedgeMesh& q,
                                           const std::vector<bool>& cut_edge) {
  std::vector<std::vector<int>> incident(at(q.num_vertices()));
  for (int e = 0; e < q.num_edges(); ++e) {
    if (!cut_edge[at(e)]) continue;
    const int h = q.edge_halfedge(e);
    incident[at(q.from(h))].push_back(e);
    incident[at(q.to(h))].push_back(e);
  }
  return incident;
}

bool is_singular(const FieldLabels& labels, int v) {
  return labels.corner_count[at(v)] % 4 != 0;
}

std::vector<CutPath> split_cut(const HalfedgeMesh& q, const std::vector<bool>& cut_edge,
                               const std::vector<std::vector<int>>& incident,
                               const std::function<bool(int)>& node) {
  std::vector<bool> used(at(q.num_edges()), false);
  std::vector<CutPath> paths;
  auto walk = [&](int start, int first_edge) {
    CutPath path{{start}, {}};
    int w = start;
    int e = first_edge;
    while (true) {
      used[at(e)] = true;
      path.edges.push_back(e);
      w = q.to(out_along(q, w, e));
      path.vertices.push_back(w);
      if (w == start || node(w)) break;
      const auto& list = incident[at(w)];
      const int next = list[0] == e ? list[1] : list[0];
      if (used[at(next)]) break;
      e = next;
    }
    paths.push_back(std::move(path));
  };
  for (int v = 0; v < q.num_vertices(); ++v) {
    if (incident[at(v)].empty() || !node(v)) continue;
    for (int e : incident[at(v)]) {
      if (!used[at(e)]) walk(v, e);
    }
  }
  for (int e = 0; e < q.num_edges(); ++e) {  // loops through no node
    if (cut_edge[at(e)] && !used[at(e)]) walk(q.from(q.edge_halfedge(e)), e);
  }
  return paths;
}

int adjacent_opposite_pairs(const HalfedgeMesh& q, const FieldLabels& labels) {
  auto index = [&](int v) { return q.is_boundary_vertex(v) ? 0 : 4 - labels.corner_count[at(v)]; };
  std::vector<bool> paired(at(q.num_vertices()), false);
  int pairs = 0;
  for (int v = 0; v < q.num_vertices(); ++v) {
    if (paired[at(v)] || std::abs(index(v)) != 1) continue;
    for (const int h : q.outgoing(v)) {
      const int w = q.to(h);
      if (!paired[at(w)] && index(w) == -index(v)) {
        paired[at(v)] = paired[at(w)] = true;
        ++pairs;
        break;
      }
    }
  }
  return pairs;
}

std::vector<std::string> verify_cut(const CutMesh& cut) {
  std::vector<std::string> problems;
  const HalfedgeMesh& q = cut.proxy;
  for (int f = 0; f < q.num_faces(); ++f) {
    for (int i = 0; i < q.degree(f); ++i) {
      const int h = q.face_start(f) + i;
      if (cut.direction[at(h)] != halfedge_direction(q, cut.labels, cut.face_frame[at(f)], h)) {
        problems.push_back("face " + std::to_string(f) + ": direction of side " +
                           std::to_string(i) + " does not follow its corners");
      }
    }
  }
  for (int h = 0; h < q.num_halfedges(); ++h) {
    const int t = q.twin(h);
    if (t < 0 || cut.cut_edge[at(q.edge(h))]) continue;
    if ((cut.direction[at(h)] + 2) % 4 != cut.direction[at(t)]) {
      problems.push_back("uncut edge " + std::to_string(q.from(h)) + "-" + std::to_string(q.to(h)) +
                         " has inconsistent labels");
    }
  }
  try {
    const HalfedgeMesh disc(cut.disc);
    if (disc.euler_characteristic() != 1) {
      problems.push_back("disc Euler characteristic is " +
                         std::to_string(disc.euler_characteristic()) + ", not 1");
    }
    if (disc.count_boundary_loops() != 1) {
      problems.push_back("disc has " + std::to_string(disc.count_boundary_loops()) +
                         " boundary loops, not 1");
    }
    // Interior disc vertices: non-vanishing corners around them must be a multiple of 4.
    std::vector<int> corners(at(disc.num_vertices()), 0);
    for (int h = 0; h < disc.num_halfedges(); ++h) {
      if (cut.labels.vanishing_corner[at(disc.face(h))] != disc.corner(h)) {
        ++corners[at(disc.from(h))];
      }
    }
    for (int v = 0; v < disc.num_vertices(); ++v) {
      if (!disc.is_boundary_vertex(v) && corners[at(v)] % 4 != 0) {
        problems.push_back("singular vertex " + std::to_string(cut.disc_source[at(v)]) +
                           " is inside the disc");
      }
    }
  } catch (const std::logic_error& e) {
    problems.push_back(std::string("disc is not an oriented manifold: ") + e.what());
  }
  std::vector<int> covered(at(q.num_edges()), 0);
  std::map<std::pair<int, int>, int> edge_of;
  for (int e = 0; e < q.num_edges(); ++e) {
    const int h = q.edge_halfedge(e);
    edge_of[undirected_edge(q.from(h), q.to(h))] = e;
  }
  for (const CutArc& arc : cut.arcs) {
    for (std::size_t i = 0; i + 1 < arc.vertices.size(); ++i) {
      const int a = arc.vertices[i];
      const int b = arc.vertices[i + 1];
      auto it = edge_of.find(undirected_edge(a, b));
      if (it == edge_of.end()) {
        problems.push_back("arc step " + std::to_string(a) + "-" + std::to_string(b) +
                           " is not an edge");
      } else {
        ++covered[at(it->second)];
      }
    }
  }
  for (int e = 0; e < q.num_edges(); ++e) {
    if (covered[at(e)] != (cut.cut_edge[at(e)] ? 1 : 0)) {
      problems.push_back("edge " + std::to_string(e) + " is covered by " +
                         std::to_string(covered[at(e)]) + " arcs");
    }
  }
  return problems;
}

CutSummary summarize(const CutMesh& cut) {
  CutSummary s;
  s.irregular_vertices = static_cast<int>(cut.labels.irregular_vertices.size());
  for (int e = 0; e < cut.proxy.num_edges(); ++e) {
    if (!cut.cut_edge[at(e)]) continue;
    ++s.cut_edges;
    s.cut_length_mm += cut.proxy.edge_length(cut.proxy.edge_halfedge(e));
  }
  s.arcs = static_cast<int>(cut.arcs.size());
  for (int c : cut.overlap_count) s.overlapping_faces += c > 1 ? 1 : 0;
  s.disc_vertices = static_cast<int>(cut.disc.positions.size());
  try {
    const HalfedgeMesh disc(cut.disc);
    s.boundary_loops = disc.count_boundary_loops();
    s.euler_characteristic = disc.euler_characteristic();
  } catch (const std::logic_error&) {
    s.boundary_loops = -1;
    s.euler_characteristic = 0;
  }
  return s;
}

}  // namespace planner
