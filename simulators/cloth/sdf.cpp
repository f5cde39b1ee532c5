#include "simulators/cloth/sdf.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "simulators/cloth/parallel.hpp"

namespace cloth {

namespace {

// Closest point on triangle (a, b, c) to p, by Voronoi regions of the
// vertices, edges and face (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const double denom = va + vb + vc;
  if (denom <= 0) {  // degenerate triangle: nearest of its vertices
    const double da = (p - a).squaredNorm(), db = (p - b).squaredNorm(), dc = (p - c).squaredNorm();
    return da <= db && da <= dc ? a : (db <= dc ? b : c);
  }
  return a + ab * (vb / denom) + ac * (vc / denom);
}

// Signed solid angle of triangle (a, b, c) seen from the origin
// (Van Oosterom & Strackee 1983); positive when the triangle's
// counter-clockwise normal points away from the origin.
double solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2.0 * std::atan2(numerator, denominator);
}

// Far-field acceptance: a cluster is replaced by its dipole when the query is
// farther than this many cluster radii from its centre (Barill et al. 2018
// use 2; the error is then well below 1e-2 of a full turn).
constexpr double kWindingBeta = 2.0;
constexpr int kLeafSize = 4;

}  // namespace

struct TriangleMeshQuery::Node {
  Eigen::AlignedBox3d box;
  Vec3 area_normal = Vec3::Zero();  // sum of (area * unit normal)
  Vec3 centre = Vec3::Zero();       // area-weighted centroid
  double radius = 0;                // of the ball around centre holding the cluster
  int left = -1, right = -1;        // children; -1 for a leaf
  int begin = 0, end = 0;           // leaf range in order_
};

TriangleMeshQuery::TriangleMeshQuery(std::vector<Vec3> vertices,
                                     std::vector<std::array<int, 3>> triangles)
    : vertices_(std::move(vertices)), triangles_(std::move(triangles)) {
  if (triangles_.empty()) throw std::invalid_argument("wearer mesh has no faces");
  for (const auto& t : triangles_) {
    for (int v : t) {
      if (v < 0 || static_cast<std::size_t>(v) >= vertices_.size()) {
        throw std::invalid_argument("wearer face refers to vertex " + std::to_string(v) + " of " +
                                    std::to_string(vertices_.size()));
      }
    }
  }
  order_.resize(triangles_.size());
  for (std::size_t i = 0; i < order_.size(); ++i) order_[i] = static_cast<int>(i);
  nodes_.reserve(2 * triangles_.size() / kLeafSize + 2);
  build(0, static_cast<int>(order_.size()));
}

TriangleMeshQuery::~TriangleMeshQuery() = default;
TriangleMeshQuery::TriangleMeshQuery(TriangleMeshQuery&&) noexcept = default;
TriangleMeshQuery& TriangleMeshQuery::operator=(TriangleMeshQuery&&) noexcept = default;

int TriangleMeshQuery::build(int begin, int end) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Node node;
  node.begin = begin;
  node.end = end;
  double area_sum = 0;
  Vec3 weighted = Vec3::Zero();
  Eigen::AlignedBox3d centroids;
  for (int i = begin; i < end; ++i) {
    const auto& t = triangles_[order_[i]];
    const Vec3 &a = vertices_[t[0]], &b = vertices_[t[1]], &c = vertices_[t[2]];
    node.box.extend(a);
    node.box.extend(b);
    node.box.extend(c);
    const Vec3 n = 0.5 * (b - a).cross(c - a);
    node.area_normal += n;
    const double area = n.norm();
    const Vec3 centroid = (a + b + c) / 3.0;
    weighted += area * centroid;
    area_sum += area;
    centroids.extend(centroid);
  }
  node.centre = area_sum > 0 ? Vec3(weighted / area_sum) : node.box.center();
  for (int corner = 0; corner < 8; ++corner) {
    const auto which = static_cast<Eigen::AlignedBox3d::CornerType>(corner);
    node.radius = std::max(node.radius, (node.box.corner(which) - node.centre).norm());
  }
  if (end - begin > kLeafSize) {
    int axis = 0;
    centroids.sizes().maxCoeff(&axis);
    const int middle = begin + (end - begin) / 2;
    auto key = [&](int t) {
      const auto& tri = triangles_[t];
      return vertices_[tri[0]][axis] + vertices_[tri[1]][axis] + vertices_[tri[2]][axis];
    };
    // Ties broken by index so the tree (and every query) is reproducible.
    std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                     [&](int x, int y) {
                       const double kx = key(x), ky = key(y);
                       return kx < ky || (kx == ky && x < y);
                     });
    node.left = build(begin, middle);
    node.right = build(middle, end);
  }
  nodes_[index] = node;
  return index;
}

double TriangleMeshQuery::distance(const Vec3& p) const {
  return (closest_point(p) - p).norm();
}

Vec3 TriangleMeshQuery::closest_point(const Vec3& p) const {
  double best = std::numeric_limits<double>::infinity();
  Vec3 nearest = p;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (node.box.squaredExteriorDistance(p) >= best) continue;
    if (node.left < 0) {
      for (int i = node.begin; i < node.end; ++i) {
        const auto& t = triangles_[order_[i]];
        const Vec3 q = closest_on_triangle(p, vertices_[t[0]], vertices_[t[1]], vertices_[t[2]]);
        const double d = (q - p).squaredNorm();
        if (d < best) {
          best = d;
          nearest = q;
        }
      }
      continue;
    }
    // Visit the nearer child first (pushed last) so pruning bites early.
    const double dl = nodes_[node.left].box.squaredExteriorDistance(p);
    const double dr = nodes_[node.right].box.squaredExteriorDistance(p);
    if (dl < dr) {
      stack[top++] = node.right;
      stack[top++] = node.left;
    } else {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
  return nearest;
}

namespace {

// Where the ray origin + t * direction enters the box: t of entry, or
// infinity when it misses it (slab test; zero components give +-inf).
double ray_box_entry(const Eigen::AlignedBox3d& box, const Vec3& origin, const Vec3& inverse) {
  double near = -std::numeric_limits<double>::infinity();
  double far = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    double t0 = (box.min()[k] - origin[k]) * inverse[k];
    double t1 = (box.max()[k] - origin[k]) * inverse[k];
    if (std::isnan(t0) || std::isnan(t1)) {  // parallel to the slab and on its plane
      if (origin[k] < box.min()[k] || origin[k] > box.max()[k])
        return std::numeric_limits<double>::infinity();
      continue;
    }
    if (t0 > t1) std::swap(t0, t1);
    near = std::max(near, t0);
    far = std::min(far, t1);
  }
  if (near > far || far < 0) return std::numeric_limits<double>::infinity();
  return std::max(near, 0.0);
}

// Möller–Trumbore: t along the ray where it crosses triangle abc, or
// infinity. The barycentric bounds have a little slack, so a ray through
// an edge or a vertex shared by several triangles hits at least one.
double ray_triangle(const Vec3& origin, const Vec3& direction, const Vec3& a, const Vec3& b,
                    const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a;
  const Vec3 p = direction.cross(e2);
  const double det = e1.dot(p);
  const double scale = e1.norm() * e2.norm();
  if (std::abs(det) <= 1e-14 * scale) return std::numeric_limits<double>::infinity();
  const Vec3 s = origin - a;
  const double u = s.dot(p) / det;
  constexpr double slack = 1e-9;
  if (u < -slack || u > 1 + slack) return std::numeric_limits<double>::infinity();
  const Vec3 q = s.cross(e1);
  const double v = direction.dot(q) / det;
  if (v < -slack || u + v > 1 + slack) return std::numeric_limits<double>::infinity();
  return e2.dot(q) / det;
}

}  // namespace

double TriangleMeshQuery::ray_hit(const Vec3& origin, const Vec3& direction, double min_t,
                                  int facing) const {
  const Vec3 inverse = direction.cwiseInverse();
  double best = std::numeric_limits<double>::infinity();
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (ray_box_entry(node.box, origin, inverse) >= best) continue;
    if (node.left < 0) {
      for (int i = node.begin; i < node.end; ++i) {
        const auto& t = triangles_[order_[i]];
        const Vec3 &a = vertices_[t[0]], &b = vertices_[t[1]], &c = vertices_[t[2]];
        if (facing != 0 && facing * direction.dot((b - a).cross(c - a)) <= 0) continue;
        const double hit = ray_triangle(origin, direction, a, b, c);
        if (hit > min_t && hit < best) best = hit;
      }
      continue;
    }
    stack[top++] = node.left;
    stack[top++] = node.right;
  }
  return best;
}

double TriangleMeshQuery::winding_number(const Vec3& p) const {
  double total = 0;
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    const Vec3 d = node.centre - p;
    const double r = d.norm();
    if (r > kWindingBeta * node.radius) {
      total += d.dot(node.area_normal) / (r * r * r);
      continue;
    }
    if (node.left < 0) {
      for (int i = node.begin; i < node.end; ++i) {
        const auto& t = triangles_[order_[i]];
        total += solid_angle(vertices_[t[0]] - p, vertices_[t[1]] - p, vertices_[t[2]] - p);
      }
      continue;
    }
    stack[top++] = node.left;
    stack[top++] = node.right;
  }
  return total / (4.0 * std::numbers::pi);
}

double TriangleMeshQuery::signed_distance(const Vec3& p) const {
  const double d = distance(p);
  return winding_number(p) > 0.5 ? -d : d;
}

SignedDistanceField::SignedDistanceField(const std::vector<Vec3>& vertices,
                                         const std::vector<std::vector<int>>& faces,
                                         const SdfParams& params) {
  std::vector<std::array<int, 3>> triangles;
  for (const auto& face : faces) {
    if (face.size() < 3) throw std::invalid_argument("wearer face with fewer than 3 vertices");
    for (std::size_t i = 1; i + 1 < face.size(); ++i)
      triangles.push_back({face[0], face[i], face[i + 1]});
  }
  mesh_ = std::make_shared<const TriangleMeshQuery>(vertices, std::move(triangles));

  Eigen::AlignedBox3d box;
  for (const auto& t : mesh_->triangles()) {
    for (int v : t) box.extend(mesh_->vertices()[v]);
  }
  scale_ = std::max(box.diagonal().norm(), 1e-12);
  const double margin = params.margin_fraction * scale_;
  const Vec3 low = box.min() - Vec3::Constant(margin);
  const Vec3 size = box.sizes() + Vec3::Constant(2 * margin);
  const int resolution = std::max(params.resolution, 4);
  cell_ = size.maxCoeff() / resolution;
  origin_ = low;
  nx_ = static_cast<int>(std::ceil(size.x() / cell_)) + 1;
  ny_ = static_cast<int>(std::ceil(size.y() / cell_)) + 1;
  nz_ = static_cast<int>(std::ceil(size.z() / cell_)) + 1;
  high_ = origin_ + cell_ * Vec3(nx_ - 1, ny_ - 1, nz_ - 1);
  values_.assign(static_cast<std::size_t>(nx_) * ny_ * nz_, 0.0f);
  const TriangleMeshQuery& mesh = *mesh_;
  parallel_for(nz_, params.threads, [&](int k) {
    for (int j = 0; j < ny_; ++j) {
      for (int i = 0; i < nx_; ++i) {
        const Vec3 p = origin_ + cell_ * Vec3(i, j, k);
        values_[(static_cast<std::size_t>(k) * ny_ + j) * nx_ + i] =
            static_cast<float>(mesh.signed_distance(p));
      }
    }
  });
}

Vec3 SignedDistanceField::box_max() const {
  return high_;
}

double SignedDistanceField::beyond_grid(const Vec3& p, Vec3* want) const {
  const Vec3& high = high_;
  const Vec3 clamped = p.cwiseMax(origin_).cwiseMin(high);
  const Vec3 outside = p - clamped;
  // A point on the box's faces, or beyond them by less than the square
  // root of the least double, is inside.
  if (outside.squaredNorm() == 0) return interpolate(p, want);
  const double gap = outside.norm();
  if (gap == 0) return interpolate(p, want);
  // Beyond the grid: the box is far from the surface (margin), so the field
  // grows like the distance to the box; the gradient points away from it.
  const double at_box = interpolate(clamped, nullptr);
  if (want != nullptr) *want = outside / gap;
  return at_box + gap;
}

}  // namespace cloth
