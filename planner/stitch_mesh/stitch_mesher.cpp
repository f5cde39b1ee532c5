#include "planner/stitch_mesh/stitch_mesher.hpp"

#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <queue>
#include <set>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "planner/common/index.hpp"
#include "simulators/cloth/sdf.hpp"

namespace planner {
namespace {

using Vec3 = Eigen::Vector3d;

std::uint64_t key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// ---------------------------------------------------------------------------
// Step 1: triangles with a wale direction each, and the row time t.

struct Triangle {
  std::array<int, 3> v{};
  int face = -1;
  Vec3 normal = Vec3::Zero();  // unit
  double area = 0;
  Vec3 wale = Vec3::Zero();  // unit, in the triangle's plane
  Vec3 grad = Vec3::Zero();  // gradient of t
};

Vec3 face_normal(const LabelledDisc& disc, const std::vector<int>& face) {
  Vec3 n = Vec3::Zero();
  for (std::size_t i = 0; i < face.size(); ++i) {
    n += disc.positions[at(face[i])].cross(disc.positions[at(face[(i + 1) % face.size()])]);
  }
  return n;
}

std::vector<Triangle> triangulate(const LabelledDisc& disc) {
  std::vector<Triangle> tris;
  for (std::size_t f = 0; f < disc.faces.size(); ++f) {
    const std::vector<int>& face = disc.faces[f];
    const std::vector<int>& dir = disc.directions[f];
    Vec3 course = Vec3::Zero();
    Vec3 wale = Vec3::Zero();
    for (std::size_t i = 0; i < face.size(); ++i) {
      const Vec3 e = disc.positions[at(face[(i + 1) % face.size()])] - disc.positions[at(face[i])];
      const double len = e.norm();
      if (len <= 0) continue;
      const Vec3 u = e / len;
      switch (dir[i] & 3) {
        case 0:
          course += u;
          break;
        case 1:
          wale += u;
          break;
        case 2:
          course -= u;
          break;
        default:
          wale -= u;
          break;
      }
    }
    // Quads are split along the shorter diagonal, other polygons as a fan.
    std::size_t start = 0;
    if (face.size() == 4) {
      const double d02 = (disc.positions[at(face[0])] - disc.positions[at(face[2])]).norm();
      const double d13 = (disc.positions[at(face[1])] - disc.positions[at(face[3])]).norm();
      if (d13 < d02) start = 1;
    }
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      Triangle t;
      t.v = {face[start], face[(start + i) % face.size()], face[(start + i + 1) % face.size()]};
      t.face = static_cast<int>(f);
      const Vec3 p0 = disc.positions[at(t.v[0])];
      const Vec3 n = (disc.positions[at(t.v[1])] - p0).cross(disc.positions[at(t.v[2])] - p0);
      t.area = 0.5 * n.norm();
      t.normal = t.area > 0 ? Vec3(n.normalized()) : Vec3(face_normal(disc, face).normalized());
      // +v is +u turned a quarter turn counter-clockwise about the normal.
      // Rows run along the course sides, so those set the wale direction;
      // +v sides are only a fallback (a face labelled by its wale sides alone).
      const Vec3 w = wale - wale.dot(t.normal) * t.normal;
      const Vec3 c = course - course.dot(t.normal) * t.normal;
      if (c.norm() > 1e-12) {
        t.wale = t.normal.cross(c.normalized());
      } else if (w.norm() > 1e-12) {
        t.wale = w.normalized();
      }
      tris.push_back(t);
    }
  }
  return tris;
}

// Gradients of the three hat functions of a triangle.
std::array<Vec3, 3> hat_gradients(const LabelledDisc& disc, const Triangle& t) {
  std::array<Vec3, 3> g;
  for (int i = 0; i < 3; ++i) {
    const Vec3 e =
        disc.positions[at(t.v[at((i + 2) % 3)])] - disc.positions[at(t.v[at((i + 1) % 3)])];
    g[at(i)] = t.area > 0 ? Vec3(t.normal.cross(e) / (2 * t.area)) : Vec3::Zero();
  }
  return g;
}

// Least-squares fit of t to the target gradients (Poisson equation with
// the cotangent Laplacian), then straightening fits towards unit speed
// until t settles.
Eigen::VectorXd row_time(const LabelledDisc& disc, std::vector<Triangle>& tris,
                         const StitchMeshParams& params, StitchMeshStats& stats) {
  const int n = static_cast<int>(disc.positions.size());
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<std::array<Vec3, 3>> grads(tris.size());
  double diagonal = 0;
  for (std::size_t k = 0; k < tris.size(); ++k) {
    grads[k] = hat_gradients(disc, tris[k]);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        const double value = tris[k].area * grads[k][at(i)].dot(grads[k][at(j)]);
        entries.emplace_back(tris[k].v[at(i)], tris[k].v[at(j)], value);
        if (i == j) diagonal += value;
      }
    }
  }
  // A tiny mass term fixes the constant; t is shifted to start at 0 later.
  const double epsilon = 1e-9 * diagonal / std::max(1, n);
  for (int i = 0; i < n; ++i) entries.emplace_back(i, i, epsilon);
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(matrix);
  if (solver.info() != Eigen::Success) {
    throw std::runtime_error("row time: the Laplacian could not be factorised");
  }
  std::vector<Vec3> target(tris.size());
  for (std::size_t k = 0; k < tris.size(); ++k) target[k] = tris[k].wale / params.wale_mm;
  Eigen::VectorXd t = Eigen::VectorXd::Zero(n);
  for (int iteration = 0; iteration <= params.straighten_iterations; ++iteration) {
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
    for (std::size_t k = 0; k < tris.size(); ++k) {
      for (int i = 0; i < 3; ++i) {
        rhs[tris[k].v[at(i)]] += tris[k].area * grads[k][at(i)].dot(target[k]);
      }
    }
    const Eigen::VectorXd before = t;
    t = solver.solve(rhs);
    stats.straighten_fits = iteration;
    // t is in rows. The fixed point of the straightening (rows of unit
    // height blended with the labels) is reached when no vertex moves by
    // more than the tolerance; a shift of the whole of t does not count.
    const Eigen::ArrayXd moved = (t - before).array();
    const bool settled =
        iteration > 0 && (moved - moved.mean()).abs().maxCoeff() < params.straighten_tolerance_rows;
    for (std::size_t k = 0; k < tris.size(); ++k) {
      Vec3 g = Vec3::Zero();
      for (int i = 0; i < 3; ++i) g += t[tris[k].v[at(i)]] * grads[k][at(i)];
      tris[k].grad = g;
      // Keep the labelled direction and the fitted one in equal parts, at
      // unit speed: rows follow the labels and keep their height.
      Vec3 d = params.label_weight * tris[k].wale;
      if (g.norm() > 1e-12) d += g.normalized();
      if (d.norm() > 1e-12) target[k] = d.normalized() / params.wale_mm;
    }
    if (settled) break;
  }
  // How far the rows' wale direction strays from the labels, by area.
  double angle_area = 0;
  double area = 0;
  for (const Triangle& tri : tris) {
    if (tri.grad.norm() <= 1e-12 || tri.wale.norm() <= 1e-12) continue;
    angle_area += tri.area * std::acos(std::clamp(tri.grad.normalized().dot(tri.wale), -1.0, 1.0));
    area += tri.area;
  }
  stats.label_deviation_deg = area > 0 ? angle_area / area * 180.0 / std::numbers::pi : 0.0;
  t.array() -= t.minCoeff();
  return t;
}

// Row placement: t mapped monotonically so that rows are wale_mm tall on
// average over each stretch of t. Where t is flat (labels that converge or
// curl keep |grad t| below 1 / wale_mm), equal steps of t would give rows
// that are too tall; there the mapped value rises faster. Per thin slab of t
// the height is its area over the length of its level curve; the mapped
// value at t is the height below t in rows (scaled so there is a whole
// number of rows). Returns the mapped value per vertex; `bands` receives the
// number of rows.
Eigen::VectorXd row_levels(const LabelledDisc& disc, const std::vector<Triangle>& tris,
                           const Eigen::VectorXd& t, const StitchMeshParams& params, int& bands) {
  const double t_max = t.maxCoeff();
  const int slabs = std::max(16, 8 * static_cast<int>(std::ceil(t_max)));
  const double width = t_max > 0 ? t_max / slabs : 1.0;
  std::vector<double> area(at(slabs), 0.0);
  std::vector<double> length(at(slabs + 1), 0.0);  // level curve at slab boundary k
  for (const Triangle& tri : tris) {
    std::array<double, 3> v{};
    std::array<Vec3, 3> p;
    for (int i = 0; i < 3; ++i) {
      v[at(i)] = t[tri.v[at(i)]];
      p[at(i)] = disc.positions[at(tri.v[at(i)])];
    }
    const double lo = std::min({v[0], v[1], v[2]});
    const double hi = std::max({v[0], v[1], v[2]});
    // Area spread evenly over the triangle's range of t.
    const int first = std::clamp(static_cast<int>(std::floor(lo / width)), 0, slabs - 1);
    const int last = std::clamp(static_cast<int>(std::floor(hi / width)), 0, slabs - 1);
    for (int k = first; k <= last; ++k) {
      const double a = std::max(lo, k * width);
      const double b = std::min(hi, (k + 1) * width);
      area[at(k)] += hi > lo ? tri.area * std::max(0.0, b - a) / (hi - lo) : tri.area;
    }
    for (int k = first + 1; k <= last; ++k) {
      const double level = k * width;
      std::vector<Vec3> cross;
      for (int i = 0; i < 3; ++i) {
        const double va = v[at(i)];
        const double vb = v[at((i + 1) % 3)];
        if ((va < level) != (vb < level)) {
          const double s = (level - va) / (vb - va);
          cross.push_back((1 - s) * p[at(i)] + s * p[at((i + 1) % 3)]);
        }
      }
      if (cross.size() == 2) length[at(k)] += (cross[1] - cross[0]).norm();
    }
  }
  // Heights in mm per slab, each at most four times what unit speed gives
  // (near the extremes of t the level curves shrink to points).
  std::vector<double> below(at(slabs + 1), 0.0);
  for (int k = 0; k < slabs; ++k) {
    const double nominal = width * params.wale_mm;
    const double curve = std::max(length[at(k)], length[at(k + 1)]);
    double height = curve > 0 ? area[at(k)] / curve : nominal;
    height = std::clamp(height, 0.25 * nominal, 4.0 * nominal);
    below[at(k + 1)] = below[at(k)] + height;
  }
  const double total = below.back();
  bands = std::max(1, static_cast<int>(std::lround(total / params.wale_mm)));
  const double per_row = total > 0 ? total / bands : 1.0;
  Eigen::VectorXd out(t.size());
  for (int i = 0; i < t.size(); ++i) {
    const double x = std::clamp(t[i] / width, 0.0, static_cast<double>(slabs));
    const int k = std::min(slabs - 1, static_cast<int>(std::floor(x)));
    const double f = x - k;
    out[i] = ((1 - f) * below[at(k)] + f * below[at(k + 1)]) / per_row;
  }
  return out;
}

// A row time with an interior extremum has closed level curves round it:
// the band there is a strip with a hole, which no zip can fill. The
// least-squares fit can make one even on consistent labels (its curl-free
// part need not follow the labels' turning everywhere). This levels t so
// that from every vertex a path runs down to the disc boundary on which t
// never rises, and another on which t never falls: pits are filled to their
// spill level and peaks cut to theirs (morphological reconstruction by
// priority flood from the boundary, alternated until neither changes t).
// Then every component of {t < c} and of {t > c} reaches the boundary, so
// no band has a hole. Returns how many vertices changed.
// The vertices joined to each vertex by a side of the triangles.
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

// Per vertex of the disc: whether it lies on the disc boundary.
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

// Saddles on a level (step 2, docs/stitch-mesh.md "Saddles on a level").
// Near a saddle of t the level curves form an X. A saddle inside a band
// makes a strip with two bottom and two top chains, which split_folds can
// only cut between corners of its chains, far from the saddle, so the
// band's height there ends up in long wale sides; a saddle on the disc
// boundary (half of one, where a cut runs through it, or a fold of the cut
// across the rows) makes a strip whose bottom and top differ in length,
// zipped with a fan of shaping. Held exactly on a level, the saddle is where
// the level curve meets itself or the boundary: the bands on either side are
// strips that meet at the saddle, and no strip needs to go round it.
// The rows are raised or lowered round each saddle among `candidates` by a
// bump, flat up to `inner_mm` from it and falling smoothly to nothing at
// `outer_mm` (along the mesh's edges), so that the saddle's value is a
// whole level; saddles already held stay where they are. A bump is not made
// where it would turn a vertex inside the disc into an extremum, stop a held
// saddle being one, or bring a neighbour of a held saddle onto its level.
// Returns the level per vertex (-1 for none).
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

// ---------------------------------------------------------------------------
// Step 2: pieces of triangles between consecutive levels.

struct Pieces {
  std::vector<Vec3> position;    // piece vertices: input vertices, then level crossings
  std::vector<int> start{0};     // piece p: half-edges start[p] .. start[p+1]-1
  std::vector<int> band;         // per piece
  std::vector<int> tri;          // per piece
  std::vector<int> from;         // per half-edge
  std::vector<int> level;        // per half-edge: level index of an isoline side, else -1
  std::vector<int> source_face;  // per half-edge on the disc boundary: input face, else -1
  std::vector<int> source_side;  // ... and its side
  std::vector<int> twin;         // per half-edge, -1 if none
  std::vector<int> piece;        // per half-edge
  std::vector<bool> pinned;      // per input vertex: a saddle of t held on a level

  int next(int h) const {
    const int p = piece[at(h)];
    return h + 1 < start[at(p) + 1] ? h + 1 : start[at(p)];
  }
  int to(int h) const { return from[at(next(h))]; }
  bool is_pinned(int v) const { return at(v) < pinned.size() && pinned[at(v)]; }
  double length(int h) const { return (position[at(to(h))] - position[at(from[at(h)])]).norm(); }
};

void link_twins(Pieces& out) {
  out.twin.assign(out.from.size(), -1);
  std::unordered_map<std::uint64_t, int> half;
  half.reserve(out.from.size());
  for (int h = 0; h < static_cast<int>(out.from.size()); ++h)
    half[key(out.from[at(h)], out.to(h))] = h;
  for (int h = 0; h < static_cast<int>(out.from.size()); ++h) {
    auto it = half.find(key(out.to(h), out.from[at(h)]));
    if (it != half.end()) out.twin[at(h)] = it->second;
  }
}

// `pin` holds, per input vertex, the level a saddle of t is held on (-1 for
// none): such a vertex lies on its level, a corner of the pieces of both
// bands, and the level curves through it meet there.
Pieces slice(const LabelledDisc& disc, const std::vector<Triangle>& tris, const Eigen::VectorXd& t,
             double spacing, int bands, const std::vector<int>& pin) {
  Pieces out;
  out.position = disc.positions;
  out.pinned.assign(disc.positions.size(), false);
  for (std::size_t v = 0; v < pin.size(); ++v) out.pinned[v] = pin[v] >= 0;
  auto pin_of = [&](int v) { return pin.empty() ? -1 : pin[at(v)]; };
  // Directed input edges that are sides of input faces on the boundary.
  std::unordered_map<std::uint64_t, std::pair<int, int>> directed;
  for (std::size_t f = 0; f < disc.faces.size(); ++f) {
    const std::vector<int>& face = disc.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      directed[key(face[i], face[(i + 1) % face.size()])] = {static_cast<int>(f),
                                                             static_cast<int>(i)};
    }
  }
  // Values a hair off the levels, so no vertex lies on one.
  std::vector<double> value(at(static_cast<int>(t.size())));
  for (int i = 0; i < t.size(); ++i) {
    double x = t[i] / spacing;
    const double nearest = std::round(x);
    if (pin_of(i) >= 0) {
      x = pin_of(i);
    } else if (std::abs(x - nearest) < 1e-6) {
      x = nearest + 2e-6;
    }
    value[at(i)] = x;
  }
  auto band_of = [&](double x) {
    return std::clamp(static_cast<int>(std::floor(x)), 0, bands - 1);
  };
  // A pinned vertex on level k belongs to bands k - 1 and k.
  auto lowest_band = [&](int v) { return pin_of(v) >= 0 ? pin_of(v) - 1 : band_of(value[at(v)]); };
  auto highest_band = [&](int v) { return pin_of(v) >= 0 ? pin_of(v) : band_of(value[at(v)]); };
  std::map<std::tuple<int, int, int>, int> crossings;
  auto get_crossing = [&](int a, int b, int level) {
    const int lo = std::min(a, b);
    const int hi = std::max(a, b);
    auto [it, inserted] = crossings.emplace(std::make_tuple(lo, hi, level), 0);
    if (inserted) {
      const double s = (level - value[at(lo)]) / (value[at(hi)] - value[at(lo)]);
      it->second = static_cast<int>(out.position.size());
      out.position.push_back((1 - s) * disc.positions[at(lo)] + s * disc.positions[at(hi)]);
    }
    return it->second;
  };
  struct Corner {
    int vertex;
    int edge;     // triangle side (0..2) of a crossing, -1 for an input vertex
    int level;    // of a crossing or a pinned vertex
    bool pinned;  // an input vertex on `level`
  };
  for (std::size_t k = 0; k < tris.size(); ++k) {
    const Triangle& tri = tris[k];
    int lo = bands;
    int hi = -1;
    for (int v : tri.v) {
      lo = std::min(lo, lowest_band(v));
      hi = std::max(hi, highest_band(v));
    }
    for (int b = lo; b <= hi; ++b) {
      std::vector<Corner> corners;
      for (int i = 0; i < 3; ++i) {
        const int p = tri.v[at(i)];
        const int q = tri.v[at((i + 1) % 3)];
        if (lowest_band(p) == b || highest_band(p) == b) {
          corners.push_back({p, -1, pin_of(p), pin_of(p) >= 0});
        }
        const double vp = value[at(p)];
        const double vq = value[at(q)];
        // Levels b (bottom) and b + 1 (top) crossed by p -> q, in travel
        // order (not the level of a pinned end: the curve passes through it).
        std::vector<int> levels;
        for (int level : {b, b + 1}) {
          if (level <= 0 || level >= bands || level == pin_of(p) || level == pin_of(q)) continue;
          if ((vp < level) != (vq < level)) levels.push_back(level);
        }
        if (levels.size() == 2 && vp > vq) std::swap(levels[0], levels[1]);
        for (int level : levels) corners.push_back({get_crossing(p, q, level), i, level, false});
      }
      if (corners.size() < 3) continue;
      const int piece = static_cast<int>(out.band.size());
      out.band.push_back(b);
      out.tri.push_back(static_cast<int>(k));
      for (std::size_t c = 0; c < corners.size(); ++c) {
        const Corner& a = corners[c];
        const Corner& z = corners[(c + 1) % corners.size()];
        out.from.push_back(a.vertex);
        out.piece.push_back(piece);
        int level = -1;
        int side = -1;  // triangle side the half-edge lies on
        const bool a_on = a.edge >= 0 || a.pinned;
        const bool z_on = z.edge >= 0 || z.pinned;
        if (a_on && z_on && a.level == z.level && !(a.pinned && z.pinned) &&
            (a.pinned || z.pinned || a.edge != z.edge)) {
          level = a.level;
        } else if (a.edge >= 0) {
          side = a.edge;
        } else if (z.edge >= 0) {
          side = z.edge;
        } else {
          // Two input vertices: the side that starts at a.
          for (int i = 0; i < 3; ++i) {
            if (tri.v[at(i)] == a.vertex) side = i;
          }
        }
        out.level.push_back(level);
        int source_face = -1;
        int source_side = -1;
        if (side >= 0) {
          const int p = tri.v[at(side)];
          const int q = tri.v[at((side + 1) % 3)];
          if (directed.find(key(q, p)) == directed.end()) {
            auto it = directed.find(key(p, q));
            if (it != directed.end()) {
              source_face = it->second.first;
              source_side = it->second.second;
            }
          }
        }
        out.source_face.push_back(source_face);
        out.source_side.push_back(source_side);
      }
      out.start.push_back(static_cast<int>(out.from.size()));
    }
  }
  link_twins(out);
  return out;
}

// The larger t at which a + t e is `radius` from `centre`, or nullopt when
// the line misses that sphere (or e is zero).
std::optional<double> sphere_exit(const Vec3& a, const Vec3& e, const Vec3& centre, double radius) {
  const Vec3 g = a - centre;
  const double ee = e.dot(e);
  const double ge = g.dot(e);
  const double root = ge * ge - ee * (g.dot(g) - radius * radius);
  if (!(ee > 0) || root < 0) return std::nullopt;
  return (-ge + std::sqrt(root)) / ee;
}

// A point to add on a half-edge of the disc boundary: at parameter s from its start.
struct HalfedgeSplit {
  int halfedge = -1;
  double s = 0;
  Vec3 point = Vec3::Zero();
};

// The pieces with points added on boundary half-edges (each split half-edge
// becomes two with the same origin; boundary half-edges have no twin).
Pieces split_halfedges(const Pieces& in, std::vector<HalfedgeSplit> splits) {
  std::sort(splits.begin(), splits.end(), [](const HalfedgeSplit& a, const HalfedgeSplit& b) {
    return std::tie(a.halfedge, a.s) < std::tie(b.halfedge, b.s);
  });
  Pieces out;
  out.position = in.position;
  out.band = in.band;
  out.tri = in.tri;
  out.pinned = in.pinned;
  out.start.assign(1, 0);
  std::size_t next_split = 0;
  for (std::size_t p = 0; p + 1 < in.start.size(); ++p) {
    for (int h = in.start[p]; h < in.start[p + 1]; ++h) {
      auto push = [&](int from) {
        out.from.push_back(from);
        out.level.push_back(in.level[at(h)]);
        out.source_face.push_back(in.source_face[at(h)]);
        out.source_side.push_back(in.source_side[at(h)]);
        out.piece.push_back(static_cast<int>(p));
      };
      push(in.from[at(h)]);
      while (next_split < splits.size() && splits[next_split].halfedge == h) {
        out.position.push_back(splits[next_split].point);
        push(static_cast<int>(out.position.size()) - 1);
        ++next_split;
      }
    }
    out.start.push_back(static_cast<int>(out.from.size()));
  }
  link_twins(out);
  return out;
}

int find(std::vector<int>& parent, int x) {
  while (parent[at(x)] != x) {
    parent[at(x)] = parent[at(parent[at(x)])];
    x = parent[at(x)];
  }
  return x;
}

// ---------------------------------------------------------------------------
// Steps 3-4: chains of each strip, stitch vertices, faces.

// A saddle split (split_folds) takes a splitting edge up to this many wales
// longer to make strips whose bottom and top lengths differ by one unit of
// |ln(bottom / top)| less. 1 left the fans of `teddy-quad`; 2 and 4 gave the
// same stitch meshes on the 38 shared meshes (docs/stitch-mesh.md, "Saddle
// splits").
constexpr double kSplitBalance = 2.0;

// Saddles on a level (pin_saddles) are looked for in X-shaped strips and in
// strips whose bottom and top chains differ in length by more than this
// ratio, the longer at least kLopsidedWales wales long. 1.3 to 1.5 and 10
// to 20 wales gave 37 of the 38 shared meshes meeting every target size;
// without the length, jagged cut boundaries lost stitches' shape
// (docs/stitch-mesh.md, "Saddles on a level").
constexpr double kLopsidedRatio = 1.3;
constexpr double kLopsidedWales = 20.0;

// A side is counted as the right length within 15% of its target. A boundary
// run's sides are placed so that fewest fall outside (each costs this much
// more than its squared relative error): with 1, 0.05 (the zip's
// outside_cost) or points every course / 8, 16 or 32, all 38 shared meshes
// met every figure (docs/stitch-mesh.md, step 3).
constexpr double kLengthTolerance = 0.15;
constexpr double kBoundaryOutsideCost = 1.0;

// The cost of a side whose length is off its target by the fraction `off`:
// its square, and `outside` more if it is over kLengthTolerance.
double length_cost(double off, double outside) {
  return off * off + (std::abs(off) > kLengthTolerance ? outside : 0.0);
}

enum class Side : std::uint8_t { Low, High, Wale };

struct Run {
  Side side = Side::Wale;
  bool level = false;          // an isoline (shared with the next strip), not the disc boundary
  std::vector<int> halfedges;  // in loop order
  double length = 0;
};

struct Chain {
  Side side = Side::Wale;
  std::vector<Run> runs;
};

double chain_length(const Chain& chain) {
  double length = 0;
  for (const Run& r : chain.runs) length += r.length;
  return length;
}

// A chain of disc boundary only (no level curve).
bool boundary_only(const Chain& chain) {
  return std::none_of(chain.runs.begin(), chain.runs.end(), [](const Run& r) { return r.level; });
}

// Neighbouring boundary runs of a chain are one stretch of boundary: join
// them into one run (isoline runs stay apart).
void join_boundary_runs(Chain& chain) {
  std::vector<Run> joined;
  for (Run& r : chain.runs) {
    if (!joined.empty() && !joined.back().level && !r.level) {
      joined.back().halfedges.insert(joined.back().halfedges.end(), r.halfedges.begin(),
                                     r.halfedges.end());
      joined.back().length += r.length;
    } else {
      joined.push_back(std::move(r));
    }
  }
  chain.runs = std::move(joined);
}

struct Builder {
  const LabelledDisc& disc;
  const StitchMeshParams& params;
  const Pieces& pieces;
  StitchMesh mesh;
  std::unordered_map<int, int> anchor;  // piece vertex -> stitch vertex
  // Level curve (by any of its undirected piece edges) -> its stitch vertices
  // in the order of the first strip that sampled it, and that order's first piece vertex.
  std::unordered_map<std::uint64_t, int> curve_of_edge;
  std::vector<std::vector<int>> curve_samples;
  std::vector<int> curve_first;
  std::vector<std::string> problems;
  StitchMeshStats stats;
  // Bottom sides (as the row above walks them) of increases and decreases.
  std::unordered_set<std::uint64_t> shaped_below;
  // Course-out sides (as the row above walks them) -> the face below.
  std::unordered_map<std::uint64_t, std::size_t> face_below;
  // Level curve (by any of its undirected piece edges) -> fewest segments.
  std::unordered_map<std::uint64_t, int> min_segments;
  // Points to add on boundary half-edges, for row ends (end_rows_in_wale_sides).
  std::vector<HalfedgeSplit> tip_splits;

  int stitch_vertex(int piece_vertex) {
    auto [it, inserted] = anchor.emplace(piece_vertex, 0);
    if (inserted) {
      it->second = static_cast<int>(mesh.positions.size());
      mesh.positions.push_back(pieces.position[at(piece_vertex)]);
    }
    return it->second;
  }

  std::int32_t arc_of(int h) const {
    const int f = pieces.source_face[at(h)];
    if (f < 0 || disc.arcs.empty()) return kNoArc;
    return disc.arcs[at(f)][at(pieces.source_side[at(h)])];
  }

  // A boundary run's length in straight steps of course_mm: a jagged cut
  // boundary is longer along its edges than across the stitches it holds
  // (docs/stitch-mesh.md, step 3).
  double straight_length(const Run& run) const {
    const std::vector<double> along = lengths_along(run.halfedges);
    const std::vector<double> walk = straight_walk(run.halfedges, along, params.course_mm);
    const Vec3 last = walk.empty() ? pieces.position[at(pieces.from[at(run.halfedges.front())])]
                                   : point_along(run.halfedges, along, walk.back());
    const Vec3 end = pieces.position[at(pieces.to(run.halfedges.back()))];
    return static_cast<double>(walk.size()) * params.course_mm + (end - last).norm();
  }

  // Segments of a run `length` long: one per ~course_mm.
  int auto_count(double length) const {
    return std::max(1, static_cast<int>(std::lround(length / params.course_mm)));
  }

  // Arc length at the end of each half-edge of a polyline (0 first).
  std::vector<double> lengths_along(const std::vector<int>& halfedges) const {
    std::vector<double> along{0};
    for (int h : halfedges) {
      along.push_back(along.back() + pieces.length(h));
    }
    return along;
  }

  // The point of a polyline at arc length t.
  Vec3 point_along(const std::vector<int>& halfedges, const std::vector<double>& along,
                   double t) const {
    std::size_t k = 0;
    while (k + 1 < halfedges.size() && along[k + 1] < t) ++k;
    const double span = along[k + 1] - along[k];
    const double w = span > 0 ? std::clamp((t - along[k]) / span, 0.0, 1.0) : 0.0;
    return (1 - w) * pieces.position[at(pieces.from[at(halfedges[k])])] +
           w * pieces.position[at(pieces.to(halfedges[k]))];
  }

  // Arc lengths of the points of a walk along a polyline that steps `step`
  // in a straight line each time from its start.
  std::vector<double> straight_walk(const std::vector<int>& halfedges,
                                    const std::vector<double>& along, double step) const {
    std::vector<double> out;
    Vec3 last = pieces.position[at(pieces.from[at(halfedges.front())])];
    for (std::size_t k = 0; k < halfedges.size(); ++k) {
      const Vec3 a = pieces.position[at(pieces.from[at(halfedges[k])])];
      const Vec3 e = pieces.position[at(pieces.to(halfedges[k]))] - a;
      double from = 0;
      while (true) {
        // The farther point of this half-edge `step` from the last one.
        const std::optional<double> exit = sphere_exit(a, e, last, step);
        if (!exit) break;
        const double t = *exit;
        if (t > 1 || t < from) break;
        last = a + t * e;
        from = t;
        out.push_back(along[k] + t * (along[k + 1] - along[k]));
      }
    }
    return out;
  }

  // Arc lengths of the n - 1 inner points of a boundary run cut into n
  // straight sides as close to course_mm as can be: fewest sides off by more
  // than 15%, then the least squared relative deviation (dynamic programming
  // over points every course_mm / 16 along the run). A jagged or folded cut
  // boundary is longer along its edges than across the stitches it holds:
  // the sides are its chords (docs/stitch-mesh.md, step 3).
  std::vector<double> straight_sides(const std::vector<int>& halfedges,
                                     const std::vector<double>& along, int n) const {
    const double spacing = params.course_mm / 16;
    std::vector<Vec3> point;
    std::vector<double> arc;
    for (std::size_t k = 0; k < halfedges.size(); ++k) {
      const Vec3 a = pieces.position[at(pieces.from[at(halfedges[k])])];
      const Vec3 b = pieces.position[at(pieces.to(halfedges[k]))];
      const int parts =
          std::max(1, static_cast<int>(std::ceil((along[k + 1] - along[k]) / spacing)));
      for (int i = 0; i < parts; ++i) {
        const double w = static_cast<double>(i) / parts;
        point.push_back((1 - w) * a + w * b);
        arc.push_back(along[k] + w * (along[k + 1] - along[k]));
      }
    }
    point.push_back(pieces.position[at(pieces.to(halfedges.back()))]);
    arc.push_back(along.back());
    const std::size_t m = point.size();
    // A side spans at most this much of the run's length.
    const double reach = 3 * std::max(params.course_mm, along.back() / n);
    auto cost = [&](const Vec3& a, const Vec3& b) {
      return length_cost((a - b).norm() / params.course_mm - 1, kBoundaryOutsideCost);
    };
    constexpr double kNone = std::numeric_limits<double>::infinity();
    std::vector<double> previous(m, kNone);
    std::vector<double> current(m, kNone);
    std::vector<std::uint32_t> from(static_cast<std::size_t>(n) * m, 0);
    previous[0] = 0;
    for (int k = 1; k <= n; ++k) {
      std::fill(current.begin(), current.end(), kNone);
      std::size_t first = 0;
      for (std::size_t j = 1; j < m; ++j) {
        while (arc[j] - arc[first] > reach) ++first;
        for (std::size_t i = first; i < j; ++i) {
          if (previous[i] == kNone) continue;
          const double c = previous[i] + cost(point[i], point[j]);
          if (c < current[j]) {
            current[j] = c;
            from[static_cast<std::size_t>(k - 1) * m + j] = static_cast<std::uint32_t>(i);
          }
        }
      }
      std::swap(previous, current);
    }
    if (previous[m - 1] == kNone) return {};
    std::vector<double> out(static_cast<std::size_t>(n - 1));
    std::size_t j = m - 1;
    for (int k = n; k > 1; --k) {
      j = from[static_cast<std::size_t>(k - 1) * m + j];
      out[at(k - 2)] = arc[j];
    }
    return out;
  }

  // Stitch vertices along a run, n segments (arcs[i] for segment i): evenly
  // along it, or with `straight` (a boundary run) in n straight sides as
  // close to course_mm as can be (straight_sides), so the stitches along a
  // jagged boundary are as wide as the others.
  std::vector<int> sample(const std::vector<int>& halfedges, std::vector<std::int32_t>* arcs, int n,
                          bool straight = false) {
    const std::vector<double> along = lengths_along(halfedges);
    const double total = along.back();
    std::vector<double> at_length;
    for (int i = 1; i < n; ++i) at_length.push_back(total * i / n);
    if (straight && n > 1) {
      std::vector<double> sides = straight_sides(halfedges, along, n);
      if (!sides.empty()) at_length = std::move(sides);
    }
    std::vector<int> out{stitch_vertex(pieces.from[at(halfedges.front())])};
    for (int i = 1; i <= n; ++i) {
      const double s = i < n ? at_length[at(i - 1)] : total;
      const double mid = 0.5 * ((i > 1 ? at_length[at(i - 2)] : 0.0) + s);
      std::size_t m = 0;
      while (m + 1 < halfedges.size() && along[m + 1] < mid) ++m;
      if (arcs != nullptr) arcs->push_back(arc_of(halfedges[m]));
      if (i == n) {
        out.push_back(stitch_vertex(pieces.to(halfedges.back())));
        break;
      }
      out.push_back(static_cast<int>(mesh.positions.size()));
      mesh.positions.push_back(point_along(halfedges, along, s));
    }
    return out;
  }

  std::uint64_t undirected(int h) const {
    const int a = pieces.from[at(h)];
    const int b = pieces.to(h);
    return key(std::min(a, b), std::max(a, b));
  }

  // A level curve is sampled once (by the strip below it, with n segments);
  // the strip above reuses the samples.
  const std::vector<int>* sampled_curve(const Run& run) const {
    auto it = curve_of_edge.find(undirected(run.halfedges.front()));
    return it == curve_of_edge.end() ? nullptr : &curve_samples[at(it->second)];
  }

  std::vector<int> level_samples(const Run& run, int n) {
    auto it = curve_of_edge.find(undirected(run.halfedges.front()));
    if (it == curve_of_edge.end()) {
      const int id = static_cast<int>(curve_samples.size());
      curve_samples.push_back(sample(run.halfedges, nullptr, n));
      curve_first.push_back(pieces.from[at(run.halfedges.front())]);
      for (int h : run.halfedges) curve_of_edge[undirected(h)] = id;
      return curve_samples.back();
    }
    std::vector<int> samples = curve_samples[at(it->second)];
    if (curve_first[at(it->second)] != pieces.from[at(run.halfedges.front())]) {
      std::reverse(samples.begin(), samples.end());
    }
    return samples;
  }

  // Fewest segments a run may have: one, or for a level curve what the strip
  // above it needs (plan_minimums).
  int minimum(const Run& run) const {
    if (!run.level) return 1;
    auto it = min_segments.find(undirected(run.halfedges.front()));
    return it == min_segments.end() ? 1 : it->second;
  }

  // Segments per run of a chain: fixed for level curves sampled already,
  // else ~length / course_mm.
  std::vector<int> run_counts(const Chain& chain) const {
    std::vector<int> counts;
    for (const Run& run : chain.runs) {
      const std::vector<int>* done = run.level ? sampled_curve(run) : nullptr;
      counts.push_back(
          done != nullptr
              ? static_cast<int>(done->size()) - 1
              : std::max(minimum(run), auto_count(run.level ? run.length : straight_length(run))));
    }
    return counts;
  }

  // Before any strip is zipped: a strip whose bottom is one level curve and
  // whose top needs more sides (one for each run, or the run's own minimum)
  // than twice that curve's sides can feed asks the strip below to sample the
  // curve more finely. Called from the top row down, so a minimum passes
  // down through as many rows as need it.
  void plan_minimums(const std::vector<Chain>& loop) {
    const Chain* low = nullptr;
    int lows = 0;
    int highs = 0;
    int top_runs = 0;
    for (const Chain& c : loop) {
      if (c.side == Side::Low) {
        ++lows;
        low = &c;
      } else if (c.side == Side::High) {
        ++highs;
        top_runs = 0;
        for (const Run& run : c.runs) top_runs += minimum(run);
      }
    }
    if (lows != 1 || highs != 1 || low->runs.size() != 1 || !low->runs.front().level) return;
    int shared = 2;
    for (const Chain& c : loop) shared -= c.side == Side::Wale;
    shared = std::max(0, shared);
    const int need = shared + (std::max(0, top_runs - shared) + 1) / 2;
    if (need <= 1) return;
    for (int h : low->runs.front().halfedges) {
      int& m = min_segments[undirected(h)];
      m = std::max(m, need);
    }
  }

  // Changes the free runs' counts (not fixed ones) so they sum to `total`
  // where possible, in proportion to their length; each keeps its minimum.
  void rescale(const Chain& chain, const std::vector<bool>& fixed, std::vector<int>& counts,
               int total) const {
    int current = std::accumulate(counts.begin(), counts.end(), 0);
    for (int guard = 0; current != total && guard < 100000; ++guard) {
      // Add to the free run with the longest segments, or take from the one
      // with the shortest.
      int best = -1;
      double best_value = 0;
      for (std::size_t r = 0; r < counts.size(); ++r) {
        if (fixed[r]) continue;
        const double per = chain.runs[r].length / counts[r];
        if (current < total) {
          if (best < 0 || per > best_value) best = static_cast<int>(r), best_value = per;
        } else if (counts[r] > minimum(chain.runs[r])) {
          if (best < 0 || per < best_value) best = static_cast<int>(r), best_value = per;
        }
      }
      if (best < 0) return;
      counts[at(best)] += current < total ? 1 : -1;
      current += current < total ? 1 : -1;
    }
  }

  std::vector<bool> fixed_runs(const Chain& chain) const {
    std::vector<bool> fixed;
    for (const Run& run : chain.runs) fixed.push_back(run.level && sampled_curve(run) != nullptr);
    return fixed;
  }

  // Vertices of a course chain and the arcs of its segments.
  std::vector<int> chain_vertices(const Chain& chain, const std::vector<int>& counts,
                                  std::vector<std::int32_t>& arcs,
                                  std::vector<bool>* on_level = nullptr) {
    std::vector<int> out;
    for (std::size_t r = 0; r < chain.runs.size(); ++r) {
      const Run& run = chain.runs[r];
      std::vector<std::int32_t> run_arcs;
      std::vector<int> v;
      if (run.level) {
        v = level_samples(run, counts[r]);
        run_arcs.assign(v.size() - 1, kNoArc);
      } else {
        v = sample(run.halfedges, &run_arcs, counts[r], /*straight=*/true);
      }
      if (!out.empty() && out.back() == v.front()) {
        out.insert(out.end(), v.begin() + 1, v.end());
      } else {
        if (!out.empty()) {
          throw std::logic_error("stitch meshing: chain runs do not meet");
        }
        out = v;
      }
      arcs.insert(arcs.end(), run_arcs.begin(), run_arcs.end());
      if (on_level != nullptr) on_level->insert(on_level->end(), run_arcs.size(), run.level);
    }
    return out;
  }

  void add_face(std::vector<int> vertices, std::vector<EdgeRole> roles,
                std::vector<std::int32_t> arcs) {
    StitchFace face;
    face.vertices.assign(vertices.begin(), vertices.end());
    face.roles = std::move(roles);
    face.arcs = std::move(arcs);
    const std::optional<FaceType> type = classify_roles(face.roles);
    if (!type) ++stats.invalid_faces;
    face.type = type.value_or(FaceType::Knit);
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      if (face.roles[i] == EdgeRole::CourseOut) {
        face_below[key(static_cast<int>(face.vertices[(i + 1) % face.vertices.size()]),
                       static_cast<int>(face.vertices[i]))] = mesh.faces.size();
      }
    }
    if (face.type == FaceType::Increase || face.type == FaceType::Decrease) {
      // Remember the pentagon's top sides, as the row above walks them.
      const std::size_t n = face.vertices.size();
      for (std::size_t i = 0; i < n; ++i) {
        if (face.roles[i] == EdgeRole::CourseOut) {
          shaped_below.insert(key(static_cast<int>(face.vertices[(i + 1) % n]),
                                  static_cast<int>(face.vertices[i])));
        }
      }
    }
    mesh.faces.push_back(std::move(face));
  }

  std::vector<Run> loop_runs(const std::vector<int>& loop, int band, const Eigen::VectorXd&,
                             const std::vector<Triangle>& tris) {
    std::vector<Run> runs;
    for (int h : loop) {
      Run piece;
      const double length = pieces.length(h);
      const int level = pieces.level[at(h)];
      if (level >= 0) {
        piece.level = true;
        piece.side = level == band ? Side::Low : Side::High;
      } else {
        // §6.2: the side's direction against the row direction.
        const Triangle& tri = tris[at(pieces.tri[at(pieces.piece[at(h)])])];
        const Vec3 e = pieces.position[at(pieces.to(h))] - pieces.position[at(pieces.from[at(h)])];
        const Vec3 outward = e.cross(tri.normal);
        const double c = tri.grad.norm() > 0 && outward.norm() > 0
                             ? tri.grad.normalized().dot(outward.normalized())
                             : 0.0;
        piece.side = c > params.side_cosine    ? Side::High
                     : c < -params.side_cosine ? Side::Low
                                               : Side::Wale;
      }
      // A level curve through a pinned saddle is two runs there, so the
      // saddle is a stitch vertex of both (it is where four runs meet).
      const bool breaks = piece.level && pieces.is_pinned(pieces.from[at(h)]);
      if (!runs.empty() && runs.back().level == piece.level && runs.back().side == piece.side &&
          !breaks) {
        runs.back().halfedges.push_back(h);
        runs.back().length += length;
      } else {
        piece.halfedges.push_back(h);
        piece.length = length;
        runs.push_back(std::move(piece));
      }
    }
    if (runs.size() > 1 && runs.front().level == runs.back().level &&
        runs.front().side == runs.back().side &&
        !(runs.front().level &&
          pieces.is_pinned(pieces.from[at(runs.front().halfedges.front())]))) {
      runs.back().halfedges.insert(runs.back().halfedges.end(), runs.front().halfedges.begin(),
                                   runs.front().halfedges.end());
      runs.back().length += runs.front().length;
      runs.erase(runs.begin());
    }
    return runs;
  }

  // Groups runs into chains: short boundary course runs become wale; a wale
  // run between two chains of one kind joins them.
  std::vector<Chain> chains(std::vector<Run> runs) {
    for (Run& run : runs) {
      if (!run.level && run.side != Side::Wale && run.length < 0.5 * params.course_mm) {
        run.side = Side::Wale;
      }
    }
    std::vector<Chain> out;
    auto merge_same = [&]() {
      std::vector<Chain> merged;
      for (Chain& c : out) {
        if (!merged.empty() && merged.back().side == c.side) {
          for (Run& r : c.runs) merged.back().runs.push_back(std::move(r));
        } else {
          merged.push_back(std::move(c));
        }
      }
      if (merged.size() > 1 && merged.front().side == merged.back().side) {
        for (Run& r : merged.front().runs) merged.back().runs.push_back(std::move(r));
        merged.erase(merged.begin());
      }
      out = std::move(merged);
    };
    for (Run& run : runs) {
      Chain c;
      c.side = run.side;
      c.runs.push_back(std::move(run));
      out.push_back(std::move(c));
    }
    merge_same();
    bool changed = true;
    while (changed && out.size() > 2) {
      changed = false;
      for (std::size_t i = 0; i < out.size(); ++i) {
        const Chain& before = out[(i + out.size() - 1) % out.size()];
        const Chain& after = out[(i + 1) % out.size()];
        if (out[i].side == Side::Wale && before.side == after.side) {
          out[i].side = before.side;
          changed = true;
        }
      }
      merge_same();
      // A short stretch of boundary facing up or down between chains of the
      // other kind is a step of a jagged cut, not a row end: a wale side.
      if (!changed && out.size() > 2) {
        for (Chain& c : out) {
          if (c.side == Side::Wale) continue;
          if (boundary_only(c) && chain_length(c) < params.step_mm_factor * params.wale_mm) {
            c.side = Side::Wale;
            changed = true;
            break;
          }
        }
        merge_same();
      }
      // Still more than one chain of a kind: the boundary folds against the
      // rows. The shortest boundary-only course chain gives way first (it
      // joins its neighbours' kind, or becomes a side).
      int lows = 0;
      for (const Chain& c : out) lows += c.side == Side::Low;
      if (!changed && lows > 1) {
        double shortest = std::numeric_limits<double>::infinity();
        Chain* pick = nullptr;
        for (Chain& c : out) {
          if (c.side == Side::Wale) continue;
          const double length = chain_length(c);
          if (boundary_only(c) && length < shortest) {
            shortest = length;
            pick = &c;
          }
        }
        if (pick != nullptr) {
          pick->side = Side::Wale;
          changed = true;
        }
        merge_same();
      }
    }
    // Neighbouring boundary runs of one chain are one stretch of boundary.
    for (Chain& c : out) join_boundary_runs(c);
    // Short boundary runs at the ends of a course chain beside a wale side
    // join the wale side: a wale edge, not a sliver course edge.
    for (std::size_t i = 0; i < out.size(); ++i) {
      if (out[i].side != Side::Wale) continue;
      Chain& before = out[(i + out.size() - 1) % out.size()];
      Chain& after = out[(i + 1) % out.size()];
      if (before.side != Side::Wale && before.runs.size() > 1 && !before.runs.back().level &&
          before.runs.back().length < 0.5 * params.course_mm) {
        out[i].runs.insert(out[i].runs.begin(), std::move(before.runs.back()));
        before.runs.pop_back();
      }
      if (after.side != Side::Wale && after.runs.size() > 1 && !after.runs.front().level &&
          after.runs.front().length < 0.5 * params.course_mm) {
        out[i].runs.push_back(std::move(after.runs.front()));
        after.runs.erase(after.runs.begin());
      }
    }
    end_rows_in_wale_sides(out);
    return out;
  }

  // Splits run `r` after its first `count` half-edges.
  static std::pair<Run, Run> split_run(const Run& r, std::size_t count, const Pieces& pieces) {
    Run a;
    Run b;
    a.side = b.side = r.side;
    a.level = b.level = r.level;
    for (std::size_t k = 0; k < r.halfedges.size(); ++k) {
      const int h = r.halfedges[k];
      Run& into = k < count ? a : b;
      into.halfedges.push_back(h);
      into.length += pieces.length(h);
    }
    return {a, b};
  }

  // §6.3, row ends. A row that ends where its bottom and top chains meet on
  // the boundary (a wedge: the boundary crosses the rows obliquely) ends
  // instead in a wale side: the stretch of the oblique boundary next to the
  // point, `tip_side_wales` (0.9) wales long in a straight line. The faces
  // before it lean towards the boundary and keep their height, where a wedge
  // would shrink them to nothing and fan increases or decreases into its
  // point (docs/stitch-mesh.md, step 4, "Row ends"). A wale side on the
  // boundary shorter than that (the boundary turns from along the wale to
  // oblique within the row) is lengthened the same way. The stretch ends at
  // a piece vertex; where none lies at that distance, `tip_splits` receives
  // the point to add (the caller adds them and makes the chains again).
  void end_rows_in_wale_sides(std::vector<Chain>& out) {
    if (!(params.tip_side_wales > 0) || out.size() < 2) return;
    const double length = params.tip_side_wales * params.wale_mm;
    const double tolerance = 0.02 * params.wale_mm;
    // Where boundary run r, walked forward from its front or backward from
    // its back, is `length` from `origin` in a straight line: the number of
    // half-edges before that vertex, or nullopt (a split point to add is
    // recorded when the distance is reached inside a half-edge).
    auto cut_at = [&](const Vec3& origin, const Run& r,
                      bool from_front) -> std::optional<std::size_t> {
      if (r.level || r.length < length - tolerance) return std::nullopt;
      const std::size_t n = r.halfedges.size();
      for (std::size_t k = 0; k < n; ++k) {
        const int h = from_front ? r.halfedges[k] : r.halfedges[n - 1 - k];
        const Vec3 near = pieces.position[at(from_front ? pieces.from[at(h)] : pieces.to(h))];
        const Vec3 far = pieces.position[at(from_front ? pieces.to(h) : pieces.from[at(h)])];
        const double d_far = (far - origin).norm();
        if (d_far < length - tolerance) continue;
        if (std::abs(d_far - length) <= tolerance) {
          if (k + 1 == n) return std::nullopt;  // the whole run: nothing left of it
          return from_front ? k + 1 : n - 1 - k;
        }
        if (std::abs((near - origin).norm() - length) <= tolerance && k > 0) {
          return from_front ? k : n - k;
        }
        // The point of this half-edge at that distance.
        const Vec3 e = far - near;
        if (const std::optional<double> exit = sphere_exit(near, e, origin, length)) {
          const double s = std::clamp(*exit, 0.0, 1.0);
          // Parameter from the half-edge's own start.
          tip_splits.push_back({h, from_front ? s : 1.0 - s, near + s * e});
        }
        return std::nullopt;
      }
      return std::nullopt;
    };
    // Takes the stretch from the back of `a` (origin_a: the point its
    // distance is measured from) or the front of `b`, the longer first.
    // Returns the stretch as a wale run, or nullopt.
    auto take = [&](Chain& a, Chain& b, const Vec3& origin_a, const Vec3& origin_b,
                    bool& from_b) -> std::optional<Run> {
      const bool prefer_b = b.runs.front().length >= a.runs.back().length;
      for (int attempt = 0; attempt < 2; ++attempt) {
        const bool use_b = (attempt == 0) == prefer_b;
        if (use_b) {
          if (auto cut = cut_at(origin_b, b.runs.front(), true)) {
            auto [near, far] = split_run(b.runs.front(), *cut, pieces);
            b.runs.front() = std::move(far);
            near.side = Side::Wale;
            from_b = true;
            return near;
          }
        } else if (auto cut = cut_at(origin_a, a.runs.back(), false)) {
          auto [far, near] = split_run(a.runs.back(), *cut, pieces);
          a.runs.back() = std::move(far);
          near.side = Side::Wale;
          from_b = false;
          return near;
        }
      }
      return std::nullopt;
    };
    auto point = [&](int vertex) { return pieces.position[at(vertex)]; };
    for (std::size_t i = 0; i < out.size(); ++i) {
      Chain& c = out[i];
      if (c.side != Side::Wale) {
        // A point where this chain meets the next course chain.
        Chain& b = out[(i + 1) % out.size()];
        if (&c == &b || b.side == Side::Wale || b.side == c.side) continue;
        const Vec3 tip = point(pieces.from[at(b.runs.front().halfedges.front())]);
        bool from_b = false;
        std::optional<Run> stretch = take(c, b, tip, tip, from_b);
        if (!stretch) continue;
        Chain wale_side;
        wale_side.side = Side::Wale;
        wale_side.runs.push_back(std::move(*stretch));
        ++stats.tip_sides;
        out.insert(out.begin() + static_cast<std::ptrdiff_t>(i) + 1, std::move(wale_side));
        ++i;
        continue;
      }
      // A short wale side on the boundary between two course chains.
      Chain& a = out[(i + out.size() - 1) % out.size()];
      Chain& b = out[(i + 1) % out.size()];
      if (&a == &b || a.side == Side::Wale || b.side == Side::Wale) continue;
      if (!boundary_only(c)) continue;
      const Vec3 start = point(pieces.from[at(c.runs.front().halfedges.front())]);
      const Vec3 end = point(pieces.to(c.runs.back().halfedges.back()));
      if ((end - start).norm() >= length - tolerance) continue;
      bool from_b = false;
      std::optional<Run> stretch = take(a, b, end, start, from_b);
      if (!stretch) continue;
      if (from_b) {
        c.runs.push_back(std::move(*stretch));
      } else {
        c.runs.insert(c.runs.begin(), std::move(*stretch));
      }
      ++stats.tip_sides;
    }
  }

  std::int32_t wale_arc(const Chain& chain) const {
    std::vector<int> all;
    double total = 0;
    for (const Run& r : chain.runs) {
      for (int h : r.halfedges) {
        all.push_back(h);
        total += pieces.length(h);
      }
    }
    double walked = 0;
    for (int h : all) {
      walked += pieces.length(h);
      if (walked >= 0.5 * total) return arc_of(h);
    }
    return all.empty() ? kNoArc : arc_of(all.back());
  }

  // Sides taken from the bottom and top chain by each face between the wale
  // sides (l[i0], t[j0]) and (l[i1], t[j1]). Each step is (1, 1), (2, 1) or
  // (1, 2) when the chains allow it (neither more than twice the other);
  // otherwise the counts are spread evenly and the faces come out invalid.
  std::vector<std::pair<int, int>> zip_steps(const std::vector<int>& l, const std::vector<int>& t,
                                             int i0, int j0, int i1, int j1, bool left_boundary,
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
          (mesh.positions[at(l[at(i0 + i)])] - mesh.positions[at(t[at(j0 + j)])]).norm();
      // A wale side is counted as the right length within 15% of the target:
      // one outside costs a step more than its squared error.
      return length_cost((len - params.wale_mm) / params.wale_mm, params.outside_cost);
    };
    // Fig. 7 rules of thumb as costs (docs/stitch-mesh.md): no increase or
    // decrease at a row's end on the boundary, none on a bottom side made by
    // an increase or decrease of the row below, and no increase beside a
    // decrease.
    auto shaped = [&](int i, int count) {
      for (int k = 0; k < count; ++k) {
        if (shaped_below.count(key(l[at(i0 + i + k)], l[at(i0 + i + k + 1)])) != 0) return true;
      }
      return false;
    };
    const std::array<std::pair<int, int>, 3> moves{{{1, 1}, {2, 1}, {1, 2}}};
    const double pentagon =
        params.pentagon_cost;  // prefer knit stitches where rows keep their length
    const double rule = params.stability_cost;
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

  int first_vertex(const Chain& c) const {
    return pieces.from[at(c.runs.front().halfedges.front())];
  }
  int last_vertex(const Chain& c) const { return pieces.to(c.runs.back().halfedges.back()); }

  // A strip around saddles of the row time (m >= 2 bottom and m top chains,
  // alternating; X-shaped for one saddle): one wale edge between two corners
  // two course chains apart (a corner is where a bottom and a top chain
  // meet) cuts off a simple strip of the two chains between them, and leaves
  // m - 1 pairs. A side chain at such a corner is first joined to the
  // bottom chain there (cast-on stitches), so the corner is a point. Of the
  // 2m possible edges the one of least cost is used; the rest is split again.
  // The cost is the edge's length plus, for each of the two strips it makes,
  // kSplitBalance wales per unit of |ln(bottom / top)|: a strip whose bottom
  // is much longer or shorter than its top is zipped with a run of decreases
  // or increases whose wale sides fan out across it (docs/stitch-mesh.md,
  // "Saddle splits"), so the split pairs chains of like length where the
  // edges differ little.
  bool split_folds(const std::string& where, std::vector<Chain> loop) {
    while (loop.front().side != Side::Low) std::rotate(loop.begin(), loop.begin() + 1, loop.end());
    std::vector<Chain> courses;
    std::vector<Chain> sides;    // side chain after each course chain
    std::vector<bool> has_side;  // a boundary side, or an edge made by an earlier split
    for (Chain& c : loop) {
      if (c.side == Side::Wale) {
        if (courses.empty() || has_side.back()) return false;
        sides.back() = std::move(c);
        has_side.back() = true;
      } else {
        if (!courses.empty() && courses.back().side == c.side) return false;
        if (c.runs.empty()) return false;
        courses.push_back(std::move(c));
        Chain none;
        none.side = Side::Wale;
        sides.push_back(std::move(none));
        has_side.push_back(false);
      }
    }
    const std::size_t n = courses.size();
    if (n < 4 || n % 2 != 0) return false;
    // An edge of an earlier split cannot join a bottom chain.
    auto usable = [&](std::size_t k) { return !has_side[k] || !sides[k].runs.empty(); };
    // Corner after course chain k once its side chain has joined a bottom chain.
    auto corner = [&](std::size_t k) {
      if (courses[k].side == Side::Low) {
        return sides[k].runs.empty() ? last_vertex(courses[k]) : last_vertex(sides[k]);
      }
      return sides[k].runs.empty() ? first_vertex(courses[(k + 1) % n]) : first_vertex(sides[k]);
    };
    std::size_t pick = 0;
    double least = std::numeric_limits<double>::infinity();
    bool found = false;
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
    for (std::size_t k = 0; k < n; ++k) {
      if (!usable(k) || !usable((k + 2) % n)) continue;
      found = true;
      const double cost =
          (pieces.position[at(corner(k))] - pieces.position[at(corner((k + 2) % n))]).norm() +
          kSplitBalance * params.wale_mm * imbalance(k);
      if (cost < least) {
        least = cost;
        pick = k;
      }
    }
    if (!found) return false;
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
    ++stats.saddles_split;
    strip(where + " (fold)", std::move(part));
    strip(where + " (rest)", std::move(rest));
    return true;
  }

  // Which ends of a strip of a bottom and b top sides, the chains sharing
  // their left and/or right end, get a short-row triangle (§6.3).
  static std::pair<bool, bool> end_triangles(int a, int b, bool left_shared, bool right_shared) {
    const bool room_for_both = a >= 2 && b >= 2;
    const bool left = left_shared && (room_for_both || !right_shared) && a >= 1 && b >= 1;
    const bool right = right_shared && (room_for_both || !left_shared) && a >= 1 && b >= 1 &&
                       !(left && (a < 2 || b < 2));
    return {left, right};
  }

  // Whether the zip below can make only valid faces from a bottom chain of
  // a and a top chain of b segments (after the end triangles of shared ends,
  // neither more than twice the other).
  static bool zippable(int a, int b, bool left_shared, bool right_shared, const Chain& high,
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
  static bool boundary_end_to_side(std::vector<Chain>& loop) {
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

  // A decrease whose course-out side was split at `middle` (two sides in,
  // two out) becomes two knit stitches sharing a wale edge.
  void split_decrease(std::size_t index, int middle) {
    const StitchFace old = mesh.faces[index];
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
    mesh.faces[index] = part(corner, top);
    mesh.faces.push_back(part(top, corner));
    for (std::size_t f : {index, mesh.faces.size() - 1}) {
      const StitchFace& face = mesh.faces[f];
      for (std::size_t i = 0; i < face.vertices.size(); ++i) {
        if (face.roles[i] == EdgeRole::CourseOut) {
          face_below[key(static_cast<int>(face.vertices[(i + 1) % face.vertices.size()]),
                         static_cast<int>(face.vertices[i]))] = f;
        }
      }
    }
  }

  // Splits the longest side of a fixed bottom chain whose face below is a
  // knit stitch (it becomes an increase, §6.3) or a decrease (it becomes two
  // knit stitches), or that has no face below (a cast-on side, possibly
  // under glued lenses: one more stitch is cast on), so the bottom chain has
  // one more side. False when no side qualifies.
  bool split_side_below(const Chain& low) {
    constexpr std::size_t kNoFace = std::numeric_limits<std::size_t>::max();
    double longest = 0;
    std::size_t best_curve = 0;
    std::size_t best_index = 0;
    std::size_t best_face = 0;
    bool found = false;
    for (const Run& run : low.runs) {
      if (!run.level) continue;
      auto it = curve_of_edge.find(undirected(run.halfedges.front()));
      if (it == curve_of_edge.end()) continue;
      const std::vector<int>& samples = curve_samples[at(it->second)];
      for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
        const int u = samples[k];
        const int v = samples[k + 1];
        const double length = (mesh.positions[at(u)] - mesh.positions[at(v)]).norm();
        auto below = face_below.find(key(u, v));
        if (below == face_below.end()) below = face_below.find(key(v, u));
        if (below == face_below.end()) {
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
        const FaceType type = mesh.faces[below->second].type;
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
    std::vector<int>& samples = curve_samples[best_curve];
    const int u = samples[best_index];
    const int v = samples[best_index + 1];
    const int middle = static_cast<int>(mesh.positions.size());
    mesh.positions.push_back(0.5 * (mesh.positions[at(u)] + mesh.positions[at(v)]));
    samples.insert(samples.begin() + static_cast<std::ptrdiff_t>(best_index) + 1, middle);
    if (best_face == kNoFace) {
      ++stats.sides_split_below;
      return true;
    }
    StitchFace& face = mesh.faces[best_face];
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const int a = static_cast<int>(face.vertices[i]);
      const int b = static_cast<int>(face.vertices[(i + 1) % n]);
      if (face.roles[i] != EdgeRole::CourseOut || !((a == u && b == v) || (a == v && b == u))) {
        continue;
      }
      face.vertices.insert(face.vertices.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                           static_cast<std::uint32_t>(middle));
      face.roles.insert(face.roles.begin() + static_cast<std::ptrdiff_t>(i) + 1,
                        EdgeRole::CourseOut);
      face.arcs.insert(face.arcs.begin() + static_cast<std::ptrdiff_t>(i) + 1, face.arcs[i]);
      face_below.erase(key(b, a));
      ++stats.sides_split_below;
      if (face.type == FaceType::Decrease) {
        // Two sides in, two out: a wale edge from the corner between the
        // course-in sides to the new vertex makes two knit stitches.
        shaped_below.erase(key(b, a));
        split_decrease(best_face, middle);
        return true;
      }
      face.type = FaceType::Increase;
      face_below[key(middle, a)] = best_face;
      face_below[key(b, middle)] = best_face;
      shaped_below.insert(key(middle, a));
      shaped_below.insert(key(b, middle));
      return true;
    }
    throw std::logic_error("stitch meshing: a course-out side is not in its face");
  }

  void strip(const std::string& where, std::vector<Chain> loop) {
    // Bring the loop to the form Low [Wale] High [Wale].
    int lows = 0;
    int highs = 0;
    for (const Chain& c : loop) {
      lows += c.side == Side::Low;
      highs += c.side == Side::High;
    }
    if (lows == 0 || highs == 0) {
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
    if (loop.size() == 1 && loop.front().side != Side::Wale && !boundary_only(loop.front()) &&
        std::any_of(loop.front().runs.begin(), loop.front().runs.end(),
                    [](const Run& r) { return !r.level; })) {
      // One course chain all round: a level curve closed by boundary that
      // faces the same way, or by a stretch of boundary too short to face
      // either way (the row begins or ends at a tip of the boundary, which
      // happens where rows are tall against the cut's features). The longest
      // stretch of boundary is the other chain.
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
      lows = highs = 1;
    }
    if (lows >= 2 && lows == highs && split_folds(where, loop)) return;
    if (lows != 1 || highs != 1) {
      std::string pattern;
      for (const Chain& c : loop) {
        const double len = chain_length(c);
        pattern += std::string(" ") +
                   (c.side == Side::Low    ? "L"
                    : c.side == Side::High ? "H"
                                           : "S") +
                   std::to_string(static_cast<int>(len * 10) / 10.0).substr(0, 4);
      }
      problems.push_back(where + pattern + ": " + std::to_string(lows) + " bottom and " +
                         std::to_string(highs) +
                         " top chains (expected one each); the row time folds here");
      return;
    }
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
    // Segment counts: the zip needs, after the end triangles of shared ends,
    // either nothing left or one chain at most twice the other (§6.3).
    const int shared = (left_wale == nullptr ? 1 : 0) + (right_wale == nullptr ? 1 : 0);
    std::vector<int> low_counts = run_counts(loop.front());
    std::vector<int> high_counts = run_counts(*high);
    const std::vector<bool> low_fixed = fixed_runs(loop.front());
    const std::vector<bool> high_fixed = fixed_runs(*high);
    int high_min = 0;
    for (const Run& run : high->runs) high_min += minimum(run);
    for (int attempt = 0; attempt < 2; ++attempt) {
      const int a = std::accumulate(low_counts.begin(), low_counts.end(), 0);
      const int b = std::accumulate(high_counts.begin(), high_counts.end(), 0);
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
        rescale(*high, high_fixed, high_counts, std::clamp(b, lo, hi));
        break;
      }
      // The top chain cannot shrink enough: lengthen the bottom one.
      rescale(loop.front(), low_fixed, low_counts,
              std::max(1, shared + (std::max(0, high_min - shared) + 1) / 2));
    }
    if (!zippable(std::accumulate(low_counts.begin(), low_counts.end(), 0),
                  std::accumulate(high_counts.begin(), high_counts.end(), 0), left_wale == nullptr,
                  right_wale == nullptr, *high, high_counts) &&
        boundary_end_to_side(loop)) {
      // A top chain of bind-off boundary around a short fixed bottom (the
      // boundary runs almost along the rows): more stitches above than the
      // row below can feed even by increasing every stitch. The bind-off
      // stretch at the top chain's end becomes the row's wale side instead,
      // and the strip is zipped again.
      ++stats.boundary_sides;
      strip(where, std::move(loop));
      return;
    }
    // Still too many stitches above a fixed bottom: split a bottom side whose
    // stitch below is a knit stitch (it becomes an increase), and fit the
    // counts again.
    if (!zippable(std::accumulate(low_counts.begin(), low_counts.end(), 0),
                  std::accumulate(high_counts.begin(), high_counts.end(), 0), left_wale == nullptr,
                  right_wale == nullptr, *high, high_counts) &&
        split_side_below(loop.front())) {
      strip(where, std::move(loop));
      return;
    }
    std::vector<std::int32_t> low_arcs;
    std::vector<std::int32_t> high_arcs;
    const std::vector<int> l = chain_vertices(loop.front(), low_counts, low_arcs);
    const bool left_shared = left_wale == nullptr;
    const bool right_shared = right_wale == nullptr;
    const int a = static_cast<int>(l.size()) - 1;
    const int b = std::accumulate(high_counts.begin(), high_counts.end(), 0);
    const auto [left_triangle, right_triangle] = end_triangles(a, b, left_shared, right_shared);
    std::vector<bool> high_on_level;
    std::vector<int> h = chain_vertices(*high, high_counts, high_arcs, &high_on_level);
    // Top chain left to right: t[j] = h[b - j]; top segment j is high segment b - 1 - j.
    std::vector<int> t(h.rbegin(), h.rend());
    auto top_arc = [&](int j) { return high_arcs[at(b - 1 - j)]; };
    if (left_shared != (t.front() == l.front()) || right_shared != (t.back() == l.back())) {
      throw std::logic_error("stitch meshing: chain ends disagree with the strip's sides");
    }
    if (left_shared && right_shared && a == 1 && b == 2 && high_on_level[0] != high_on_level[1]) {
      // One fixed bottom side, a top of a level piece and a boundary piece:
      // the boundary piece is the wale side of a short-row triangle.
      const EdgeRole first = high_on_level[0] ? EdgeRole::CourseOut : EdgeRole::Wale;
      const EdgeRole second = high_on_level[1] ? EdgeRole::CourseOut : EdgeRole::Wale;
      add_face({l[0], l[1], t[1]}, {EdgeRole::CourseIn, first, second},
               {low_arcs[0], top_arc(1), top_arc(0)});
      return;
    }
    if (left_shared && right_shared && a == 1 && b == 1) {
      ++stats.lenses_skipped;  // one edge below, one above, same ends: they are glued
      return;
    }
    using R = EdgeRole;
    int i0 = 0;
    int j0 = 0;
    int i1 = a;
    int j1 = b;
    std::int32_t left_arc = left_wale != nullptr ? wale_arc(*left_wale) : kNoArc;
    std::int32_t right_arc = right_wale != nullptr ? wale_arc(*right_wale) : kNoArc;
    if (left_triangle) {
      // §6.3 short row ending on the left: the strip narrows to a point.
      add_face({l[0], l[1], t[1]}, {R::CourseIn, R::Wale, R::CourseOut},
               {low_arcs[0], kNoArc, top_arc(0)});
      i0 = 1;
      j0 = 1;
      left_arc = kNoArc;
    }
    if (right_triangle) {
      add_face({l[at(a - 1)], l[at(a)], t[at(b - 1)]}, {R::CourseIn, R::CourseOut, R::Wale},
               {low_arcs[at(a - 1)], top_arc(b - 1), kNoArc});
      i1 = a - 1;
      j1 = b - 1;
      right_arc = kNoArc;
    }
    const int na = i1 - i0;
    const int nb = j1 - j0;
    if (na == 0 && nb == 0) return;
    if (na <= 0 || nb <= 0) {
      // Nothing valid fits: one face with all that is left, reported by check.
      std::vector<int> v;
      std::vector<R> roles;
      std::vector<std::int32_t> arcs;
      for (int i = i0; i < i1; ++i) {
        v.push_back(l[at(i)]);
        roles.push_back(R::CourseIn);
        arcs.push_back(low_arcs[at(i)]);
      }
      if (l[at(i1)] != t[at(j1)]) {
        v.push_back(l[at(i1)]);
        roles.push_back(R::Wale);
        arcs.push_back(right_arc);
      }
      for (int j = j1; j > j0; --j) {
        v.push_back(t[at(j)]);
        roles.push_back(R::CourseOut);
        arcs.push_back(top_arc(j - 1));
      }
      if (t[at(j0)] != l[at(i0)]) {
        v.push_back(t[at(j0)]);
        roles.push_back(R::Wale);
        arcs.push_back(left_arc);
      }
      add_face(std::move(v), std::move(roles), std::move(arcs));
      return;
    }
    // Zip (§6.3): faces with one or two sides on each chain (knit, decrease,
    // increase), chosen by dynamic programming so wale sides are as close to
    // wale_mm as possible and pentagons are used only where rows change length.
    const std::vector<std::pair<int, int>> steps =
        zip_steps(l, t, i0, j0, i1, j1, left_wale != nullptr && !left_wale->runs.empty(),
                  right_wale != nullptr && !right_wale->runs.empty());
    int i = i0;
    int j = j0;
    for (std::size_t f = 0; f < steps.size(); ++f) {
      const int cb = steps[f].first;
      const int ct = steps[f].second;
      std::vector<int> v;
      std::vector<R> roles;
      std::vector<std::int32_t> arcs;
      for (int k = 0; k < cb; ++k) {
        v.push_back(l[at(i + k)]);
        roles.push_back(R::CourseIn);
        arcs.push_back(low_arcs[at(i + k)]);
      }
      v.push_back(l[at(i + cb)]);
      roles.push_back(R::Wale);
      arcs.push_back(f + 1 == steps.size() ? right_arc : kNoArc);
      for (int k = ct; k > 0; --k) {
        v.push_back(t[at(j + k)]);
        roles.push_back(R::CourseOut);
        arcs.push_back(top_arc(j + k - 1));
      }
      v.push_back(t[at(j)]);
      roles.push_back(R::Wale);
      arcs.push_back(f == 0 ? left_arc : kNoArc);
      add_face(std::move(v), std::move(roles), std::move(arcs));
      i += cb;
      j += ct;
    }
  }
};

// The disc as triangles (fans of its faces), for exact distances and
// nearest points.
cloth::TriangleMeshQuery disc_surface(const LabelledDisc& disc) {
  std::vector<std::array<int, 3>> triangles;
  for (const std::vector<int>& face : disc.faces) {
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      triangles.push_back({face[0], face[i], face[i + 1]});
    }
  }
  return cloth::TriangleMeshQuery(disc.positions, std::move(triangles));
}

Vec3 polygon_normal(const StitchMesh& mesh, const StitchFace& face) {
  Vec3 normal = Vec3::Zero();
  const std::size_t n = face.vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    normal += mesh.positions[face.vertices[i]].cross(mesh.positions[face.vertices[(i + 1) % n]]);
  }
  return normal;
}

// Step 5, relaxing (docs/stitch-mesh.md): the stitch vertices inside the
// sheet move over the cut mesh so that the sides come closer to their
// target lengths, course or wale; the boundary's vertices stay. Each sweep
// moves each inner vertex to where its sides, as springs of their target
// lengths, would hold it (each weighted by 1 / target^2, and less the
// farther it is off, so a fan's chord across a hole does not drag the
// sheet), then onto the nearest point of the surface. A move that turns an
// incident face over is not made. The faces and their types do not change.
// Returns the number of sweeps made.
int relax_positions(StitchMesh& mesh, const LabelledDisc& disc, int sweeps) {
  if (sweeps <= 0) return 0;
  const cloth::TriangleMeshQuery surface = disc_surface(disc);
  struct Spring {
    std::uint32_t other;
    double target;
  };
  const std::size_t count = mesh.positions.size();
  std::vector<std::vector<Spring>> springs(count);
  std::vector<std::vector<std::size_t>> faces_of(count);
  std::map<std::pair<std::uint32_t, std::uint32_t>, EdgeRole> sides;
  std::set<std::pair<std::uint32_t, std::uint32_t>> directed;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const StitchFace& face = mesh.faces[f];
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t a = face.vertices[i];
      const std::uint32_t b = face.vertices[(i + 1) % n];
      faces_of[a].push_back(f);
      directed.insert({a, b});
      sides.emplace(std::make_pair(std::min(a, b), std::max(a, b)), face.roles[i]);
    }
  }
  std::vector<bool> fixed(count, false);
  for (const auto& [a, b] : directed) {
    if (directed.count({b, a}) == 0) fixed[a] = fixed[b] = true;
  }
  for (const auto& [side, role] : sides) {
    const double target = role == EdgeRole::Wale ? mesh.wale_mm : mesh.course_mm;
    springs[side.first].push_back({side.second, target});
    springs[side.second].push_back({side.first, target});
  }
  std::vector<Vec3> normals;
  for (const StitchFace& face : mesh.faces) normals.push_back(polygon_normal(mesh, face));
  // A vertex is visited again only while it or a neighbour still moves.
  const double still = 1e-4 * mesh.course_mm;
  std::vector<bool> active(count, true);
  std::vector<bool> moved(count, false);
  int sweep = 0;
  while (sweep < sweeps) {
    ++sweep;
    std::fill(moved.begin(), moved.end(), false);
    for (std::size_t v = 0; v < count; ++v) {
      if (fixed[v] || springs[v].empty() || !active[v]) continue;
      const Vec3 x = mesh.positions[v];
      Vec3 sum = Vec3::Zero();
      double weights = 0;
      for (const Spring& s : springs[v]) {
        const Vec3 d = x - mesh.positions[s.other];
        const double length = d.norm();
        if (!(length > 0)) continue;
        const double off = (length - s.target) / (0.5 * s.target);
        const double w = 1.0 / (s.target * s.target * (1 + off * off));
        sum += w * (mesh.positions[s.other] + s.target / length * d);
        weights += w;
      }
      if (!(weights > 0)) continue;
      mesh.positions[v] = surface.closest_point(sum / weights);
      for (std::size_t f : faces_of[v]) {
        if (polygon_normal(mesh, mesh.faces[f]).dot(normals[f]) <= 0) {
          mesh.positions[v] = x;
          break;
        }
      }
      moved[v] = (mesh.positions[v] - x).norm() > still;
    }
    bool any = false;
    for (std::size_t v = 0; v < count; ++v) {
      active[v] = moved[v];
      for (const Spring& s : springs[v]) active[v] = active[v] || moved[s.other];
      any = any || active[v];
    }
    if (!any) break;
  }
  return sweep;
}

}  // namespace

std::vector<std::string> check_disc(const LabelledDisc& disc) {
  std::vector<std::string> problems;
  if (disc.faces.empty()) problems.push_back("the disc has no faces");
  if (disc.directions.size() != disc.faces.size()) {
    problems.push_back(std::to_string(disc.faces.size()) + " faces but " +
                       std::to_string(disc.directions.size()) + " direction lists");
    return problems;
  }
  if (!disc.arcs.empty() && disc.arcs.size() != disc.faces.size()) {
    problems.push_back(std::to_string(disc.faces.size()) + " faces but " +
                       std::to_string(disc.arcs.size()) + " arc lists");
  }
  for (std::size_t f = 0; f < disc.faces.size(); ++f) {
    const std::vector<int>& face = disc.faces[f];
    const std::string where = "face " + std::to_string(f);
    if (face.size() < 3) problems.push_back(where + ": fewer than 3 corners");
    if (disc.directions[f].size() != face.size()) {
      problems.push_back(where + ": " + std::to_string(face.size()) + " corners but " +
                         std::to_string(disc.directions[f].size()) + " side directions");
      continue;
    }
    if (!disc.arcs.empty() && f < disc.arcs.size() && disc.arcs[f].size() != face.size()) {
      problems.push_back(where + ": " + std::to_string(face.size()) + " corners but " +
                         std::to_string(disc.arcs[f].size()) + " side arcs");
    }
    bool ok = true;
    for (int v : face) {
      if (v < 0 || at(v) >= disc.positions.size()) {
        problems.push_back(where + ": vertex " + std::to_string(v) + " out of range");
        ok = false;
      }
    }
    for (int d : disc.directions[f]) {
      if (d < 0 || d > 3) {
        problems.push_back(where + ": side direction " + std::to_string(d) + " is not 0..3");
        ok = false;
      }
    }
    if (!ok) continue;
    if (face_normal(disc, face).norm() <= 1e-12) problems.push_back(where + ": zero area");
    bool has_course = false;
    bool has_wale = false;
    for (int d : disc.directions[f]) (d % 2 == 0 ? has_course : has_wale) = true;
    if (!has_course && !has_wale) problems.push_back(where + ": no labelled side");
  }
  return problems;
}

StitchMeshResult make_stitch_mesh(const LabelledDisc& disc, const StitchMeshParams& params) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::string> input_problems = check_disc(disc);
  if (!input_problems.empty()) {
    throw std::invalid_argument("make_stitch_mesh: " + input_problems.front());
  }
  if (!(params.course_mm > 0) || !(params.wale_mm > 0)) {
    throw std::invalid_argument("make_stitch_mesh: course_mm and wale_mm must be positive");
  }
  StitchMeshResult result;
  std::vector<Triangle> tris = triangulate(disc);
  Eigen::VectorXd t = row_time(disc, tris, params, result.stats);
  result.stats.solve_seconds = seconds_since(start);
  int bands = 1;
  Pieces pieces;
  std::map<int, std::vector<std::vector<int>>> loops;  // strip root -> boundary loops
  std::vector<int> parent;
  // Rows, pieces and strips from t. A strip with a hole (an interior
  // extremum of t) makes the row time be levelled and the rows be placed
  // again; a row time without one is used as fitted.
  auto find_strips = [&] {
    // Strips: pieces of one band joined across their shared sides.
    const int num_pieces = static_cast<int>(pieces.band.size());
    parent.assign(at(num_pieces), 0);
    std::iota(parent.begin(), parent.end(), 0);
    for (std::size_t h = 0; h < pieces.from.size(); ++h) {
      const int tw = pieces.twin[h];
      if (tw < 0 || pieces.level[h] >= 0) continue;
      const int a = find(parent, pieces.piece[h]);
      const int b = find(parent, pieces.piece[at(tw)]);
      if (a != b) parent[at(std::max(a, b))] = std::min(a, b);
    }
    auto on_boundary = [&](int h) { return pieces.twin[at(h)] < 0 || pieces.level[at(h)] >= 0; };
    loops.clear();
    std::vector<bool> visited(pieces.from.size(), false);
    for (int h0 = 0; h0 < static_cast<int>(pieces.from.size()); ++h0) {
      if (visited[at(h0)] || !on_boundary(h0)) continue;
      std::vector<int> loop;
      int h = h0;
      do {
        visited[at(h)] = true;
        loop.push_back(h);
        int c = pieces.next(h);
        int guard = 0;
        while (!on_boundary(c)) {
          c = pieces.next(pieces.twin[at(c)]);
          if (++guard > 100000) throw std::logic_error("stitch meshing: vertex walk does not end");
        }
        h = c;
      } while (h != h0 && !visited[at(h)]);
      if (h != h0) throw std::logic_error("stitch meshing: strip boundary does not close");
      loops[find(parent, pieces.piece[at(h0)])].push_back(std::move(loop));
    }
  };
  auto make_strips = [&](const std::vector<bool>& candidates) {
    Eigen::VectorXd rows = row_levels(disc, tris, t, params, bands);
    const std::vector<int> pin =
        pin_saddles(disc, tris, rows, bands, 0.4 * params.saddle_wales * params.wale_mm,
                    params.saddle_wales * params.wale_mm, candidates, result.stats.saddles_pinned);
    pieces = slice(disc, tris, rows, 1.0, bands, pin);
    find_strips();
  };
  make_strips({});
  auto has_hole = [&] {
    return std::any_of(loops.begin(), loops.end(),
                       [](const auto& entry) { return entry.second.size() > 1; });
  };
  if (has_hole()) {
    result.stats.row_time_levelled = level_interior_extrema(disc, tris, t);
    make_strips({});
  }
  // Saddles on a level: those among the vertices of strips with two bottom
  // and two top chains, or whose bottom and top differ in length by more
  // than kLopsidedRatio, are held on a level and the rows are made again.
  if (params.saddle_wales > 0) {
    std::set<int> roots;
    Builder probe{disc, params, pieces, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}};
    for (const auto& [root, strip_loops] : loops) {
      if (strip_loops.size() != 1) continue;
      int lows = 0;
      int highs = 0;
      double bottom = 0;
      double top = 0;
      for (const Chain& c :
           probe.chains(probe.loop_runs(strip_loops.front(), pieces.band[at(root)], t, tris))) {
        lows += c.side == Side::Low ? 1 : 0;
        highs += c.side == Side::High ? 1 : 0;
        if (c.side != Side::Wale) (c.side == Side::Low ? bottom : top) += chain_length(c);
      }
      const bool x_shaped = lows >= 2 && lows == highs;
      const bool lopsided = bottom > 0 && top > 0 &&
                            std::abs(std::log(bottom / top)) > std::log(kLopsidedRatio) &&
                            std::max(bottom, top) >= kLopsidedWales * params.wale_mm;
      if (x_shaped || lopsided) roots.insert(root);
    }
    if (!roots.empty()) {
      std::vector<bool> candidates(disc.positions.size(), false);
      for (std::size_t p = 0; p < pieces.band.size(); ++p) {
        if (roots.count(find(parent, static_cast<int>(p))) == 0) continue;
        for (int v : tris[at(pieces.tri[p])].v) candidates[at(v)] = true;
      }
      make_strips(candidates);
      // Held saddles make no extremum, so no strip with a hole; should one
      // appear all the same, the rows are made as before.
      if (has_hole()) make_strips({});
    }
  }
  // Row ends: the boundary points 0.9 wale (`tip_side_wales`) from where a row's chains meet
  // become piece vertices, so those rows can end in a wale side there.
  if (params.tip_side_wales > 0) {
    std::vector<HalfedgeSplit> splits;
    {
      Builder probe{disc, params, pieces, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}};
      for (const auto& [root, strip_loops] : loops) {
        if (strip_loops.size() == 1) {
          probe.chains(probe.loop_runs(strip_loops.front(), pieces.band[at(root)], t, tris));
        }
      }
      splits = std::move(probe.tip_splits);
    }
    if (!splits.empty()) {
      pieces = split_halfedges(pieces, std::move(splits));
      find_strips();
    }
  }
  Builder builder{disc, params, pieces, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}, {}};
  builder.mesh.course_mm = params.course_mm;
  builder.mesh.wale_mm = params.wale_mm;
  // Strips in row order, so level curves are sampled from below first.
  std::vector<std::pair<int, int>> order;
  for (const auto& [root, strip_loops] : loops) order.push_back({pieces.band[at(root)], root});
  std::sort(order.begin(), order.end());
  // Each strip's chains, made once (empty for a strip with a hole).
  std::vector<std::vector<Chain>> strip_chains(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto& [band, root] = order[i];
    const std::vector<std::vector<int>>& strip_loops = loops[root];
    if (strip_loops.size() == 1) {
      strip_chains[i] = builder.chains(builder.loop_runs(strip_loops.front(), band, t, tris));
    }
  }
  for (auto it = strip_chains.rbegin(); it != strip_chains.rend(); ++it) builder.plan_minimums(*it);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto& [band, root] = order[i];
    const std::vector<std::vector<int>>& strip_loops = loops[root];
    ++builder.stats.strips;
    const std::string where =
        "row " + std::to_string(band) + " strip at piece " + std::to_string(root);
    if (strip_loops.size() != 1) {
      builder.problems.push_back(where + ": " + std::to_string(strip_loops.size()) +
                                 " boundary loops (a strip with a hole: the row time has an "
                                 "interior extremum)");
      continue;
    }
    builder.strip(where, std::move(strip_chains[i]));
  }
  result.stats.rows = bands;
  result.stats.strips = builder.stats.strips;
  result.stats.lenses_skipped = builder.stats.lenses_skipped;
  result.stats.saddles_split = builder.stats.saddles_split;
  result.stats.invalid_faces = builder.stats.invalid_faces;
  result.stats.boundary_sides = builder.stats.boundary_sides;
  result.stats.sides_split_below = builder.stats.sides_split_below;
  result.stats.tip_sides = builder.stats.tip_sides;
  result.mesh = std::move(builder.mesh);
  const auto relax_start = std::chrono::steady_clock::now();
  result.stats.relax_sweeps = relax_positions(result.mesh, disc, params.relax_sweeps);
  result.stats.relax_seconds = seconds_since(relax_start);
  result.problems = std::move(builder.problems);
  for (std::string& line : check(result.mesh)) result.problems.push_back(std::move(line));
  result.stats.total_seconds = seconds_since(start);
  return result;
}

namespace {

EdgeLengthStats length_stats(const std::vector<double>& lengths, double target) {
  EdgeLengthStats s;
  s.count = static_cast<int>(lengths.size());
  if (lengths.empty()) return s;
  s.min_mm = *std::min_element(lengths.begin(), lengths.end());
  s.max_mm = *std::max_element(lengths.begin(), lengths.end());
  s.mean_mm =
      std::accumulate(lengths.begin(), lengths.end(), 0.0) / static_cast<double>(lengths.size());
  int within = 0;
  for (double x : lengths) within += std::abs(x - target) <= kLengthTolerance * target;
  s.within_15_percent = static_cast<double>(within) / static_cast<double>(lengths.size());
  return s;
}

}  // namespace

StitchMeshFigures measure(const StitchMesh& mesh) {
  StitchMeshFigures out;
  out.faces = static_cast<int>(mesh.faces.size());
  out.vertices = static_cast<int>(mesh.positions.size());
  std::map<std::pair<std::uint32_t, std::uint32_t>, EdgeRole> edges;  // undirected -> role
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const StitchFace& face : mesh.faces) {
    switch (face.type) {
      case FaceType::Knit:
        ++out.knit;
        break;
      case FaceType::Increase:
        ++out.increase;
        break;
      case FaceType::Decrease:
        ++out.decrease;
        break;
      case FaceType::ShortRow:
        ++out.short_row;
        break;
    }
    const std::size_t n = face.vertices.size();
    Vec3 normal = Vec3::Zero();
    for (std::size_t i = 0; i < n && i < face.roles.size(); ++i) {
      const std::uint32_t a = face.vertices[i];
      const std::uint32_t b = face.vertices[(i + 1) % n];
      if (a >= mesh.positions.size() || b >= mesh.positions.size()) continue;
      normal += mesh.positions[a].cross(mesh.positions[b]);
      edges[{std::min(a, b), std::max(a, b)}] = face.roles[i];
      ++directed[{a, b}];
    }
    out.area_mm2 += 0.5 * normal.norm();
  }
  std::vector<double> course;
  std::vector<double> wale;
  for (const auto& [e, role] : edges) {
    const double len = (mesh.positions[e.second] - mesh.positions[e.first]).norm();
    (role == EdgeRole::Wale ? wale : course).push_back(len);
  }
  out.course = length_stats(course, mesh.course_mm);
  out.wale = length_stats(wale, mesh.wale_mm);
  // Boundary: directed sides with no reverse; loops by following them.
  std::map<std::uint32_t, std::uint32_t> next;
  for (const auto& [e, count] : directed) {
    if (directed.find({e.second, e.first}) == directed.end()) {
      next[e.first] = e.second;
      out.boundary_length_mm += (mesh.positions[e.second] - mesh.positions[e.first]).norm();
    }
  }
  std::map<std::uint32_t, bool> seen;
  for (const auto& [a, b] : next) {
    if (seen[a]) continue;
    ++out.boundary_loops;
    std::uint32_t v = a;
    while (!seen[v]) {
      seen[v] = true;
      auto it = next.find(v);
      if (it == next.end()) break;
      v = it->second;
    }
  }
  std::vector<bool> used(mesh.positions.size(), false);
  for (const StitchFace& face : mesh.faces) {
    for (std::uint32_t v : face.vertices) {
      if (v < used.size()) used[v] = true;
    }
  }
  const int used_vertices = static_cast<int>(std::count(used.begin(), used.end(), true));
  out.euler_characteristic = used_vertices - static_cast<int>(edges.size()) + out.faces;
  return out;
}

StabilityCounts count_stability_rules(const StitchMesh& mesh) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<std::size_t, std::size_t>> sides;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const StitchFace& face = mesh.faces[f];
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      sides[{face.vertices[i], face.vertices[(i + 1) % face.vertices.size()]}] = {f, i};
    }
  }
  auto pentagon = [](FaceType t) { return t == FaceType::Increase || t == FaceType::Decrease; };
  StabilityCounts counts;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const StitchFace& face = mesh.faces[f];
    const std::size_t n = face.vertices.size();
    bool edge = false;
    bool stacked = false;
    for (std::size_t i = 0; i < n; ++i) {
      auto twin = sides.find({face.vertices[(i + 1) % n], face.vertices[i]});
      const StitchFace* other = twin == sides.end() ? nullptr : &mesh.faces[twin->second.first];
      if (pentagon(face.type)) {
        if (face.roles[i] == EdgeRole::Wale && other == nullptr) edge = true;
        if (face.roles[i] == EdgeRole::CourseIn && other != nullptr && pentagon(other->type)) {
          stacked = true;
        }
        if (face.roles[i] == EdgeRole::Wale && other != nullptr && pentagon(other->type) &&
            other->type != face.type && f < twin->second.first) {
          ++counts.opposed_shaping;
        }
      }
      if (face.type == FaceType::ShortRow && face.roles[i] == EdgeRole::Wale && other != nullptr &&
          other->type == FaceType::ShortRow && f < twin->second.first) {
        ++counts.one_stitch_rows;
      }
    }
    counts.edge_shaping += edge;
    counts.stacked_shaping += stacked;
  }
  return counts;
}

OffSurface off_surface_faces(const StitchMesh& mesh, const LabelledDisc& disc,
                             double tolerance_mm) {
  OffSurface out;
  out.tolerance_mm = tolerance_mm;
  const cloth::TriangleMeshQuery surface = disc_surface(disc);
  std::unordered_map<std::uint64_t, double> offset_of;  // side -> midpoint distance
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const std::vector<std::uint32_t>& v = mesh.faces[f].vertices;
    double worst = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      const Vec3& p = mesh.positions[v[i]];
      const Vec3& q = mesh.positions[v[(i + 1) % v.size()]];
      // Both ends lie on the surface, so the midpoint is within half the side of it.
      if ((q - p).norm() <= 2 * tolerance_mm) continue;
      const std::uint64_t side = key(static_cast<int>(std::min(v[i], v[(i + 1) % v.size()])),
                                     static_cast<int>(std::max(v[i], v[(i + 1) % v.size()])));
      auto [it, fresh] = offset_of.emplace(side, 0.0);
      if (fresh) it->second = surface.distance(0.5 * (p + q));
      worst = std::max(worst, it->second);
    }
    if (worst > tolerance_mm) {
      out.faces.push_back(f);
      if (worst > out.max_offset_mm) {
        out.max_offset_mm = worst;
        out.farthest_face = f;
      }
    }
  }
  return out;
}

double disc_area_mm2(const LabelledDisc& disc) {
  double area = 0;
  for (const std::vector<int>& face : disc.faces) area += 0.5 * face_normal(disc, face).norm();
  return area;
}

double disc_boundary_length_mm(const LabelledDisc& disc) {
  std::unordered_map<std::uint64_t, int> directed;
  for (const std::vector<int>& face : disc.faces) {
    for (std::size_t i = 0; i < face.size(); ++i)
      ++directed[key(face[i], face[(i + 1) % face.size()])];
  }
  double length = 0;
  for (const std::vector<int>& face : disc.faces) {
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i];
      const int b = face[(i + 1) % face.size()];
      if (directed.find(key(b, a)) == directed.end()) {
        length += (disc.positions[at(b)] - disc.positions[at(a)]).norm();
      }
    }
  }
  return length;
}

}  // namespace planner
