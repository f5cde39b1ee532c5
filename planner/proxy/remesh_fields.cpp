// The remesher's fields (remesh.hpp): a multi-resolution hierarchy of the
// samples' graph, the 4-RoSy orientation field and the 4-PoSy position
// field solved on it coarse to fine (Instant Meshes §3.1, §3.2, §4).
#include <algorithm>
#include <cmath>
#include <limits>

#include "planner/common/index.hpp"
#include "planner/proxy/remesh.hpp"
#include "planner/proxy/remesh_internal.hpp"

namespace planner {

// The representative of the 4-fold direction (o, n x o, -o, -n x o) closest to `target`.
Vec3 closest_representative(const Vec3& o, const Vec3& n, const Vec3& target) {
  const Vec3 q = n.cross(o);
  const double a = o.dot(target);
  const double b = q.dot(target);
  if (std::abs(a) >= std::abs(b)) return a >= 0 ? o : Vec3(-o);
  return b >= 0 ? q : Vec3(-q);
}

namespace remesh_detail {

namespace {

// The graph the fields live on, at one level of the multi-resolution
// hierarchy of Instant Meshes (Jakob et al. 2015, §4): level 0 is the
// sampled surface; each coarser level merges pairs of neighbours.
struct FieldGraph {
  std::vector<Vec3> position;
  std::vector<Vec3> normal;
  std::vector<double> area;
  std::vector<std::vector<int>> adjacent;
  std::vector<int> parent;  // each vertex's vertex in the next coarser level
};

FieldGraph sample_graph(const HalfedgeMesh& mesh) {
  const int nv = mesh.num_vertices();
  FieldGraph g;
  g.position.resize(at(nv));
  g.normal.assign(at(nv), Vec3::Zero());
  g.area.assign(at(nv), 0.0);
  g.adjacent.resize(at(nv));
  for (int v = 0; v < nv; ++v) g.position[at(v)] = mesh.position(v);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 n = mesh.face_normal(f);
    const int start = mesh.face_start(f);
    for (int i = 0; i < mesh.degree(f); ++i) {
      g.normal[at(mesh.from(start + i))] += n;
      g.area[at(mesh.from(start + i))] += 0.5 * n.norm() / mesh.degree(f);
    }
  }
  for (Vec3& n : g.normal) {
    if (n.norm() > 0)
      n.normalize();
    else
      n = Vec3::UnitZ();
  }
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    g.adjacent[at(mesh.from(h))].push_back(mesh.to(h));
    if (mesh.twin(h) < 0) g.adjacent[at(mesh.to(h))].push_back(mesh.from(h));
  }
  return g;
}

// Instant Meshes' downsampling: neighbours are merged in pairs, those with
// the most similar normals and the most unequal areas first (so small
// vertices join larger ones); a vertex left without a partner stays alone.
// Fills fine.parent.
FieldGraph coarsen(FieldGraph& fine) {
  const std::size_t n = fine.position.size();
  struct Candidate {
    double score;
    int i, j;
  };
  std::vector<Candidate> candidates;
  for (std::size_t i = 0; i < n; ++i) {
    for (const int j : fine.adjacent[i]) {
      if (at(j) <= i) continue;
      const double ai = std::max(fine.area[i], 1e-30);
      const double aj = std::max(fine.area[at(j)], 1e-30);
      candidates.push_back({fine.normal[i].dot(fine.normal[at(j)]) * std::max(ai / aj, aj / ai),
                            static_cast<int>(i), j});
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  fine.parent.assign(n, -1);
  FieldGraph coarse;
  auto add = [&](const std::vector<int>& children) {
    const int c = static_cast<int>(coarse.position.size());
    Vec3 p = Vec3::Zero();
    Vec3 normal = Vec3::Zero();
    double area = 0.0;
    for (const int v : children) {
      fine.parent[at(v)] = c;
      const double w = std::max(fine.area[at(v)], 1e-30);
      p += w * fine.position[at(v)];
      normal += w * fine.normal[at(v)];
      area += w;
    }
    coarse.position.push_back(p / area);
    coarse.normal.push_back(normal.norm() > 1e-12 ? Vec3(normal.normalized())
                                                  : fine.normal[at(children.front())]);
    coarse.area.push_back(area);
  };
  for (const Candidate& c : candidates) {
    if (fine.parent[at(c.i)] < 0 && fine.parent[at(c.j)] < 0) add({c.i, c.j});
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (fine.parent[v] < 0) add({static_cast<int>(v)});
  }
  coarse.adjacent.resize(coarse.position.size());
  for (std::size_t i = 0; i < n; ++i) {
    for (const int j : fine.adjacent[i]) {
      const int a = fine.parent[i];
      const int b = fine.parent[at(j)];
      if (a != b) coarse.adjacent[at(a)].push_back(b);
    }
  }
  for (auto& list : coarse.adjacent) sort_unique(list);
  return coarse;
}

// Level 0 and coarser levels until one is small or stops shrinking.
std::vector<FieldGraph> field_hierarchy(FieldGraph finest) {
  std::vector<FieldGraph> levels;
  levels.push_back(std::move(finest));
  while (levels.back().position.size() > 16) {
    FieldGraph next = coarsen(levels.back());
    if (next.position.size() * 10 > levels.back().position.size() * 9) {
      levels.back().parent.clear();
      break;
    }
    levels.push_back(std::move(next));
  }
  return levels;
}

// Extrinsic 4-RoSy smoothing (Instant Meshes §3.1): every vertex moves its
// direction towards the sum of its neighbours' closest representatives,
// projected onto its tangent plane.
void smooth_orientation(const FieldGraph& g, std::vector<Vec3>& field, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    for (std::size_t v = 0; v < g.position.size(); ++v) {
      const Vec3& n = g.normal[v];
      Vec3 sum = field[v];
      double weight = 1.0;
      for (const int w : g.adjacent[v]) {
        sum += closest_representative(field[at(w)], g.normal[at(w)], sum / weight);
        weight += 1.0;
      }
      const Vec3 t = sum - n * n.dot(sum);
      if (t.norm() > 1e-12) field[v] = t.normalized();
    }
  }
}

// A fixed start (no randomness): the axis least aligned with the normal.
Vec3 start_direction(const Vec3& n) {
  const Vec3 axis = std::abs(n.x()) > 0.8 ? Vec3::UnitY() : Vec3::UnitX();
  return (axis - n * n.dot(axis)).normalized();
}

// The orientation field solved coarse to fine: the coarsest level from the
// fixed start, each finer level from its parents' directions projected onto
// its tangent planes, then smoothed (`iterations` sweeps per level). One
// field per level, level 0 first.
std::vector<std::vector<Vec3>> solve_orientation(const std::vector<FieldGraph>& levels,
                                                 int iterations) {
  std::vector<std::vector<Vec3>> fields(levels.size());
  for (std::size_t k = levels.size(); k-- > 0;) {
    const FieldGraph& g = levels[k];
    std::vector<Vec3>& field = fields[k];
    field.resize(g.position.size());
    for (std::size_t v = 0; v < g.position.size(); ++v) {
      const Vec3& n = g.normal[v];
      if (k + 1 == levels.size()) {
        field[v] = start_direction(n);
        continue;
      }
      const Vec3& up = fields[k + 1][at(g.parent[v])];
      const Vec3 t = up - n * n.dot(up);
      field[v] = t.norm() > 1e-9 ? Vec3(t.normalized()) : start_direction(n);
    }
    smooth_orientation(g, field, iterations);
  }
  return fields;
}

// The point between p0 and p1 closest to both tangent planes (Instant
// Meshes' middle_point): where the lattices of two neighbours are compared.
Vec3 middle_point(const Vec3& p0, const Vec3& n0, const Vec3& p1, const Vec3& n1) {
  const double n0p0 = n0.dot(p0), n0p1 = n0.dot(p1), n1p0 = n1.dot(p0), n1p1 = n1.dot(p1);
  const double n0n1 = n0.dot(n1);
  const double denom = 1.0 / (1.0 - n0n1 * n0n1 + 1e-4);
  const double l0 = 2.0 * (n0p1 - n0p0 - n0n1 * (n1p0 - n1p1)) * denom;
  const double l1 = 2.0 * (n1p0 - n1p1 - n0n1 * (n0p1 - n0p0)) * denom;
  return 0.5 * (p0 + p1) - 0.25 * (n0 * l0 + n1 * l1);
}

// Lattice (origin o, axes q and n x q, spacing s): the point at or below
// `target` in both axes.
Vec3 lattice_floor(const Vec3& o, const Vec3& q, const Vec3& n, const Vec3& target, double s) {
  const Vec3 t = n.cross(q);
  const Vec3 d = target - o;
  return o + q * std::floor(q.dot(d) / s) * s + t * std::floor(t.dot(d) / s) * s;
}

Vec3 lattice_round(const Vec3& o, const Vec3& q, const Vec3& n, const Vec3& target, double s) {
  const Vec3 t = n.cross(q);
  const Vec3 d = target - o;
  return o + q * std::round(q.dot(d) / s) * s + t * std::round(t.dot(d) / s) * s;
}

}  // namespace

std::pair<Vec3, Vec3> compatible_positions(const Vec3& p0, const Vec3& n0, const Vec3& q0,
                                           const Vec3& o0, const Vec3& p1, const Vec3& n1,
                                           const Vec3& q1, const Vec3& o1, double s) {
  const Vec3 t0 = n0.cross(q0);
  const Vec3 t1 = n1.cross(q1);
  const Vec3 middle = middle_point(p0, n0, p1, n1);
  const Vec3 f0 = lattice_floor(o0, q0, n0, middle, s);
  const Vec3 f1 = lattice_floor(o1, q1, n1, middle, s);
  double best = std::numeric_limits<double>::infinity();
  std::pair<Vec3, Vec3> result{f0, f1};
  for (int i = 0; i < 4; ++i) {
    const Vec3 a = f0 + (q0 * (i & 1) + t0 * ((i & 2) >> 1)) * s;
    for (int j = 0; j < 4; ++j) {
      const Vec3 b = f1 + (q1 * (j & 1) + t1 * ((j & 2) >> 1)) * s;
      const double d = (a - b).squaredNorm();
      if (d < best) {
        best = d;
        result = {a, b};
      }
    }
  }
  return result;
}

namespace {

// 4-PoSy smoothing (Instant Meshes §3.2, extrinsic): each lattice origin
// moves to the average of its neighbours' compatible lattice points, then
// snaps to the lattice point nearest its own vertex.
void smooth_position(const FieldGraph& g, const std::vector<Vec3>& q, std::vector<Vec3>& origin,
                     double s, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    for (std::size_t v = 0; v < g.position.size(); ++v) {
      const Vec3& p = g.position[v];
      const Vec3& n = g.normal[v];
      const Vec3& qv = q[v];
      Vec3 sum = origin[v];
      double weight = 0.0;
      for (const int w : g.adjacent[v]) {
        const Vec3 qw = closest_representative(q[at(w)], g.normal[at(w)], qv);
        const auto [a, b] = compatible_positions(p, n, qv, sum, g.position[at(w)], g.normal[at(w)],
                                                 qw, origin[at(w)], s);
        sum = (a * weight + b) / (weight + 1.0);
        weight += 1.0;
        sum -= n * n.dot(sum - p);
      }
      origin[v] = lattice_round(sum, qv, n, p, s);
    }
  }
}

// The position field coarse to fine, as the orientation: each vertex starts
// from its parent's lattice origin moved onto its own tangent plane.
std::vector<Vec3> solve_position(const std::vector<FieldGraph>& levels,
                                 const std::vector<std::vector<Vec3>>& fields, double s,
                                 int iterations) {
  std::vector<Vec3> origin;
  for (std::size_t k = levels.size(); k-- > 0;) {
    const FieldGraph& g = levels[k];
    std::vector<Vec3> next(g.position.size());
    for (std::size_t v = 0; v < g.position.size(); ++v) {
      const Vec3& p = g.position[v];
      const Vec3& n = g.normal[v];
      if (k + 1 == levels.size()) {
        next[v] = p;
        continue;
      }
      const Vec3& up = origin[at(g.parent[v])];
      next[v] = up - n * n.dot(up - p);
    }
    origin = std::move(next);
    smooth_position(g, fields[k], origin, s, iterations);
  }
  return origin;
}

}  // namespace

LatticeFields solve_fields(const HalfedgeMesh& samples, double s, int orientation_iterations,
                           int position_iterations) {
  std::vector<FieldGraph> levels = field_hierarchy(sample_graph(samples));
  std::vector<std::vector<Vec3>> orientation = solve_orientation(levels, orientation_iterations);
  LatticeFields fields;
  fields.origin = solve_position(levels, orientation, s, position_iterations);
  fields.normal = std::move(levels.front().normal);
  fields.orientation = std::move(orientation.front());
  return fields;
}

}  // namespace remesh_detail

std::vector<Vec3> orientation_field(const HalfedgeMesh& mesh, std::vector<Vec3>& normals,
                                    int iterations) {
  std::vector<remesh_detail::FieldGraph> levels =
      remesh_detail::field_hierarchy(remesh_detail::sample_graph(mesh));
  normals = levels.front().normal;
  return std::move(remesh_detail::solve_orientation(levels, iterations).front());
}

}  // namespace planner
