#include <array>
#include <cmath>
#include <utility>

#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner::stitch_meshing {

Vec3 face_normal(const LabelledDisc& disc, const std::vector<int>& face) {
  Vec3 n = Vec3::Zero();
  for (std::size_t i = 0; i < face.size(); ++i) {
    n += disc.positions[at(face[i])].cross(disc.positions[at(face[(i + 1) % face.size()])]);
  }
  return n;
}

cloth::TriangleMeshQuery disc_surface(const LabelledDisc& disc) {
  const PolygonMesh& mesh = disc.surface.faces.empty() ? disc : disc.surface;
  std::vector<std::array<int, 3>> triangles;
  for (const std::vector<int>& face : mesh.faces) {
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      triangles.push_back({face[0], face[i], face[i + 1]});
    }
  }
  return cloth::TriangleMeshQuery(mesh.positions, std::move(triangles));
}

std::optional<double> sphere_exit(const Vec3& a, const Vec3& e, const Vec3& centre, double radius) {
  const Vec3 g = a - centre;
  const double ee = e.dot(e);
  const double ge = g.dot(e);
  const double root = ge * ge - ee * (g.dot(g) - radius * radius);
  if (!(ee > 0) || root < 0) return std::nullopt;
  return (-ge + std::sqrt(root)) / ee;
}

double length_cost(double off, double outside) {
  return off * off + (std::abs(off) > kLengthTolerance ? outside : 0.0);
}

}  // namespace planner::stitch_meshing
