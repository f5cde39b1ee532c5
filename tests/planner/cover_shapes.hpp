// Meshes with known physical answers for the wearability tests, made in
// code: spheres, hemispherical caps and tori, quad-dominant and oriented
// counter-clockwise seen from outside.
#pragma once

#include <cmath>
#include <numbers>
#include <vector>

#include "planner/wearability/wearability.hpp"

namespace wearknit::test {

using planner::CoverMesh;
using planner::Vec3;

// Sphere of `radius` about the origin: `rings` latitude bands (quads, with
// triangle fans at the poles) and `segments` longitudes. With
// `max_polar_angle` < π the mesh stops at that angle from the north pole
// (+z): an open cap whose boundary is the last ring.
inline CoverMesh sphere_mesh(double radius, int segments, int rings,
                             double max_polar_angle = std::numbers::pi) {
  CoverMesh mesh;
  const bool closed = max_polar_angle >= std::numbers::pi;
  const int last_ring = closed ? rings - 1 : rings;  // ring indices 1..last_ring
  mesh.positions.push_back({0, 0, radius});
  for (int i = 1; i <= last_ring; ++i) {
    const double theta = max_polar_angle * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * std::numbers::pi * j / segments;
      mesh.positions.push_back(radius * Vec3(std::sin(theta) * std::cos(phi),
                                             std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  auto ring = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) mesh.faces.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i < last_ring; ++i) {
    for (int j = 0; j < segments; ++j) {
      mesh.faces.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  if (closed) {
    const int south = static_cast<int>(mesh.positions.size());
    mesh.positions.push_back({0, 0, -radius});
    for (int j = 0; j < segments; ++j) {
      mesh.faces.push_back({ring(last_ring, j), south, ring(last_ring, j + 1)});
    }
  }
  return mesh;
}

// Box of half-sizes hx × hy × hz about the origin: 8 corners (corner i at
// x = ±hx by bit 0, y by bit 1, z by bit 2) and 6 quads.
inline CoverMesh box_mesh(double hx, double hy, double hz) {
  CoverMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.positions.push_back({i & 1 ? hx : -hx, i & 2 ? hy : -hy, i & 4 ? hz : -hz});
  mesh.faces = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return mesh;
}

// A box cover whose twelve edges are its arcs, one each.
inline CoverMesh box_cover(double hx, double hy, double hz) {
  CoverMesh mesh = box_mesh(hx, hy, hz);
  const int edges[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7}, {0, 2}, {1, 3},
                            {4, 6}, {5, 7}, {0, 4}, {1, 5}, {2, 6}, {3, 7}};
  for (const auto& e : edges) mesh.arcs.push_back(planner::arc_from_path({e[0], e[1]}));
  return mesh;
}

// Torus about the z axis: tube centre circle `major`, tube radius `minor`;
// vertex (i, j) at longitude 2πi/nu, tube angle 2πj/nv (j = 0 on the outer
// equator).
inline int torus_vertex(int nu, int nv, int i, int j) {
  return ((i % nu + nu) % nu) * nv + ((j % nv + nv) % nv);
}

inline CoverMesh torus_mesh(double major, double minor, int nu, int nv) {
  CoverMesh mesh;
  for (int i = 0; i < nu; ++i) {
    const double u = 2 * std::numbers::pi * i / nu;
    for (int j = 0; j < nv; ++j) {
      const double v = 2 * std::numbers::pi * j / nv;
      const double rho = major + minor * std::cos(v);
      mesh.positions.push_back({rho * std::cos(u), rho * std::sin(u), minor * std::sin(v)});
    }
  }
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      mesh.faces.push_back({torus_vertex(nu, nv, i, j), torus_vertex(nu, nv, i + 1, j),
                            torus_vertex(nu, nv, i + 1, j + 1), torus_vertex(nu, nv, i, j + 1)});
    }
  }
  return mesh;
}

// A torus cover cut into a disc: arc 0 is the meridian loop at i = 0 (around
// the tube); arcs 1..pieces split the outer equator loop (j = 0) into equal
// runs. Every arc open gives a disc; keeping any equator arc closed leaves a
// band of cloth closed around the tube.
inline CoverMesh torus_cover(double major, double minor, int nu, int nv, int pieces) {
  CoverMesh mesh = torus_mesh(major, minor, nu, nv);
  planner::CoverArc meridian{"meridian", {}};
  for (int j = 0; j < nv; ++j) {
    meridian.edges.push_back({torus_vertex(nu, nv, 0, j), torus_vertex(nu, nv, 0, j + 1)});
  }
  mesh.arcs.push_back(meridian);
  for (int p = 0; p < pieces; ++p) {
    planner::CoverArc equator{"equator-" + std::to_string(p), {}};
    for (int i = p * nu / pieces; i < (p + 1) * nu / pieces; ++i) {
      equator.edges.push_back({torus_vertex(nu, nv, i, 0), torus_vertex(nu, nv, i + 1, 0)});
    }
    mesh.arcs.push_back(equator);
  }
  return mesh;
}

}  // namespace wearknit::test
