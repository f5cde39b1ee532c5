#include "planner/proxy/proxy.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <optional>
#include <set>
#include <stdexcept>

#include "planner/common/index.hpp"
#include "planner/mesh/mesh.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/soup.hpp"
#include "planner/proxy/field_proxy.hpp"
#include "planner/proxy/remesh.hpp"

namespace planner {

namespace {

double corner_angle_at(const PolygonMesh& mesh, const std::vector<int>& face, std::size_t i) {
  const std::size_t n = face.size();
  const Vec3& p = mesh.positions[at(face[i])];
  return angle_between(mesh.positions[at(face[(i + 1) % n])] - p,
                       mesh.positions[at(face[(i + n - 1) % n])] - p);
}

std::vector<int> rotate_to(const std::vector<int>& face, std::size_t start) {
  std::vector<int> out(face.size());
  for (std::size_t i = 0; i < face.size(); ++i) out[i] = face[(start + i) % face.size()];
  return out;
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
      const Vec3& p0 = he.position(quad[at(i)]);
      const Vec3& p1 = he.position(quad[at((i + 1) % 4)]);
      const Vec3& p2 = he.position(quad[at((i + 2) % 4)]);
      if ((p1 - p0).cross(p2 - p1).dot(n) <= 0) convex = false;
    }
    if (!convex) continue;
    const Vec3 o =
        closest_representative(field[at(b)], normals[at(b)], field[at(a)]) + field[at(a)];
    if (o.norm() < 1e-12) continue;
    const Vec3 on = (o - n * n.dot(o)).normalized();
    double score = 0.0;
    for (int i = 0; i < 4; ++i) {
      score += misalignment(he.position(quad[at((i + 1) % 4)]) - he.position(quad[at(i)]), on, n);
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
    if (used[at(f1)] || used[at(f2)]) continue;
    used[at(f1)] = used[at(f2)] = true;
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

bool is_valid_proxy(const PolygonMesh& mesh) {
  for (const auto& face : mesh.faces) {
    if (face.size() > 4) return false;
  }
  knitout::DiagnosticSink sink;
  return check_mesh(mesh, "proxy", sink);
}

}  // namespace

double total_area(const PolygonMesh& mesh) {
  double area = 0.0;
  for (const auto& face : mesh.faces) area += vector_area(mesh, face).norm();
  return area;
}

bool is_quad_dominant(const PolygonMesh& mesh) {
  std::size_t quads = 0;
  for (const auto& face : mesh.faces) quads += face.size() == 4 ? 1 : 0;
  return 2 * quads > mesh.faces.size();
}

int split_polygons(PolygonMesh& mesh) {
  // A diagonal must not repeat an edge the mesh already has (it would be
  // shared by three faces then): such corners are passed over.
  std::set<std::pair<int, int>> edges;
  for (const auto& face : mesh.faces) {
    for (std::size_t i = 0; i < face.size(); ++i)
      edges.insert(undirected_edge(face[i], face[(i + 1) % face.size()]));
  }
  int split = 0;
  std::vector<std::vector<int>> extra;
  for (auto& face : mesh.faces) {
    if (face.size() <= 4) continue;
    ++split;
    while (face.size() > 4) {
      const std::size_t n = face.size();
      std::vector<std::pair<double, std::size_t>> corners;
      for (std::size_t i = 0; i < n; ++i) corners.emplace_back(-corner_angle_at(mesh, face, i), i);
      std::stable_sort(corners.begin(), corners.end());
      bool done = false;
      for (const auto& [negative_angle, largest] : corners) {
        std::vector<int> f = rotate_to(face, largest);  // the largest corner is f[0]
        if (n == 5) {
          // §4.1: the diagonal that best halves the largest corner.
          const Vec3& p = mesh.positions[at(f[0])];
          const Vec3 next = mesh.positions[at(f[1])] - p;
          const Vec3 prev = mesh.positions[at(f[4])] - p;
          const Vec3 d2 = mesh.positions[at(f[2])] - p;
          const Vec3 d3 = mesh.positions[at(f[3])] - p;
          const double imbalance2 = std::abs(angle_between(next, d2) - angle_between(d2, prev));
          const double imbalance3 = std::abs(angle_between(next, d3) - angle_between(d3, prev));
          const bool free2 = !edges.count(undirected_edge(f[0], f[2]));
          const bool free3 = !edges.count(undirected_edge(f[0], f[3]));
          if (free2 && (imbalance2 <= imbalance3 || !free3)) {
            extra.push_back({f[0], f[1], f[2]});
            face = {f[0], f[2], f[3], f[4]};
            edges.insert(undirected_edge(f[0], f[2]));
          } else if (free3) {
            extra.push_back({f[0], f[3], f[4]});
            face = {f[0], f[1], f[2], f[3]};
            edges.insert(undirected_edge(f[0], f[3]));
          } else {
            continue;
          }
        } else {
          // Cut a quad off the largest corner; a hexagon becomes two quads.
          if (edges.count(undirected_edge(f[0], f[3]))) continue;
          extra.push_back({f[0], f[1], f[2], f[3]});
          edges.insert(undirected_edge(f[0], f[3]));
          std::vector<int> rest = {f[0]};
          rest.insert(rest.end(), f.begin() + 3, f.end());
          face = std::move(rest);
        }
        done = true;
        break;
      }
      if (!done) break;  // no free diagonal: left for the caller's check
    }
  }
  for (auto& f : extra) mesh.faces.push_back(std::move(f));
  return split;
}

namespace {

// The fallback when no extraction gives a clean proxy: the surface
// resampled at 0.8 times the target edge and its triangles paired along
// the field. `why` says what failed.
void pair_resampled(const PolygonMesh& input, const ProxyParams& params, std::string why,
                    ProxyResult& result) {
  result.method = "paired";
  result.remesh_failure = std::move(why);
  result.mesh = resample(input, 0.8 * result.edge_mm, 0.8);
  result.triangles_paired = pair_triangles(result.mesh, params.field_iterations);
}

// The target edge of a remeshed proxy, mm.
double target_edge(const PolygonMesh& input, const ProxyParams& params) {
  return params.proxy_edge_mm > 0.0 ? params.proxy_edge_mm
                                    : std::sqrt(total_area(input) / std::max(1, params.auto_faces));
}

// The proxy of a surface that is not quad-dominant: field-aligned
// remeshing, or pairing when no extraction is clean.
void remesh_proxy(const PolygonMesh& input, const ProxyParams& params, ProxyResult& result) {
  result.remeshed = true;
  result.edge_mm = target_edge(input, params);
  RemeshParams remesh;
  remesh.orientation_iterations = params.field_iterations;
  remesh.position_iterations = params.position_iterations;
  // The extraction can fail at one lattice spacing and not at one a few
  // percent off (a lattice that folds into an extra handle where the
  // surface is thin: mannequin at 103 mm, Euler characteristic -1 for 1,
  // extracts cleanly at 97-103% of the spacing). Nearby spacings are tried
  // before falling back to pairing triangles; the first failure is kept
  // to report when none works.
  const double base = result.edge_mm;
  std::optional<PolygonMesh> extracted;
  RemeshStats stats;
  std::string first_failure;
  for (const double factor : {1.0, 0.99, 1.01, 0.97, 1.03}) {
    remesh.edge_mm = base * factor;
    stats = RemeshStats{};
    extracted = field_aligned_remesh(input, remesh, stats);
    ++result.remesh_attempts;
    if (extracted && is_quad_dominant(*extracted)) break;
    if (first_failure.empty())
      first_failure = extracted ? "extracted mesh is not quad-dominant" : stats.failure;
    extracted.reset();
  }
  result.samples = stats.samples;
  if (!extracted) {
    pair_resampled(input, params, first_failure, result);
    return;
  }
  result.method = "instant-meshes";
  result.edge_mm = remesh.edge_mm;
  result.holes_filled = stats.holes_filled;
  result.folds_removed = stats.folds_removed;
  result.mesh = std::move(*extracted);
}

}  // namespace

const char* proxy_method_name(ProxyMethod method) {
  switch (method) {
    case ProxyMethod::Field:
      return "field";
    case ProxyMethod::Remesh:
      return "remesh";
  }
  throw std::logic_error("proxy_method_name: unknown method");
}

std::optional<ProxyMethod> proxy_method(std::string_view name) {
  for (const auto method : {ProxyMethod::Field, ProxyMethod::Remesh}) {
    if (name == proxy_method_name(method)) return method;
  }
  return std::nullopt;
}

ProxyResult make_field_proxy(const PolygonMesh& input, const ProxyParams& params) {
  ProxyResult result;
  result.remeshed = true;
  result.method = "field";
  result.edge_mm = target_edge(input, params);
  FieldProxyParams field;
  field.edge_mm = result.edge_mm;
  field.flip_bend_deg = params.flip_bend_deg;
  field.misfit_cost = params.misfit_cost;
  field.singular_cost = params.singular_cost;
  FieldProxy proxy = field_guided_proxy(input, field);
  result.edge_mm = proxy.edge_mm;
  result.edge_candidates = proxy.candidates;
  result.mesh = std::move(proxy.mesh);
  result.vanishing_corner = std::move(proxy.vanishing_corner);
  result.valence_flips = proxy.valence_flips;
  result.field_misfit = proxy.misfit;
  return result;
}

ProxyResult make_proxy(const PolygonMesh& input, const ProxyParams& params) {
  if (params.method == ProxyMethod::Field && !is_quad_dominant(input))
    return make_field_proxy(input, params);
  ProxyResult result;
  if (is_quad_dominant(input)) {
    result.mesh = input;
    result.edge_mm = mean_edge_length(input);
  } else {
    remesh_proxy(input, params, result);
  }
  result.polygons_split = split_polygons(result.mesh);
  if (result.method == "instant-meshes") {
    // A pentagon with two corners on one point splits into a folded quad.
    result.folds_removed += collapse_folded_quads(result.mesh, RemeshParams{}.fold_ratio);
    if (!is_valid_proxy(result.mesh)) {
      pair_resampled(input, params,
                     "splitting the extracted polygons left a face of more than 4 corners "
                     "or a non-manifold edge",
                     result);
      result.polygons_split = 0;
    }
  }
  return result;
}

}  // namespace planner
