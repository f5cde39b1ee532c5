// Step 5 of the stitch mesher (stitch_mesher.hpp): the stitch vertices
// inside the sheet moved over the garment's surface (or the cut mesh, where
// the disc does not carry it) towards their sides' target lengths.
#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner::stitch_meshing {
namespace {

Vec3 polygon_normal(const StitchMesh& mesh, const StitchFace& face) {
  Vec3 normal = Vec3::Zero();
  const std::size_t n = face.vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    normal += mesh.positions[face.vertices[i]].cross(mesh.positions[face.vertices[(i + 1) % n]]);
  }
  return normal;
}

}  // namespace

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
  // On the garment's own surface, the sheet's edge moves onto it too: it
  // lies on the cut mesh's boundary, whose edges are chords of the garment
  // (a move of more than a wale would be to another part of it).
  if (!disc.surface.faces.empty()) {
    for (std::size_t v = 0; v < count; ++v) {
      if (!fixed[v]) continue;
      const Vec3 on = surface.closest_point(mesh.positions[v]);
      if ((on - mesh.positions[v]).norm() <= mesh.wale_mm) mesh.positions[v] = on;
    }
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

}  // namespace planner::stitch_meshing
