// Synthetic labelled discs for the stitch meshing tests: a grid over (s, t)
// in [0, 1]^2 mapped to 3D, with +s the course (u) and +t the wale (v)
// direction, so every quad's sides are labelled 0, 1, 2, 3 in order.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "planner/stitch_mesh/stitch_mesher.hpp"

namespace planner::stitch_discs {

inline const double kPi = std::acos(-1.0);

using Map = std::function<Eigen::Vector3d(double s, double t)>;

inline LabelledDisc grid_disc(int n, int m, const Map& map) {
  LabelledDisc disc;
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= n; ++i) {
      disc.positions.push_back(map(static_cast<double>(i) / n, static_cast<double>(j) / m));
    }
  }
  auto id = [&](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      disc.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      disc.directions.push_back({0, 1, 2, 3});
    }
  }
  return disc;
}

// A flat rectangle, course along x.
inline LabelledDisc rectangle(double width_mm, double height_mm, int n = 30, int m = 20) {
  return grid_disc(
      n, m, [=](double s, double t) { return Eigen::Vector3d(width_mm * s, height_mm * t, 0.0); });
}
inline double rectangle_area(double width_mm, double height_mm) {
  return width_mm * height_mm;
}

// A cylinder (axis z) cut open along one generator: rows go around it.
inline LabelledDisc cylinder(double radius_mm, double height_mm, int n = 48, int m = 20) {
  return grid_disc(n, m, [=](double s, double t) {
    return Eigen::Vector3d(radius_mm * std::cos(2 * kPi * s), radius_mm * std::sin(2 * kPi * s),
                           height_mm * t);
  });
}
inline double cylinder_area(double radius_mm, double height_mm) {
  return 2 * kPi * radius_mm * height_mm;
}

// A truncated cone cut open along one generator, radius r0 at the bottom
// and r1 at the top: rows shrink or grow (decreases, increases).
inline LabelledDisc cone(double r0_mm, double r1_mm, double height_mm, int n = 48, int m = 20) {
  return grid_disc(n, m, [=](double s, double t) {
    const double r = r0_mm + (r1_mm - r0_mm) * t;
    return Eigen::Vector3d(r * std::cos(2 * kPi * s), r * std::sin(2 * kPi * s), height_mm * t);
  });
}
inline double cone_area(double r0_mm, double r1_mm, double height_mm) {
  const double slant = std::hypot(height_mm, r1_mm - r0_mm);
  return kPi * (r0_mm + r1_mm) * slant;
}

// The upper hemisphere z >= 0 of radius R with two thin lunes near +-x
// left out (|beta - pi/2| <= pi/2 - beta0): course along the great half
// circles from -x to +x (the x axis projected on the sphere: no singular
// point inside), rows stacked from the y > 0 equator over the top to y < 0.
inline LabelledDisc hemisphere(double radius_mm, double beta0 = 0.25, int n = 40, int m = 40) {
  return grid_disc(n, m, [=](double s, double t) {
    const double beta = beta0 + (kPi - 2 * beta0) * s;
    const double alpha = kPi * t;
    return Eigen::Vector3d(radius_mm * std::cos(beta), radius_mm * std::sin(beta) * std::cos(alpha),
                           radius_mm * std::sin(beta) * std::sin(alpha));
  });
}
inline double hemisphere_area(double radius_mm, double beta0 = 0.25) {
  return radius_mm * radius_mm * kPi * 2 * std::cos(beta0);
}

// Largest distance from a boundary vertex of the stitch mesh to the disc's
// boundary polyline (0 when the stitch mesh keeps the disc's boundary).
inline double farthest_boundary_vertex(const LabelledDisc& disc, const StitchMesh& mesh) {
  std::set<std::pair<int, int>> directed;
  for (const auto& face : disc.faces) {
    for (std::size_t i = 0; i < face.size(); ++i)
      directed.insert({face[i], face[(i + 1) % face.size()]});
  }
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> segments;
  for (const auto& [a, b] : directed) {
    if (directed.count({b, a}) == 0) {
      segments.push_back({disc.positions[static_cast<std::size_t>(a)],
                          disc.positions[static_cast<std::size_t>(b)]});
    }
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> sides;
  for (const StitchFace& face : mesh.faces) {
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      ++sides[{face.vertices[i], face.vertices[(i + 1) % face.vertices.size()]}];
    }
  }
  double worst = 0;
  for (const auto& [e, count] : sides) {
    if (sides.count({e.second, e.first}) != 0) continue;
    const Eigen::Vector3d p = mesh.positions[e.first];
    double best = 1e300;
    for (const auto& [pa, pb] : segments) {
      const double len2 = (pb - pa).squaredNorm();
      const double s = len2 > 0 ? std::clamp((p - pa).dot(pb - pa) / len2, 0.0, 1.0) : 0.0;
      best = std::min(best, (pa + s * (pb - pa) - p).squaredNorm());
    }
    worst = std::max(worst, std::sqrt(best));
  }
  return worst;
}

}  // namespace planner::stitch_discs
