#include "planner/mesh/mesh.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "planner/common/index.hpp"
#include "planner/mesh/soup.hpp"

namespace planner {

double angle_between(const Vec3& a, const Vec3& b) {
  const double na = a.norm();
  const double nb = b.norm();
  if (na <= 0.0 || nb <= 0.0) return 0.0;
  return std::acos(std::clamp(a.dot(b) / (na * nb), -1.0, 1.0));
}

HalfedgeMesh::HalfedgeMesh(PolygonMesh mesh) : mesh_(std::move(mesh)) {
  const std::size_t nf = mesh_.faces.size();
  face_start_.assign(nf + 1, 0);
  for (std::size_t f = 0; f < nf; ++f) {
    face_start_[f + 1] = face_start_[f] + static_cast<int>(mesh_.faces[f].size());
  }
  const std::size_t nh = at(face_start_[nf]);
  face_.resize(nh);
  from_.resize(nh);
  twin_.assign(nh, -1);
  edge_.assign(nh, -1);
  std::unordered_map<std::uint64_t, int> directed;
  directed.reserve(nh * 2);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto& face = mesh_.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int h = face_start_[f] + static_cast<int>(i);
      face_[at(h)] = static_cast<int>(f);
      from_[at(h)] = face[i];
      const int to_vertex = face[(i + 1) % face.size()];
      if (!directed.emplace(pair_key(face[i], to_vertex), h).second) {
        throw std::logic_error("HalfedgeMesh: half-edge " + std::to_string(face[i]) + "->" +
                               std::to_string(to_vertex) + " used twice (unchecked mesh)");
      }
    }
  }
  for (std::size_t h = 0; h < nh; ++h) {
    const int a = from_[h];
    const int b = to(static_cast<int>(h));
    auto it = directed.find(pair_key(b, a));
    if (it != directed.end()) twin_[h] = it->second;
  }
  for (std::size_t h = 0; h < nh; ++h) {
    if (edge_[h] >= 0) continue;
    edge_[h] = num_edges_;
    if (twin_[h] >= 0) edge_[at(twin_[h])] = num_edges_;
    edge_halfedge_.push_back(static_cast<int>(h));
    ++num_edges_;
  }
  vertex_out_.assign(mesh_.positions.size(), -1);
  boundary_vertex_.assign(mesh_.positions.size(), false);
  for (std::size_t h = 0; h < nh; ++h) {
    const auto v = at(from_[h]);
    // A boundary vertex keeps its outgoing half-edge with no face clockwise
    // of it (twin(h) < 0): the counter-clockwise fan walk starts there.
    if (twin_[h] < 0) {
      boundary_vertex_[v] = true;
      vertex_out_[v] = static_cast<int>(h);
    } else if (vertex_out_[v] < 0) {
      vertex_out_[v] = static_cast<int>(h);
    }
  }
  // Vertices that are the end of a boundary half-edge are boundary too.
  for (std::size_t h = 0; h < nh; ++h) {
    if (twin_[h] < 0) boundary_vertex_[at(to(static_cast<int>(h)))] = true;
  }
}

int HalfedgeMesh::next(int h) const {
  const int f = face(h);
  const int start = face_start(f);
  const int n = degree(f);
  return start + (h - start + 1) % n;
}

int HalfedgeMesh::prev(int h) const {
  const int f = face(h);
  const int start = face_start(f);
  const int n = degree(f);
  return start + (h - start + n - 1) % n;
}

std::vector<int> HalfedgeMesh::outgoing(int v) const {
  std::vector<int> result;
  const int start = vertex_out_[at(v)];
  if (start < 0) return result;
  // Counter-clockwise rotation: the next outgoing half-edge is twin(prev(h)).
  int h = start;
  do {
    result.push_back(h);
    const int t = twin(prev(h));
    if (t < 0) break;  // reached the boundary on the other side
    h = t;
  } while (h != start);
  return result;
}

double HalfedgeMesh::corner_angle(int h) const {
  const Vec3& p = position(from(h));
  return angle_between(position(to(h)) - p, position(from(prev(h))) - p);
}

Vec3 HalfedgeMesh::face_normal(int f) const {
  return vector_area(mesh_, mesh_.faces[at(f)]);
}

Vec3 HalfedgeMesh::face_center(int f) const {
  Vec3 c = Vec3::Zero();
  const int start = face_start(f);
  for (int i = 0; i < degree(f); ++i) c += position(from(start + i));
  return c / degree(f);
}

int HalfedgeMesh::count_boundary_loops() const {
  std::vector<bool> seen(at(num_halfedges()), false);
  int loops = 0;
  for (int h = 0; h < num_halfedges(); ++h) {
    if (twin(h) >= 0 || seen[at(h)]) continue;
    ++loops;
    // Walk the loop: from the end of h, the next boundary half-edge is found
    // by rotating clockwise around to(h) until a half-edge without twin.
    int b = h;
    do {
      seen[at(b)] = true;
      int n = next(b);
      while (twin(n) >= 0) n = next(twin(n));
      b = n;
    } while (b != h && !seen[at(b)]);
  }
  return loops;
}

}  // namespace planner
