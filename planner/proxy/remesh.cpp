#include "planner/proxy/remesh.hpp"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModEdgeLengthT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

#include "knitout/diagnostic.hpp"
#include "planner/common/index.hpp"
#include "planner/common/union_find.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/soup.hpp"

namespace planner {

namespace {

struct TriTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  HalfedgeAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::PrevHalfedge);
};
using TriMesh = OpenMesh::TriMesh_ArrayKernelT<TriTraits>;

TriMesh to_trimesh(const PolygonMesh& input) {
  TriMesh tri;
  std::vector<TriMesh::VertexHandle> handles;
  handles.reserve(input.positions.size());
  for (const Vec3& p : input.positions) {
    handles.push_back(tri.add_vertex(TriMesh::Point(p.x(), p.y(), p.z())));
  }
  for (const auto& face : input.faces) {
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      const auto fh = tri.add_face(handles[static_cast<std::size_t>(face[0])],
                                   handles[static_cast<std::size_t>(face[i])],
                                   handles[static_cast<std::size_t>(face[i + 1])]);
      if (!fh.is_valid()) throw std::logic_error("resample: checked mesh rejected by OpenMesh");
    }
  }
  return tri;
}

PolygonMesh from_trimesh(TriMesh& tri) {
  tri.garbage_collection();
  PolygonMesh out;
  out.positions.reserve(tri.n_vertices());
  for (const auto vh : tri.vertices()) {
    const auto& p = tri.point(vh);
    out.positions.emplace_back(p[0], p[1], p[2]);
  }
  for (const auto fh : tri.faces()) {
    std::vector<int> face;
    for (const auto vh : tri.fv_range(fh)) face.push_back(vh.idx());
    out.faces.push_back(std::move(face));
  }
  return out;
}

// Shortest edges collapse first until none is shorter than `target`; normal
// flips are refused and OpenMesh's link condition keeps the topology. With
// `guard_aspect`, a collapse may also not make the worst triangle around it
// thinner than aspect ratio 10 unless it was already: slower, and used only
// when the plain pass leaves a zero-area sliver (which happened at one scale
// of a mesh and not at another, and made the samples depend on the units).
PolygonMesh decimate(const PolygonMesh& input, double target, bool guard_aspect) {
  TriMesh tri = to_trimesh(input);
  tri.update_face_normals();
  tri.update_vertex_normals();
  {
    using Decimater = OpenMesh::Decimater::DecimaterT<TriMesh>;
    using EdgeLength = OpenMesh::Decimater::ModEdgeLengthT<TriMesh>::Handle;
    using NormalFlipping = OpenMesh::Decimater::ModNormalFlippingT<TriMesh>::Handle;
    using AspectRatio = OpenMesh::Decimater::ModAspectRatioT<TriMesh>::Handle;
    Decimater decimater(tri);
    EdgeLength edge_length;
    NormalFlipping normal_flipping;
    AspectRatio aspect_ratio;
    decimater.add(edge_length);
    decimater.add(normal_flipping);
    if (guard_aspect) {
      decimater.add(aspect_ratio);
      decimater.module(aspect_ratio).set_binary(true);
      decimater.module(aspect_ratio).set_aspect_ratio(10.0);
    }
    decimater.module(edge_length).set_edge_length(target);
    decimater.module(edge_length).set_binary(false);
    decimater.module(normal_flipping).set_max_normal_deviation(60.0);
    decimater.initialize();
    decimater.decimate();
  }
  return from_trimesh(tri);
}

// `decimate`, checked; once more with the aspect guard if the plain pass
// leaves a degenerate face; nothing if that fails too.
std::optional<PolygonMesh> checked_decimation(const PolygonMesh& input, double target) {
  for (const bool guard_aspect : {false, true}) {
    PolygonMesh decimated = decimate(input, target, guard_aspect);
    knitout::DiagnosticSink sink;
    if (check_mesh(decimated, "resample", sink)) return decimated;
  }
  return std::nullopt;
}

// Every edge longer than `max_length` is split at its midpoint (with the
// triangles on both sides) until none is: the fields compare neighbouring
// samples, and a sample edge longer than half a lattice step can span two
// lattice steps, which the extraction cannot connect (Instant Meshes
// subdivides its input the same way before solving).
PolygonMesh split_long_edges(const PolygonMesh& input, double max_length) {
  TriMesh tri = to_trimesh(input);
  const double limit = max_length * max_length;
  for (bool split = true; split;) {
    split = false;
    const std::size_t edges = tri.n_edges();
    for (std::size_t e = 0; e < edges; ++e) {
      const auto eh = tri.edge_handle(static_cast<int>(e));
      const auto heh = tri.halfedge_handle(eh, 0);
      const auto& a = tri.point(tri.from_vertex_handle(heh));
      const auto& b = tri.point(tri.to_vertex_handle(heh));
      if ((b - a).sqrnorm() <= limit) continue;
      tri.split(eh, TriMesh::Point((a + b) * 0.5));
      split = true;
    }
  }
  return from_trimesh(tri);
}

// 1-to-4 midpoint subdivision of a triangle mesh (positions unchanged).
PolygonMesh subdivide(const PolygonMesh& mesh) {
  PolygonMesh out;
  out.positions = mesh.positions;
  std::map<std::pair<int, int>, int> midpoint;
  auto mid = [&](int a, int b) {
    const auto key = undirected_edge(a, b);
    auto it = midpoint.find(key);
    if (it != midpoint.end()) return it->second;
    out.positions.push_back(0.5 * (mesh.positions[at(a)] + mesh.positions[at(b)]));
    const int id = static_cast<int>(out.positions.size()) - 1;
    midpoint.emplace(key, id);
    return id;
  };
  for (const auto& f : mesh.faces) {
    const int ab = mid(f[0], f[1]);
    const int bc = mid(f[1], f[2]);
    const int ca = mid(f[2], f[0]);
    out.faces.push_back({f[0], ab, ca});
    out.faces.push_back({ab, f[1], bc});
    out.faces.push_back({ca, bc, f[2]});
    out.faces.push_back({ab, bc, ca});
  }
  return out;
}

}  // namespace

PolygonMesh resample(const PolygonMesh& input, double target_mm, double keep_above) {
  PolygonMesh tri;
  tri.positions = input.positions;
  for (const auto& face : input.faces) {
    for (std::size_t i = 1; i + 1 < face.size(); ++i)
      tri.faces.push_back({face[0], face[i], face[i + 1]});
  }
  // Coarse input is refined; input within a factor 2 of the target is used
  // as it is; only a much finer one is decimated (the decimater is the
  // slowest step, so it is kept for the meshes that need it).
  while (mean_edge_length(tri) > 2.0 * target_mm && tri.faces.size() < 4000000)
    tri = subdivide(tri);
  if (mean_edge_length(tri) < keep_above * target_mm) {
    // OpenMesh keeps the topology; should a collapse still leave a fold, the
    // finer mesh is the safe answer.
    std::optional<PolygonMesh> decimated = checked_decimation(tri, target_mm);
    if (decimated) tri = std::move(*decimated);
  }
  return tri;
}

PolygonMesh sample_surface(const PolygonMesh& input, double target_mm) {
  PolygonMesh tri = split_long_edges(resample(input, target_mm), 1.25 * target_mm);
  std::size_t edges = 0;
  std::size_t short_edges = 0;
  for (const auto& face : tri.faces) {
    for (std::size_t i = 0; i < face.size(); ++i) {
      const double length =
          (tri.positions[at(face[(i + 1) % face.size()])] - tri.positions[at(face[i])]).norm();
      ++edges;
      if (length < 0.5 * target_mm) ++short_edges;
    }
  }
  if (short_edges * 5 <= edges) return tri;
  std::optional<PolygonMesh> decimated = checked_decimation(tri, 0.7 * target_mm);
  if (!decimated) return tri;
  return split_long_edges(*decimated, 1.25 * target_mm);
}

// The representative of the 4-fold direction (o, n x o, -o, -n x o) closest to `target`.
Vec3 closest_representative(const Vec3& o, const Vec3& n, const Vec3& target) {
  const Vec3 q = n.cross(o);
  const double a = o.dot(target);
  const double b = q.dot(target);
  if (std::abs(a) >= std::abs(b)) return a >= 0 ? o : Vec3(-o);
  return b >= 0 ? q : Vec3(-q);
}

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
      if (static_cast<std::size_t>(j) <= i) continue;
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
  for (auto& list : coarse.adjacent) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
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

}  // namespace

std::vector<Vec3> orientation_field(const HalfedgeMesh& mesh, std::vector<Vec3>& normals,
                                    int iterations) {
  std::vector<FieldGraph> levels = field_hierarchy(sample_graph(mesh));
  normals = levels.front().normal;
  return std::move(solve_orientation(levels, iterations).front());
}

namespace {

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

// The closest pair of lattice points of two neighbours near their middle
// (Instant Meshes' compat_position_extrinsic_4); q1 already matches q0.
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

// A vertex whose faces form several fans (sheets touching at a point) gets
// one copy per fan, so the surface becomes a manifold there. Each copy, and
// the vertex itself, is then moved 2% of the way to its fan's centre, so
// the sheets no longer touch: later stages that weld the cut mesh's two
// sides by position (the wearability stage) must not merge them again.
void split_pinched_vertices(PolygonMesh& mesh) {
  const std::vector<int> start = corner_starts(mesh);
  UnionFind corners = corner_fans(mesh, start);
  std::vector<int> owner(mesh.positions.size(), -1);  // fan root that keeps the original vertex
  std::map<int, int> copy_of_root;
  std::vector<int> split;  // the vertices split and their copies
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (std::size_t i = 0; i < mesh.faces[f].size(); ++i) {
      int& v = mesh.faces[f][i];
      const int root = corners.find(start[f] + static_cast<int>(i));
      if (owner[at(v)] < 0) owner[at(v)] = root;
      if (owner[at(v)] == root) continue;
      auto [it, inserted] = copy_of_root.emplace(root, static_cast<int>(mesh.positions.size()));
      if (inserted) {
        mesh.positions.push_back(mesh.positions[at(v)]);
        split.push_back(v);
        split.push_back(it->second);
      }
      v = it->second;
    }
  }
  if (split.empty()) return;
  std::vector<Vec3> centre(mesh.positions.size(), Vec3::Zero());
  std::vector<int> count(mesh.positions.size(), 0);
  for (const auto& face : mesh.faces) {
    Vec3 c = Vec3::Zero();
    for (int v : face) c += mesh.positions[at(v)];
    c /= static_cast<double>(face.size());
    for (int v : face) {
      centre[at(v)] += c;
      ++count[at(v)];
    }
  }
  std::sort(split.begin(), split.end());
  split.erase(std::unique(split.begin(), split.end()), split.end());
  for (int v : split) {
    if (count[at(v)] == 0) continue;
    Vec3& p = mesh.positions[at(v)];
    p += 0.02 * (centre[at(v)] / count[at(v)] - p);
  }
}

}  // namespace

int collapse_folded_quads(PolygonMesh& mesh, double ratio) {
  int collapsed = 0;
  for (bool changed = true; changed;) {
    changed = false;
    const std::size_t n = mesh.positions.size();
    std::vector<std::vector<int>> ring(n);
    std::vector<std::vector<int>> faces_of(n);
    std::map<std::pair<int, int>, int> uses;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const auto& face = mesh.faces[f];
      for (std::size_t i = 0; i < face.size(); ++i) {
        const int a = face[i];
        const int b = face[(i + 1) % face.size()];
        ring[at(a)].push_back(b);
        ring[at(b)].push_back(a);
        faces_of[at(a)].push_back(static_cast<int>(f));
        ++uses[undirected_edge(a, b)];
      }
    }
    std::vector<bool> boundary(n, false);
    for (const auto& [edge, count] : uses) {
      if (count == 1) boundary[at(edge.first)] = boundary[at(edge.second)] = true;
    }
    for (auto& list : ring) {
      std::sort(list.begin(), list.end());
      list.erase(std::unique(list.begin(), list.end()), list.end());
    }
    for (std::size_t f = 0; f < mesh.faces.size() && !changed; ++f) {
      const auto& face = mesh.faces[f];
      if (face.size() != 4) continue;
      for (std::size_t i = 0; i < 2; ++i) {
        const int a = face[i];
        const int c = face[i + 2];
        const int b = face[i + 1];
        const int d = face[(i + 3) % 4];
        const double diagonal = (mesh.positions[at(a)] - mesh.positions[at(c)]).norm();
        const double other = (mesh.positions[at(b)] - mesh.positions[at(d)]).norm();
        if (!(diagonal < ratio * other) || (boundary[at(a)] && boundary[at(c)])) continue;
        std::vector<int> common;
        std::set_intersection(ring[at(a)].begin(), ring[at(a)].end(), ring[at(c)].begin(),
                              ring[at(c)].end(), std::back_inserter(common));
        if (common != std::vector<int>{std::min(b, d), std::max(b, d)}) continue;
        const auto& fa = faces_of[at(a)];
        const auto& fc = faces_of[at(c)];
        const bool shared = std::any_of(fa.begin(), fa.end(), [&](int g) {
          return g != static_cast<int>(f) && std::find(fc.begin(), fc.end(), g) != fc.end();
        });
        if (shared) continue;
        const Vec3 middle = boundary[at(a)] ? mesh.positions[at(a)]
                            : boundary[at(c)]
                                ? mesh.positions[at(c)]
                                : 0.5 * (mesh.positions[at(a)] + mesh.positions[at(c)]);
        mesh.positions[at(a)] = middle;
        mesh.faces.erase(mesh.faces.begin() + static_cast<std::ptrdiff_t>(f));
        for (auto& g : mesh.faces) std::replace(g.begin(), g.end(), c, a);
        ++collapsed;
        changed = true;
        break;
      }
    }
  }
  if (collapsed > 0) drop_unused_vertices(mesh);
  return collapsed;
}

namespace {

// Folded quads welded, and any vertex the welds leave pinched split again,
// until none is left. Returns how many quads were welded.
int weld_folds(PolygonMesh& mesh, double ratio) {
  int welded = 0;
  for (int folds; (folds = collapse_folded_quads(mesh, ratio)) > 0;) {
    welded += folds;
    split_pinched_vertices(mesh);
  }
  return welded;
}

// Crumbs of a few faces left where the lattice folded are dropped; a
// second big component is kept (and fails the topology check).
void keep_largest_component(PolygonMesh& mesh) {
  UnionFind vertices = vertex_components(mesh);
  std::map<int, std::size_t> size;
  for (const auto& face : mesh.faces) ++size[vertices.find(face[0])];
  if (size.size() <= 1) return;
  const auto largest = std::max_element(size.begin(), size.end(), [](const auto& a, const auto& b) {
                         return a.second < b.second;
                       })->first;
  std::size_t others = 0;
  for (const auto& [root, count] : size) others += root == largest ? 0 : count;
  if (others * 50 > mesh.faces.size()) return;
  std::vector<std::vector<int>> kept;
  for (auto& face : mesh.faces) {
    if (vertices.find(face[0]) == largest) kept.push_back(std::move(face));
  }
  mesh.faces = std::move(kept);
  drop_unused_vertices(mesh);
}

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

// Where the tracing left a face out (a walk that did not close, a loop
// dropped as a spike) the extracted surface has a hole the input does not
// have. Every boundary loop but the `keep` longest is closed by one polygon
// (the proxy splits polygons into quads and triangles, §4.1); a hole wider
// than `max_corners` is left, and the topology check then rejects the mesh.
// Instant Meshes' extraction closes its holes the same way. Returns the
// number of holes closed. Vertices must not be pinched (one boundary gap
// each), so every boundary loop is simple.
int fill_holes(PolygonMesh& mesh, int keep, std::size_t max_corners) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& face : mesh.faces) {
    for (std::size_t i = 0; i < face.size(); ++i)
      ++directed[{face[i], face[(i + 1) % face.size()]}];
  }
  std::unordered_map<int, int> boundary_next;
  for (const auto& [edge, count] : directed) {
    if (directed.count({edge.second, edge.first}) == 0) boundary_next[edge.first] = edge.second;
  }
  std::vector<std::vector<int>> loops;
  std::vector<double> lengths;
  std::unordered_map<int, bool> seen;
  for (const auto& [start, unused] : boundary_next) {
    if (seen[start]) continue;
    std::vector<int> loop;
    double length = 0.0;
    for (int v = start; !seen[v]; v = boundary_next.at(v)) {
      seen[v] = true;
      loop.push_back(v);
      const auto next = boundary_next.find(v);
      if (next == boundary_next.end()) return 0;  // an open chain: not a manifold rim
      length += (mesh.positions[at(next->second)] - mesh.positions[at(v)]).norm();
    }
    loops.push_back(std::move(loop));
    lengths.push_back(length);
  }
  std::vector<std::size_t> order(loops.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return lengths[a] > lengths[b]; });
  int closed = 0;
  for (std::size_t k = static_cast<std::size_t>(std::max(keep, 0)); k < order.size(); ++k) {
    std::vector<int>& loop = loops[order[k]];
    if (loop.size() < 3 || loop.size() > max_corners) continue;
    // The rim runs against the faces around it; the new face runs along it.
    std::reverse(loop.begin(), loop.end());
    mesh.faces.push_back(std::move(loop));
    ++closed;
  }
  return closed;
}

// Sorted, without repeats.
void sort_unique(std::vector<int>& list) {
  std::sort(list.begin(), list.end());
  list.erase(std::unique(list.begin(), list.end()), list.end());
}

// The two fields per sample, as the extraction reads them.
struct LatticeFields {
  std::vector<Vec3> normal;
  std::vector<Vec3> orientation;  // 4-RoSy: one of the lattice's four axis directions
  std::vector<Vec3> origin;       // 4-PoSy: a lattice point near the sample
};

// The orientation field, then the position field on its lattice spacing
// `s`, both solved coarse to fine over the hierarchy of the samples' graph.
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

// The graph the extraction builds and then traces: its vertices are
// lattice points, its edges lattice steps.
struct LatticeGraph {
  std::vector<Vec3> position;
  std::vector<Vec3> normal;    // unit
  std::vector<Vec3> axis;      // the orientation field at the vertex: its angular reference
  std::vector<bool> boundary;  // made from a sample on the input's boundary
  std::vector<std::vector<int>> adjacent;
};

// The vertices of `fine` grouped into classes, root[v] naming v's class;
// classes are numbered in the order of their first vertex. A class sits at
// the mean of its vertices' positions, with the normalised sum of their
// normals and its first vertex's axis, on the boundary when one of its
// vertices is. Returns each vertex's class; `merged` gets the classes, with
// no adjacency yet.
std::vector<int> merge_classes(const LatticeGraph& fine, const std::vector<int>& root,
                               LatticeGraph& merged) {
  const std::size_t n = fine.position.size();
  std::vector<int> class_of_root(n, -1);
  std::vector<int> class_of(n, -1);
  std::vector<int> count;
  merged = LatticeGraph{};
  for (std::size_t v = 0; v < n; ++v) {
    int& c = class_of_root[at(root[v])];
    if (c < 0) {
      c = static_cast<int>(merged.position.size());
      merged.position.push_back(Vec3::Zero());
      merged.normal.push_back(Vec3::Zero());
      merged.axis.push_back(fine.axis[v]);
      merged.boundary.push_back(false);
      count.push_back(0);
    }
    class_of[v] = c;
    merged.position[at(c)] += fine.position[v];
    merged.normal[at(c)] += fine.normal[v];
    merged.boundary[at(c)] = merged.boundary[at(c)] || fine.boundary[v];
    ++count[at(c)];
  }
  for (std::size_t c = 0; c < merged.position.size(); ++c) {
    merged.position[c] /= count[c];
    merged.normal[c].normalize();
  }
  merged.adjacent.resize(merged.position.size());
  return class_of;
}

// Along every sample edge, the integer lattice offset between the lattice
// points of its two ends: ends at offset 0 are one output vertex
// (`same_point` joins them), ends one step apart make an output edge.
struct LatticeLinks {
  UnionFind same_point;
  std::vector<std::pair<int, int>> unit_edges;
};

LatticeLinks lattice_links(const HalfedgeMesh& mesh, const LatticeFields& fields, double s) {
  const std::vector<Vec3>& normals = fields.normal;
  const std::vector<Vec3>& q = fields.orientation;
  const std::vector<Vec3>& origin = fields.origin;
  LatticeLinks links{UnionFind(at(mesh.num_vertices())), {}};
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    const int i = mesh.from(h);
    const int j = mesh.to(h);
    if (mesh.twin(h) >= 0 && i > j) continue;
    const Vec3& ni = normals[at(i)];
    const Vec3& qi = q[at(i)];
    const Vec3 qj = closest_representative(q[at(j)], normals[at(j)], qi);
    const auto [a, b] =
        compatible_positions(mesh.position(i), ni, qi, origin[at(i)], mesh.position(j),
                             normals[at(j)], qj, origin[at(j)], s);
    const Vec3 ti = ni.cross(qi);
    const Vec3 tj = normals[at(j)].cross(qj);
    const long di0 = std::lround(qi.dot(a - origin[at(i)]) / s);
    const long di1 = std::lround(ti.dot(a - origin[at(i)]) / s);
    const long dj0 = std::lround(qj.dot(b - origin[at(j)]) / s);
    const long dj1 = std::lround(tj.dot(b - origin[at(j)]) / s);
    const long du = di0 - dj0;
    const long dv = di1 - dj1;
    const long manhattan = std::labs(du) + std::labs(dv);
    if (manhattan == 0)
      links.same_point.unite(i, j);
    else if (manhattan == 1)
      links.unit_edges.emplace_back(i, j);
  }
  return links;
}

// The output graph: one vertex per class of samples at one lattice point,
// at the mean of their lattice origins, an edge per pair of classes one
// lattice step apart.
LatticeGraph lattice_graph(const HalfedgeMesh& mesh, LatticeFields fields, double s) {
  LatticeLinks links = lattice_links(mesh, fields, s);
  const int nv = mesh.num_vertices();
  std::vector<int> root(at(nv));
  std::vector<bool> boundary(at(nv));
  for (int v = 0; v < nv; ++v) {
    root[at(v)] = links.same_point.find(v);
    boundary[at(v)] = mesh.is_boundary_vertex(v);
  }
  const LatticeGraph samples{std::move(fields.origin),
                             std::move(fields.normal),
                             std::move(fields.orientation),
                             std::move(boundary),
                             {}};
  LatticeGraph graph;
  const std::vector<int> cls = merge_classes(samples, root, graph);
  for (const auto& [i, j] : links.unit_edges) {
    const int a = cls[at(i)];
    const int b = cls[at(j)];
    if (a == b) continue;
    graph.adjacent[at(a)].push_back(b);
    graph.adjacent[at(b)].push_back(a);
  }
  for (auto& list : graph.adjacent) sort_unique(list);
  return graph;
}

// Lattice vertices joined by an edge shorter than `below` are one vertex
// (the extraction's rounding leaves such pairs where the position field
// bends, and they would become needle-thin faces). Pairs only: a vertex
// merged once is not merged again, so a row of short edges does not
// collapse into one point. Positions and normals are averaged; adjacency
// lists are renumbered, sorted and free of self-loops.
void merge_short_edges(double below, LatticeGraph& g) {
  const std::size_t n = g.position.size();
  std::vector<int> into(n, -1);
  std::vector<std::tuple<double, int, int>> short_edges;
  for (std::size_t a = 0; a < n; ++a) {
    for (int b : g.adjacent[a]) {
      const double length = (g.position[at(b)] - g.position[a]).norm();
      if (static_cast<int>(a) < b && length < below)
        short_edges.emplace_back(length, static_cast<int>(a), b);
    }
  }
  if (short_edges.empty()) return;
  std::sort(short_edges.begin(), short_edges.end());
  for (const auto& [length, a, b] : short_edges) {
    if (into[at(a)] >= 0 || into[at(b)] >= 0) continue;
    into[at(a)] = a;
    into[at(b)] = a;
  }
  std::vector<int> root(n);
  for (std::size_t v = 0; v < n; ++v) root[v] = into[v] >= 0 ? into[v] : static_cast<int>(v);
  LatticeGraph merged;
  const std::vector<int> index = merge_classes(g, root, merged);
  for (std::size_t v = 0; v < n; ++v) {
    for (int o : g.adjacent[v]) {
      if (index[v] != index[at(o)]) merged.adjacent[at(index[v])].push_back(index[at(o)]);
    }
  }
  for (auto& list : merged.adjacent) sort_unique(list);
  g = std::move(merged);
}

// Dangling edges bound no face: peel them off.
void peel_dangling_edges(LatticeGraph& g) {
  const int nc = static_cast<int>(g.position.size());
  for (bool changed = true; changed;) {
    changed = false;
    for (int c = 0; c < nc; ++c) {
      if (g.adjacent[at(c)].size() != 1) continue;
      const int other = g.adjacent[at(c)][0];
      g.adjacent[at(c)].clear();
      auto& list = g.adjacent[at(other)];
      list.erase(std::remove(list.begin(), list.end(), c), list.end());
      changed = true;
    }
  }
}

// Neighbours in counter-clockwise order around each vertex's normal,
// angles measured from its axis.
void sort_neighbours_by_angle(LatticeGraph& g) {
  for (std::size_t c = 0; c < g.position.size(); ++c) {
    const Vec3& n = g.normal[c];
    const Vec3 x = (g.axis[c] - n * n.dot(g.axis[c])).normalized();
    const Vec3 y = n.cross(x);
    auto angle = [&](int o) {
      const Vec3 d = g.position[at(o)] - g.position[c];
      return std::atan2(d.dot(y), d.dot(x));
    };
    std::sort(g.adjacent[c].begin(), g.adjacent[c].end(),
              [&](int a, int b) { return angle(a) < angle(b); });
  }
}

// A hole of an open surface is traced like a face along its rim; its
// centre lies in the opening, farther than 0.6 lattice steps `s` from
// every sample of the surface.
bool is_hole(const std::vector<int>& loop, const LatticeGraph& g, const HalfedgeMesh& samples,
             double s) {
  bool touches_boundary = false;
  Vec3 centre = Vec3::Zero();
  for (int v : loop) {
    touches_boundary = touches_boundary || g.boundary[at(v)];
    centre += g.position[at(v)];
  }
  if (!touches_boundary) return false;
  centre /= static_cast<double>(loop.size());
  double nearest = std::numeric_limits<double>::infinity();
  for (int v = 0; v < samples.num_vertices(); ++v)
    nearest = std::min(nearest, (samples.position(v) - centre).squaredNorm());
  return std::sqrt(nearest) > 0.6 * s;
}

// The walk that starts along a0 -> b0 and, arriving at b from a, leaves
// along the neighbour of b just clockwise of a; every step it takes is
// marked in `used`. Nothing when it has not closed after 64 steps.
std::optional<std::vector<int>> walk_face(const LatticeGraph& g, int a0, int b0,
                                          std::map<std::pair<int, int>, bool>& used) {
  std::vector<int> face;
  int a = a0;
  int b = b0;
  for (int steps = 0; steps < 64; ++steps) {
    used[{a, b}] = true;
    face.push_back(a);
    const auto& list = g.adjacent[at(b)];
    const auto it = std::find(list.begin(), list.end(), a);
    const std::size_t k = static_cast<std::size_t>(it - list.begin());
    const int next = list[(k + list.size() - 1) % list.size()];
    a = b;
    b = next;
    if (a == a0 && b == b0) return face;
  }
  return std::nullopt;
}

// A walk that meets a vertex twice runs round an island or along a bridge:
// its simple loops, without the two-corner spikes.
std::vector<std::vector<int>> simple_loops(const std::vector<int>& walk) {
  std::vector<std::vector<int>> loops;
  std::vector<int> stack;
  std::map<int, std::size_t> where;
  for (int v : walk) {
    auto found = where.find(v);
    if (found != where.end()) {
      std::vector<int> loop(stack.begin() + static_cast<std::ptrdiff_t>(found->second),
                            stack.end());
      for (std::size_t k = found->second + 1; k < stack.size(); ++k) where.erase(stack[k]);
      stack.resize(found->second + 1);
      if (loop.size() >= 3) loops.push_back(std::move(loop));
    } else {
      where[v] = stack.size();
      stack.push_back(v);
    }
  }
  if (stack.size() >= 3) loops.push_back(std::move(stack));
  return loops;
}

// The faces of the lattice graph: every directed edge not yet walked starts
// a walk; the simple loops of a closed walk are faces, except the holes of
// an open surface. Positions are the graph's, unused ones included.
PolygonMesh trace_faces(const LatticeGraph& g, const HalfedgeMesh& samples, double s) {
  std::map<std::pair<int, int>, bool> used;
  PolygonMesh out;
  out.positions = g.position;
  for (int a0 = 0; a0 < static_cast<int>(g.position.size()); ++a0) {
    for (int b0 : g.adjacent[at(a0)]) {
      if (used[{a0, b0}]) continue;
      const std::optional<std::vector<int>> walk = walk_face(g, a0, b0, used);
      if (!walk || walk->size() < 3) continue;
      for (auto& loop : simple_loops(*walk)) {
        if (!is_hole(loop, g, samples, s)) out.faces.push_back(std::move(loop));
      }
    }
  }
  return out;
}

// The lattice of the fields as polygons (Instant Meshes' extraction): the
// output graph, its short edges merged and dangling ones peeled, its faces
// traced. Unused vertices, pinches and folds are left to the clean-up.
PolygonMesh extract_lattice(const HalfedgeMesh& samples, LatticeFields fields,
                            const RemeshParams& params) {
  const double s = params.edge_mm;
  LatticeGraph graph = lattice_graph(samples, std::move(fields), s);
  merge_short_edges(params.merge_below * s, graph);
  peel_dangling_edges(graph);
  sort_neighbours_by_angle(graph);
  return trace_faces(graph, samples, s);
}

// Whether `mesh` passes the input checks; if not, stats.failure is `what`
// and the first problem.
bool is_clean_surface(const PolygonMesh& mesh, const std::string& what, RemeshStats& stats) {
  knitout::DiagnosticSink sink;
  if (check_mesh(mesh, "remesh", sink)) return true;
  stats.failure = what + ": " + sink.diagnostics().front().message;
  return false;
}

}  // namespace

std::optional<PolygonMesh> field_aligned_remesh(const PolygonMesh& input,
                                                const RemeshParams& params, RemeshStats& stats) {
  const double s = params.edge_mm;
  // Samples about half a lattice step apart, so every lattice cell holds some.
  const HalfedgeMesh samples(sample_surface(input, params.sample_ratio * s));
  stats.samples = samples.num_vertices();
  LatticeFields fields =
      solve_fields(samples, s, params.orientation_iterations, params.position_iterations);
  PolygonMesh mesh = extract_lattice(samples, std::move(fields), params);
  drop_unused_vertices(mesh);
  split_pinched_vertices(mesh);
  stats.folds_removed += weld_folds(mesh, params.fold_ratio);
  keep_largest_component(mesh);
  if (!is_clean_surface(mesh, "extracted mesh is not a clean surface", stats)) return std::nullopt;
  const HalfedgeMesh source(input);
  if (HalfedgeMesh(mesh).count_boundary_loops() > source.count_boundary_loops()) {
    stats.holes_filled = fill_holes(mesh, source.count_boundary_loops(), 16);
    if (stats.holes_filled > 0) {
      split_pinched_vertices(mesh);
      // A fold along a hole's rim has both short corners on the boundary
      // until the hole is closed.
      stats.folds_removed += weld_folds(mesh, params.fold_ratio);
      if (!is_clean_surface(mesh, "extracted mesh with its holes closed is not a clean surface",
                            stats)) {
        return std::nullopt;
      }
    }
  }
  const HalfedgeMesh result(mesh);
  if (result.euler_characteristic() != source.euler_characteristic() ||
      result.count_boundary_loops() != source.count_boundary_loops()) {
    stats.failure = "extracted mesh has Euler characteristic " +
                    std::to_string(result.euler_characteristic()) + " and " +
                    std::to_string(result.count_boundary_loops()) + " boundary loops, the input " +
                    std::to_string(source.euler_characteristic()) + " and " +
                    std::to_string(source.count_boundary_loops());
    return std::nullopt;
  }
  return mesh;
}

}  // namespace planner
