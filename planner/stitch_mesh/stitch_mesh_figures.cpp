// Figures of a finished stitch mesh (stitch_mesher.hpp): sizes, the Fig. 7
// stability counts, stitches off the surface, and the disc's own area and
// boundary length.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <unordered_map>
#include <utility>
#include <vector>

#include "planner/stitch_mesh/stitch_mesher.hpp"
#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner {

using stitch_meshing::disc_surface;
using stitch_meshing::face_normal;
using stitch_meshing::key;
using stitch_meshing::kLengthTolerance;

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
