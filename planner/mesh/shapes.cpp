#include "planner/mesh/shapes.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <utility>

namespace planner {

PolygonMesh quad_ellipsoid(double radius, double z_stretch, int n) {
  PolygonMesh mesh;
  std::map<std::array<int, 3>, int> index;  // cube lattice point -> vertex
  auto vertex = [&](const std::array<int, 3>& k) {
    const auto [it, fresh] = index.try_emplace(k, static_cast<int>(mesh.positions.size()));
    if (fresh) {
      const Vec3 on_cube(2.0 * k[0] / n - 1, 2.0 * k[1] / n - 1, 2.0 * k[2] / n - 1);
      mesh.positions.push_back(on_cube.normalized().cwiseProduct(Vec3(1, 1, z_stretch)) * radius);
    }
    return it->second;
  };
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;  // (b, c, a) is right-handed
    for (int side : {0, n}) {
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
          std::vector<int> face;
          for (const auto& [di, dj] : {std::pair{0, 0}, {1, 0}, {1, 1}, {0, 1}}) {
            std::array<int, 3> k{};
            k[a] = side;
            k[b] = i + di;
            k[c] = j + dj;
            face.push_back(vertex(k));
          }
          if (side == 0) std::reverse(face.begin(), face.end());  // faces -a
          mesh.faces.push_back(face);
        }
      }
    }
  }
  return mesh;
}

}  // namespace planner
