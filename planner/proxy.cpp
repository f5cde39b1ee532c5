#include "planner/proxy.hpp"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModEdgeLengthT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "planner/mesh.hpp"

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

double corner_angle_at(const PolygonMesh& mesh, const std::vector<int>& face, std::size_t i) {
  const std::size_t n = face.size();
  const Vec3& p = mesh.positions[static_cast<std::size_t>(face[i])];
  const Vec3 a = mesh.positions[static_cast<std::size_t>(face[(i + 1) % n])] - p;
  const Vec3 b = mesh.positions[static_cast<std::size_t>(face[(i + n - 1) % n])] - p;
  const double na = a.norm();
  const double nb = b.norm();
  if (na <= 0.0 || nb <= 0.0) return 0.0;
  return std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0));
}

double angle_between(const Vec3& a, const Vec3& b) {
  const double na = a.norm();
  const double nb = b.norm();
  if (na <= 0.0 || nb <= 0.0) return 0.0;
  return std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0));
}

std::vector<int> rotate_to(const std::vector<int>& face, std::size_t start) {
  std::vector<int> out(face.size());
  for (std::size_t i = 0; i < face.size(); ++i) out[i] = face[(start + i) % face.size()];
  return out;
}

double total_area(const PolygonMesh& mesh) {
  double area = 0.0;
  for (const auto& face : mesh.faces) {
    Vec3 n = Vec3::Zero();
    for (std::size_t i = 0; i < face.size(); ++i) {
      n += mesh.positions[static_cast<std::size_t>(face[i])].cross(
          mesh.positions[static_cast<std::size_t>(face[(i + 1) % face.size()])]);
    }
    area += 0.5 * n.norm();
  }
  return area;
}

// Shortest edges collapse first until none is shorter than `target`; normal
// flips are refused and OpenMesh's link condition keeps the topology.
PolygonMesh decimate(const PolygonMesh& input, double target) {
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
      if (!fh.is_valid()) throw std::logic_error("decimate: checked mesh rejected by OpenMesh");
    }
  }
  tri.update_face_normals();
  tri.update_vertex_normals();
  {
    using Decimater = OpenMesh::Decimater::DecimaterT<TriMesh>;
    using EdgeLength = OpenMesh::Decimater::ModEdgeLengthT<TriMesh>::Handle;
    using NormalFlipping = OpenMesh::Decimater::ModNormalFlippingT<TriMesh>::Handle;
    Decimater decimater(tri);
    EdgeLength edge_length;
    NormalFlipping normal_flipping;
    decimater.add(edge_length);
    decimater.add(normal_flipping);
    decimater.module(edge_length).set_edge_length(target);
    decimater.module(edge_length).set_binary(false);
    decimater.module(normal_flipping).set_max_normal_deviation(60.0);
    decimater.initialize();
    decimater.decimate();
  }
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

// The representative of the 4-fold direction (o, n x o, -o, -n x o) closest to `target`.
Vec3 closest_representative(const Vec3& o, const Vec3& n, const Vec3& target) {
  const Vec3 q = n.cross(o);
  const double a = o.dot(target);
  const double b = q.dot(target);
  if (std::abs(a) >= std::abs(b)) return a >= 0 ? o : Vec3(-o);
  return b >= 0 ? q : Vec3(-q);
}

// Extrinsic 4-RoSy smoothing (Instant Meshes, Jakob et al. 2015, §3.1):
// every vertex moves its direction towards the sum of its neighbours'
// closest representatives, projected onto its tangent plane.
std::vector<Vec3> orientation_field(const HalfedgeMesh& mesh, std::vector<Vec3>& normals,
                                    int iterations) {
  const int nv = mesh.num_vertices();
  normals.assign(static_cast<std::size_t>(nv), Vec3::Zero());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const Vec3 n = mesh.face_normal(f);
    const int start = mesh.face_start(f);
    for (int i = 0; i < mesh.degree(f); ++i)
      normals[static_cast<std::size_t>(mesh.from(start + i))] += n;
  }
  std::vector<Vec3> field(static_cast<std::size_t>(nv));
  for (int v = 0; v < nv; ++v) {
    Vec3& n = normals[static_cast<std::size_t>(v)];
    if (n.norm() > 0)
      n.normalize();
    else
      n = Vec3::UnitZ();
    // A fixed start (no randomness): the axis least aligned with the normal.
    Vec3 axis = Vec3::UnitX();
    if (std::abs(n.x()) > 0.8) axis = Vec3::UnitY();
    field[static_cast<std::size_t>(v)] = (axis - n * n.dot(axis)).normalized();
  }
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(nv));
  for (int h = 0; h < mesh.num_halfedges(); ++h) {
    neighbours[static_cast<std::size_t>(mesh.from(h))].push_back(mesh.to(h));
    if (mesh.twin(h) < 0) neighbours[static_cast<std::size_t>(mesh.to(h))].push_back(mesh.from(h));
  }
  for (int it = 0; it < iterations; ++it) {
    for (int v = 0; v < nv; ++v) {
      const Vec3& n = normals[static_cast<std::size_t>(v)];
      Vec3 sum = field[static_cast<std::size_t>(v)];
      double weight = 1.0;
      for (int w : neighbours[static_cast<std::size_t>(v)]) {
        Vec3 r = closest_representative(field[static_cast<std::size_t>(w)],
                                        normals[static_cast<std::size_t>(w)], sum / weight);
        sum += r;
        weight += 1.0;
      }
      Vec3 t = sum - n * n.dot(sum);
      if (t.norm() > 1e-12) field[static_cast<std::size_t>(v)] = t.normalized();
    }
  }
  return field;
}

// How far edge direction `e` is from the field (0 aligned, up to ~0.29 at 45 degrees).
double misalignment(const Vec3& e, const Vec3& o, const Vec3& n) {
  const Vec3 d = e.normalized();
  const double a = std::max(std::abs(d.dot(o)), std::abs(d.dot(n.cross(o))));
  return 1.0 - a;
}

// Pairs adjacent triangles into quads whose four sides follow the field,
// best pairs first; unpaired triangles stay.
int pair_triangles(PolygonMesh& mesh, int field_iterations) {
  const HalfedgeMesh he(mesh);
  std::vector<Vec3> normals;
  const std::vector<Vec3> field = orientation_field(he, normals, field_iterations);
  struct Candidate {
    double score;
    int h;
  };
  std::vector<Candidate> candidates;
  for (int h = 0; h < he.num_halfedges(); ++h) {
    const int t = he.twin(h);
    if (t < h) continue;  // each interior edge once; boundary edges (t < 0) skipped
    if (he.degree(he.face(h)) != 3 || he.degree(he.face(t)) != 3) continue;
    const int a = he.from(h);
    const int b = he.to(h);
    const int c = he.from(he.prev(h));
    const int d = he.from(he.prev(t));
    const Vec3 n1 = he.face_normal(he.face(h)).normalized();
    const Vec3 n2 = he.face_normal(he.face(t)).normalized();
    if (n1.dot(n2) < 0.5) continue;  // too folded to be one quad
    const Vec3 n = (n1 + n2).normalized();
    // Convex at a and b: the quad a-d-b-c turns the same way everywhere.
    const std::array<int, 4> quad = {a, d, b, c};
    bool convex = true;
    for (int i = 0; i < 4; ++i) {
      const Vec3& p0 = he.position(quad[static_cast<std::size_t>(i)]);
      const Vec3& p1 = he.position(quad[static_cast<std::size_t>((i + 1) % 4)]);
      const Vec3& p2 = he.position(quad[static_cast<std::size_t>((i + 2) % 4)]);
      if ((p1 - p0).cross(p2 - p1).dot(n) <= 0) convex = false;
    }
    if (!convex) continue;
    const Vec3 o = closest_representative(field[static_cast<std::size_t>(b)],
                                          normals[static_cast<std::size_t>(b)],
                                          field[static_cast<std::size_t>(a)]) +
                   field[static_cast<std::size_t>(a)];
    if (o.norm() < 1e-12) continue;
    const Vec3 on = (o - n * n.dot(o)).normalized();
    double score = 0.0;
    for (int i = 0; i < 4; ++i) {
      score += misalignment(he.position(quad[static_cast<std::size_t>((i + 1) % 4)]) -
                                he.position(quad[static_cast<std::size_t>(i)]),
                            on, n);
    }
    // The diagonal should run at 45 degrees to the field.
    score -= misalignment(he.position(b) - he.position(a), on, n);
    candidates.push_back({score, h});
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.score < y.score; });
  std::vector<bool> used(mesh.faces.size(), false);
  std::vector<std::vector<int>> faces;
  int paired = 0;
  for (const Candidate& cand : candidates) {
    const int f1 = he.face(cand.h);
    const int f2 = he.face(he.twin(cand.h));
    if (used[static_cast<std::size_t>(f1)] || used[static_cast<std::size_t>(f2)]) continue;
    used[static_cast<std::size_t>(f1)] = used[static_cast<std::size_t>(f2)] = true;
    const int a = he.from(cand.h);
    const int b = he.to(cand.h);
    faces.push_back({a, he.from(he.prev(he.twin(cand.h))), b, he.from(he.prev(cand.h))});
    paired += 2;
  }
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!used[f]) faces.push_back(mesh.faces[f]);
  }
  mesh.faces = std::move(faces);
  return paired;
}

}  // namespace

bool is_quad_dominant(const PolygonMesh& mesh) {
  std::size_t quads = 0;
  for (const auto& face : mesh.faces) quads += face.size() == 4 ? 1 : 0;
  return 2 * quads > mesh.faces.size();
}

int split_polygons(PolygonMesh& mesh) {
  int split = 0;
  std::vector<std::vector<int>> extra;
  for (auto& face : mesh.faces) {
    if (face.size() <= 4) continue;
    ++split;
    while (face.size() > 4) {
      const std::size_t n = face.size();
      std::size_t largest = 0;
      double best = -1.0;
      for (std::size_t i = 0; i < n; ++i) {
        const double angle = corner_angle_at(mesh, face, i);
        if (angle > best) {
          best = angle;
          largest = i;
        }
      }
      std::vector<int> f = rotate_to(face, largest);  // the largest corner is f[0]
      if (n == 5) {
        // §4.1: the diagonal that best halves the largest corner.
        const Vec3& p = mesh.positions[static_cast<std::size_t>(f[0])];
        const Vec3 next = mesh.positions[static_cast<std::size_t>(f[1])] - p;
        const Vec3 prev = mesh.positions[static_cast<std::size_t>(f[4])] - p;
        const Vec3 d2 = mesh.positions[static_cast<std::size_t>(f[2])] - p;
        const Vec3 d3 = mesh.positions[static_cast<std::size_t>(f[3])] - p;
        const double imbalance2 = std::abs(angle_between(next, d2) - angle_between(d2, prev));
        const double imbalance3 = std::abs(angle_between(next, d3) - angle_between(d3, prev));
        if (imbalance2 <= imbalance3) {
          extra.push_back({f[0], f[1], f[2]});
          face = {f[0], f[2], f[3], f[4]};
        } else {
          extra.push_back({f[0], f[3], f[4]});
          face = {f[0], f[1], f[2], f[3]};
        }
      } else {
        // Cut a quad off the largest corner; a hexagon becomes two quads.
        extra.push_back({f[0], f[1], f[2], f[3]});
        std::vector<int> rest = {f[0]};
        rest.insert(rest.end(), f.begin() + 3, f.end());
        face = std::move(rest);
      }
    }
  }
  for (auto& f : extra) mesh.faces.push_back(std::move(f));
  return split;
}

ProxyResult make_proxy(const PolygonMesh& input, const ProxyParams& params) {
  ProxyResult result;
  if (is_quad_dominant(input)) {
    result.mesh = input;
    double total = 0.0;
    std::size_t count = 0;
    for (const auto& face : input.faces) {
      for (std::size_t i = 0; i < face.size(); ++i) {
        total += (input.positions[static_cast<std::size_t>(face[(i + 1) % face.size()])] -
                  input.positions[static_cast<std::size_t>(face[i])])
                     .norm();
        ++count;
      }
    }
    result.edge_mm = count > 0 ? total / static_cast<double>(count) : 0.0;
  } else {
    result.remeshed = true;
    const double area = total_area(input);
    result.edge_mm = params.proxy_edge_mm > 0.0 ? params.proxy_edge_mm
                                                : std::sqrt(area / std::max(1, params.auto_faces));
    result.mesh = decimate(input, result.edge_mm);
    result.triangles_paired = pair_triangles(result.mesh, params.field_iterations);
  }
  result.polygons_split = split_polygons(result.mesh);
  return result;
}

}  // namespace planner
