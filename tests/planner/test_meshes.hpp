// Small synthetic meshes for the planner tests.
#pragma once

#include <cmath>

#include "planner/mesh/mesh.hpp"

namespace planner::test_meshes {

// n x m quads in the plane z = 0, counter-clockwise seen from +z.
inline PolygonMesh grid(int n, int m) {
  PolygonMesh mesh;
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= n; ++i) mesh.positions.emplace_back(i, j, 0.0);
  }
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i)
      mesh.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  }
  return mesh;
}

// An n x m quad torus (genus 1, every vertex regular), outward normals.
inline PolygonMesh torus(int n, int m, double big = 3.0, double small = 1.0) {
  PolygonMesh mesh;
  const double pi = std::acos(-1.0);
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      const double a = 2 * pi * i / n;
      const double b = 2 * pi * j / m;
      mesh.positions.emplace_back((big + small * std::cos(b)) * std::cos(a),
                                  (big + small * std::cos(b)) * std::sin(a), small * std::sin(b));
    }
  }
  auto id = [&](int i, int j) { return ((j + m) % m) * n + (i + n) % n; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i)
      mesh.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  }
  return mesh;
}

// A closed surface of revolution about the z axis: `rings` circles of `n`
// vertices at z = length * (i + 1) / (rings + 1) with radius radius(z),
// closed by a pole vertex at each end; quads, and triangles at the poles,
// facing outwards.
template <class Radius>
PolygonMesh revolution(double length, int rings, int n, Radius radius) {
  PolygonMesh mesh;
  const double pi = std::acos(-1.0);
  mesh.positions.emplace_back(0, 0, 0);
  for (int j = 0; j < rings; ++j) {
    const double z = length * (j + 1) / (rings + 1);
    const double r = radius(z);
    for (int i = 0; i < n; ++i) {
      const double a = 2 * pi * i / n;
      mesh.positions.emplace_back(r * std::cos(a), r * std::sin(a), z);
    }
  }
  mesh.positions.emplace_back(0, 0, length);
  const int top = static_cast<int>(mesh.positions.size()) - 1;
  auto id = [&](int i, int j) { return 1 + j * n + (i + n) % n; };
  for (int i = 0; i < n; ++i) mesh.faces.push_back({0, id(i + 1, 0), id(i, 0)});
  for (int j = 0; j + 1 < rings; ++j) {
    for (int i = 0; i < n; ++i)
      mesh.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  }
  for (int i = 0; i < n; ++i) mesh.faces.push_back({id(i, rings - 1), id(i + 1, rings - 1), top});
  return mesh;
}

// The surface of the cube [0,k]^3 split into k x k quads per side (genus 0;
// its 8 corners have 3 quads each: irregular).
inline PolygonMesh cube(int k) {
  PolygonMesh mesh;
  auto vertex = [&](const Vec3& p) {
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      if ((mesh.positions[i] - p).norm() < 1e-9) return static_cast<int>(i);
    }
    mesh.positions.push_back(p);
    return static_cast<int>(mesh.positions.size()) - 1;
  };
  // Each side: origin o, axes a and b with a x b pointing outwards.
  const Vec3 X = Vec3::UnitX(), Y = Vec3::UnitY(), Z = Vec3::UnitZ();
  const struct {
    Vec3 o, a, b;
  } sides[6] = {{Vec3(0, 0, 0), Y, X}, {Vec3(0, 0, k), X, Y}, {Vec3(0, 0, 0), X, Z},
                {Vec3(0, k, 0), Z, X}, {Vec3(0, 0, 0), Z, Y}, {Vec3(k, 0, 0), Y, Z}};
  for (const auto& s : sides) {
    for (int j = 0; j < k; ++j) {
      for (int i = 0; i < k; ++i) {
        mesh.faces.push_back(
            {vertex(s.o + s.a * i + s.b * j), vertex(s.o + s.a * (i + 1) + s.b * j),
             vertex(s.o + s.a * (i + 1) + s.b * (j + 1)), vertex(s.o + s.a * i + s.b * (j + 1))});
      }
    }
  }
  return mesh;
}

}  // namespace planner::test_meshes
