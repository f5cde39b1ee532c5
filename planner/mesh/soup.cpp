#include "planner/mesh/soup.hpp"

#include <unordered_map>

#include "planner/common/index.hpp"

namespace planner {

std::vector<int> corner_starts(const PolygonMesh& mesh) {
  std::vector<int> start(mesh.faces.size() + 1, 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    start[f + 1] = start[f] + static_cast<int>(mesh.faces[f].size());
  }
  return start;
}

UnionFind corner_fans(const PolygonMesh& mesh, const std::vector<int>& corner_start,
                      const std::vector<bool>& usable) {
  UnionFind corners(at(corner_start.back()));
  // The first corner seen at each directed pair (vertex, neighbour): a later
  // corner of the vertex along the same edge is in the same fan.
  std::unordered_map<std::uint64_t, int> first;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!usable.empty() && !usable[f]) continue;
    const auto& face = mesh.faces[f];
    const std::size_t n = face.size();
    for (std::size_t i = 0; i < n; ++i) {
      const int c = corner_start[f] + static_cast<int>(i);
      for (const int w : {face[(i + 1) % n], face[(i + n - 1) % n]}) {
        auto [it, inserted] = first.emplace(pair_key(face[i], w), c);
        if (!inserted) corners.unite(c, it->second);
      }
    }
  }
  return corners;
}

UnionFind vertex_components(const PolygonMesh& mesh, const std::vector<bool>& usable) {
  UnionFind vertices(mesh.positions.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!usable.empty() && !usable[f]) continue;
    const auto& face = mesh.faces[f];
    for (std::size_t i = 1; i < face.size(); ++i) vertices.unite(face[0], face[i]);
  }
  return vertices;
}

void drop_unused_vertices(PolygonMesh& mesh) {
  std::vector<int> index(mesh.positions.size(), -1);
  std::vector<Vec3> kept;
  for (auto& face : mesh.faces) {
    for (int& v : face) {
      if (index[at(v)] < 0) {
        index[at(v)] = static_cast<int>(kept.size());
        kept.push_back(mesh.positions[at(v)]);
      }
      v = index[at(v)];
    }
  }
  mesh.positions = std::move(kept);
}

double mean_edge_length(const PolygonMesh& mesh) {
  double total = 0.0;
  std::size_t count = 0;
  for (const auto& face : mesh.faces) {
    for (std::size_t i = 0; i < face.size(); ++i) {
      total +=
          (mesh.positions[at(face[(i + 1) % face.size()])] - mesh.positions[at(face[i])]).norm();
      ++count;
    }
  }
  return count == 0 ? 0.0 : total / static_cast<double>(count);
}

Vec3 vector_area(const PolygonMesh& mesh, const std::vector<int>& face) {
  Vec3 n = Vec3::Zero();
  for (std::size_t i = 0; i < face.size(); ++i) {
    n += mesh.positions[at(face[i])].cross(mesh.positions[at(face[(i + 1) % face.size()])]);
  }
  return 0.5 * n;
}

}  // namespace planner
