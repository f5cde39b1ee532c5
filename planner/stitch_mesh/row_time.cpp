// Step 1 of the stitch mesher (stitch_mesher.hpp): the disc's triangles with
// their wale directions, the row time fitted to them, and the rows placed on
// it by height.
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <queue>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "planner/common/index.hpp"
#include "planner/mesh/soup.hpp"
#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner::stitch_meshing {
namespace {

// Gradients of the three hat functions of a triangle.
std::array<Vec3, 3> hat_gradients(const LabelledDisc& disc, const Triangle& t) {
  std::array<Vec3, 3> g;
  for (int i = 0; i < 3; ++i) {
    const Vec3 e =
        disc.positions[at(t.v[at((i + 2) % 3)])] - disc.positions[at(t.v[at((i + 1) % 3)])];
    g[at(i)] = t.area > 0 ? Vec3(t.normal.cross(e) / (2 * t.area)) : Vec3::Zero();
  }
  return g;
}

// The least-squares fit of t to a target gradient per triangle: the
// cotangent Laplacian of the triangles (a tiny mass term fixes the
// constant), factorised once, so each fit is one solve.
class GradientFit {
 public:
  GradientFit(const LabelledDisc& disc, const std::vector<Triangle>& tris)
      : tris_(tris), n_(static_cast<int>(disc.positions.size())), grads_(tris.size()) {
    std::vector<Eigen::Triplet<double>> entries;
    double diagonal = 0;
    for (std::size_t k = 0; k < tris.size(); ++k) {
      grads_[k] = hat_gradients(disc, tris[k]);
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
          const double value = tris[k].area * grads_[k][at(i)].dot(grads_[k][at(j)]);
          entries.emplace_back(tris[k].v[at(i)], tris[k].v[at(j)], value);
          if (i == j) diagonal += value;
        }
      }
    }
    const double epsilon = 1e-9 * diagonal / std::max(1, n_);
    for (int i = 0; i < n_; ++i) entries.emplace_back(i, i, epsilon);
    Eigen::SparseMatrix<double> matrix(n_, n_);
    matrix.setFromTriplets(entries.begin(), entries.end());
    solver_.compute(matrix);
    if (solver_.info() != Eigen::Success) {
      throw std::runtime_error("row time: the Laplacian could not be factorised");
    }
  }

  // The hat gradients of triangle k.
  const std::array<Vec3, 3>& grads(std::size_t k) const { return grads_[k]; }

  // t whose gradient is closest to `target` (per triangle) in least squares.
  Eigen::VectorXd solve(const std::vector<Vec3>& target) const {
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_);
    for (std::size_t k = 0; k < tris_.size(); ++k) {
      for (int i = 0; i < 3; ++i) {
        rhs[tris_[k].v[at(i)]] += tris_[k].area * grads_[k][at(i)].dot(target[k]);
      }
    }
    return solver_.solve(rhs);
  }

  // The gradient of t on triangle k.
  Vec3 gradient(std::size_t k, const Eigen::VectorXd& t) const {
    Vec3 g = Vec3::Zero();
    for (int i = 0; i < 3; ++i) g += t[tris_[k].v[at(i)]] * grads_[k][at(i)];
    return g;
  }

 private:
  const std::vector<Triangle>& tris_;
  int n_;
  std::vector<std::array<Vec3, 3>> grads_;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
};

// The wale direction of a triangular face is its labels' at best within
// about 30 degrees: its sides lie at 60 degrees to each other, and the
// labels say only which of them are course and which wale. Quads of a
// field-aligned proxy follow the field with all four sides; a proxy of
// triangles (the field-guided proxy, docs/cutting.md) does not. Inside the
// disc the labels agree across every edge, so the wale directions form one
// vector field there, and the triangles of triangular faces take the
// area-weighted mean of their own and their edge neighbours' directions,
// a few sweeps, which averages that quantisation out; quads keep theirs.
void smooth_triangle_labels(const LabelledDisc& disc, std::vector<Triangle>& tris) {
  constexpr int kSweeps = 10;
  std::unordered_map<std::uint64_t, std::vector<int>> by_edge;
  for (std::size_t k = 0; k < tris.size(); ++k) {
    for (int i = 0; i < 3; ++i) {
      const int a = tris[k].v[at(i)];
      const int b = tris[k].v[at((i + 1) % 3)];
      by_edge[pair_key(std::min(a, b), std::max(a, b))].push_back(static_cast<int>(k));
    }
  }
  std::vector<std::vector<int>> neighbours(tris.size());
  for (const auto& [key, list] : by_edge) {
    if (list.size() != 2) continue;
    neighbours[at(list[0])].push_back(list[1]);
    neighbours[at(list[1])].push_back(list[0]);
  }
  std::vector<bool> smooth(tris.size(), false);
  bool any = false;
  for (std::size_t k = 0; k < tris.size(); ++k) {
    smooth[k] = disc.faces[at(tris[k].face)].size() == 3;
    any = any || smooth[k];
  }
  if (!any) return;
  for (int sweep = 0; sweep < kSweeps; ++sweep) {
    std::vector<Vec3> next(tris.size());
    for (std::size_t k = 0; k < tris.size(); ++k) {
      next[k] = tris[k].wale;
      if (!smooth[k]) continue;
      Vec3 sum = tris[k].area * tris[k].wale;
      for (const int j : neighbours[k]) sum += tris[at(j)].area * tris[at(j)].wale;
      const Vec3& n = tris[k].normal;
      const Vec3 tangent = sum - sum.dot(n) * n;
      if (tangent.norm() > 1e-12) next[k] = tangent.normalized();
    }
    for (std::size_t k = 0; k < tris.size(); ++k) tris[k].wale = next[k];
  }
}

}  // namespace

std::vector<Triangle> triangulate(const LabelledDisc& disc) {
  std::vector<Triangle> tris;
  for (std::size_t f = 0; f < disc.faces.size(); ++f) {
    const std::vector<int>& face = disc.faces[f];
    const std::vector<int>& dir = disc.directions[f];
    Vec3 course = Vec3::Zero();
    Vec3 wale = Vec3::Zero();
    for (std::size_t i = 0; i < face.size(); ++i) {
      const Vec3 e = disc.positions[at(face[(i + 1) % face.size()])] - disc.positions[at(face[i])];
      const double len = e.norm();
      if (len <= 0) continue;
      const Vec3 u = e / len;
      switch (dir[i] & 3) {
        case 0:
          course += u;
          break;
        case 1:
          wale += u;
          break;
        case 2:
          course -= u;
          break;
        default:
          wale -= u;
          break;
      }
    }
    // Quads are split along the shorter diagonal, other polygons as a fan.
    std::size_t start = 0;
    if (face.size() == 4) {
      const double d02 = (disc.positions[at(face[0])] - disc.positions[at(face[2])]).norm();
      const double d13 = (disc.positions[at(face[1])] - disc.positions[at(face[3])]).norm();
      if (d13 < d02) start = 1;
    }
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      Triangle t;
      t.v = {face[start], face[(start + i) % face.size()], face[(start + i + 1) % face.size()]};
      t.face = static_cast<int>(f);
      const Vec3 p0 = disc.positions[at(t.v[0])];
      const Vec3 n = (disc.positions[at(t.v[1])] - p0).cross(disc.positions[at(t.v[2])] - p0);
      t.area = 0.5 * n.norm();
      t.normal = t.area > 0 ? Vec3(n.normalized()) : Vec3(face_normal(disc, face).normalized());
      // +v is +u turned a quarter turn counter-clockwise about the normal.
      // Rows run along the course sides, so those set the wale direction;
      // +v sides are only a fallback (a face labelled by its wale sides alone).
      const Vec3 w = wale - wale.dot(t.normal) * t.normal;
      const Vec3 c = course - course.dot(t.normal) * t.normal;
      if (c.norm() > 1e-12) {
        t.wale = t.normal.cross(c.normalized());
      } else if (w.norm() > 1e-12) {
        t.wale = w.normalized();
      }
      tris.push_back(t);
    }
  }
  smooth_triangle_labels(disc, tris);
  return tris;
}

Eigen::VectorXd row_time(const LabelledDisc& disc, std::vector<Triangle>& tris,
                         const StitchMeshParams& params, StitchMeshStats& stats) {
  const GradientFit fit(disc, tris);
  std::vector<Vec3> target(tris.size());
  for (std::size_t k = 0; k < tris.size(); ++k) target[k] = tris[k].wale / params.wale_mm;
  Eigen::VectorXd t = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(disc.positions.size()));
  for (int iteration = 0; iteration <= params.straighten_iterations; ++iteration) {
    const Eigen::VectorXd before = t;
    t = fit.solve(target);
    stats.straighten_fits = iteration;
    // t is in rows. The fixed point of the straightening (rows of unit
    // height blended with the labels) is reached when no vertex moves by
    // more than the tolerance; a shift of the whole of t does not count.
    const Eigen::ArrayXd moved = (t - before).array();
    const bool settled =
        iteration > 0 && (moved - moved.mean()).abs().maxCoeff() < params.straighten_tolerance_rows;
    for (std::size_t k = 0; k < tris.size(); ++k) {
      const Vec3 g = fit.gradient(k, t);
      tris[k].grad = g;
      // Keep the labelled direction and the fitted one in equal parts, at
      // unit speed: rows follow the labels and keep their height.
      Vec3 d = params.label_weight * tris[k].wale;
      if (g.norm() > 1e-12) d += g.normalized();
      if (d.norm() > 1e-12) target[k] = d.normalized() / params.wale_mm;
    }
    if (settled) break;
  }
  // How far the rows' wale direction strays from the labels, by area.
  double angle_area = 0;
  double area = 0;
  for (const Triangle& tri : tris) {
    if (tri.grad.norm() <= 1e-12 || tri.wale.norm() <= 1e-12) continue;
    angle_area += tri.area * std::acos(std::clamp(tri.grad.normalized().dot(tri.wale), -1.0, 1.0));
    area += tri.area;
  }
  stats.label_deviation_deg = area > 0 ? angle_area / area * 180.0 / std::numbers::pi : 0.0;
  t.array() -= t.minCoeff();
  return t;
}

int drain_interior_extrema(const LabelledDisc& disc, std::vector<Triangle>& tris,
                           Eigen::VectorXd& t, const StitchMeshParams& params, int rounds) {
  const int n = static_cast<int>(disc.positions.size());
  const GradientFit fit(disc, tris);
  // The targets of the settled fit: unit speed, blended with the labels.
  std::vector<Vec3> target(tris.size());
  for (std::size_t k = 0; k < tris.size(); ++k) {
    Vec3 d = params.label_weight * tris[k].wale;
    if (tris[k].grad.norm() > 1e-12) d += tris[k].grad.normalized();
    target[k] = d.norm() > 1e-12 ? Vec3(d.normalized() / params.wale_mm) : Vec3::Zero();
  }
  const std::vector<std::vector<int>> adjacent = vertex_neighbours(tris, at(n));
  std::vector<std::vector<int>> tris_of(at(n));
  for (std::size_t k = 0; k < tris.size(); ++k) {
    for (int v : tris[k].v) tris_of[at(v)].push_back(static_cast<int>(k));
  }
  int drained = 0;
  for (int round = 0; round < rounds; ++round) {
    Eigen::VectorXd levelled = t;
    if (level_interior_extrema(disc, tris, levelled) == 0) return drained;
    std::vector<int> region(at(n), -1);  // per vertex: its extremum's region
    int regions = 0;
    for (int v = 0; v < n; ++v) {
      if (levelled[v] == t[v] || region[at(v)] >= 0) continue;
      // One pit (raised) or peak (cut), its vertices joined by edges.
      const double sign = levelled[v] > t[v] ? 1.0 : -1.0;
      std::vector<int> members{v};
      region[at(v)] = regions;
      for (std::size_t i = 0; i < members.size(); ++i) {
        for (int w : adjacent[at(members[i])]) {
          if (region[at(w)] < 0 && levelled[w] != t[w] && (levelled[w] > t[w]) == (sign > 0)) {
            region[at(w)] = regions;
            members.push_back(w);
          }
        }
      }
      ++regions;
      drained += static_cast<int>(members.size());
      // Where it spills: the neighbour outside lowest (pit) or highest (peak).
      int spill = -1;
      for (int m : members) {
        for (int w : adjacent[at(m)]) {
          if (region[at(w)] >= 0) continue;
          if (spill < 0 || sign * (t[w] - t[spill]) < 0) spill = w;
        }
      }
      if (spill < 0) continue;
      // Distances from the spill point over the region and its rim.
      std::unordered_map<int, double> dist;
      using Entry = std::pair<double, int>;
      std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
      dist[spill] = 0;
      queue.push({0.0, spill});
      auto inside = [&](int w) {
        if (region[at(w)] == regions - 1) return true;
        for (int x : adjacent[at(w)]) {
          if (region[at(x)] == regions - 1) return true;
        }
        return false;
      };
      while (!queue.empty()) {
        const auto [d, u] = queue.top();
        queue.pop();
        if (d > dist[u]) continue;
        for (int w : adjacent[at(u)]) {
          if (!inside(w)) continue;
          const double next = d + (disc.positions[at(w)] - disc.positions[at(u)]).norm();
          const auto it = dist.find(w);
          if (it == dist.end() || next < it->second) {
            dist[w] = next;
            queue.push({next, w});
          }
        }
      }
      // The region's triangles rise away from the spill point (a pit) or
      // fall away from it (a peak): it drains through its spill point.
      for (int m : members) {
        for (int k : tris_of[at(m)]) {
          Vec3 g = Vec3::Zero();
          bool all = true;
          for (int i = 0; i < 3; ++i) {
            const auto it = dist.find(tris[at(k)].v[at(i)]);
            if (it == dist.end()) {
              all = false;
              break;
            }
            g += it->second * fit.grads(at(k))[at(i)];
          }
          if (all && g.norm() > 1e-12) target[at(k)] = sign * g.normalized() / params.wale_mm;
        }
      }
    }
    t = fit.solve(target);
    t.array() -= t.minCoeff();
    for (std::size_t k = 0; k < tris.size(); ++k) tris[k].grad = fit.gradient(k, t);
  }
  return drained;
}

Eigen::VectorXd row_levels(const LabelledDisc& disc, const std::vector<Triangle>& tris,
                           const Eigen::VectorXd& t, const StitchMeshParams& params, int& bands) {
  const double t_max = t.maxCoeff();
  const int slabs = std::max(16, 8 * static_cast<int>(std::ceil(t_max)));
  const double width = t_max > 0 ? t_max / slabs : 1.0;
  std::vector<double> area(at(slabs), 0.0);
  std::vector<double> length(at(slabs + 1), 0.0);  // level curve at slab boundary k
  for (const Triangle& tri : tris) {
    std::array<double, 3> v{};
    std::array<Vec3, 3> p;
    for (int i = 0; i < 3; ++i) {
      v[at(i)] = t[tri.v[at(i)]];
      p[at(i)] = disc.positions[at(tri.v[at(i)])];
    }
    const double lo = std::min({v[0], v[1], v[2]});
    const double hi = std::max({v[0], v[1], v[2]});
    // Area spread evenly over the triangle's range of t.
    const int first = std::clamp(static_cast<int>(std::floor(lo / width)), 0, slabs - 1);
    const int last = std::clamp(static_cast<int>(std::floor(hi / width)), 0, slabs - 1);
    for (int k = first; k <= last; ++k) {
      const double a = std::max(lo, k * width);
      const double b = std::min(hi, (k + 1) * width);
      area[at(k)] += hi > lo ? tri.area * std::max(0.0, b - a) / (hi - lo) : tri.area;
    }
    for (int k = first + 1; k <= last; ++k) {
      const double level = k * width;
      std::vector<Vec3> cross;
      for (int i = 0; i < 3; ++i) {
        const double va = v[at(i)];
        const double vb = v[at((i + 1) % 3)];
        if ((va < level) != (vb < level)) {
          const double s = (level - va) / (vb - va);
          cross.push_back((1 - s) * p[at(i)] + s * p[at((i + 1) % 3)]);
        }
      }
      if (cross.size() == 2) length[at(k)] += (cross[1] - cross[0]).norm();
    }
  }
  // Heights in mm per slab, each at most four times what unit speed gives
  // (near the extremes of t the level curves shrink to points).
  std::vector<double> below(at(slabs + 1), 0.0);
  for (int k = 0; k < slabs; ++k) {
    const double nominal = width * params.wale_mm;
    const double curve = std::max(length[at(k)], length[at(k + 1)]);
    double height = curve > 0 ? area[at(k)] / curve : nominal;
    height = std::clamp(height, 0.25 * nominal, 4.0 * nominal);
    below[at(k + 1)] = below[at(k)] + height;
  }
  const double total = below.back();
  bands = std::max(1, static_cast<int>(std::lround(total / params.wale_mm)));
  const double per_row = total > 0 ? total / bands : 1.0;
  Eigen::VectorXd out(t.size());
  for (int i = 0; i < t.size(); ++i) {
    const double x = std::clamp(t[i] / width, 0.0, static_cast<double>(slabs));
    const int k = std::min(slabs - 1, static_cast<int>(std::floor(x)));
    const double f = x - k;
    out[i] = ((1 - f) * below[at(k)] + f * below[at(k + 1)]) / per_row;
  }
  return out;
}

}  // namespace planner::stitch_meshing
