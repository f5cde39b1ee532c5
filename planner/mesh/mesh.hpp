// The planner's meshes: the one polygon-mesh type (a soup: positions and
// faces), and the half-edge connectivity every algorithm walks.
//
// Units: positions are in millimetres once `load_mesh` has applied --units
// and --scale (mesh_io.hpp); every length the planner reports is in mm.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "planner/common/index.hpp"
#include "simulators/cloth/polygon_mesh.hpp"

namespace planner {

using Vec3 = Eigen::Vector3d;

// Faces are lists of vertex indices (0-based), counter-clockwise seen from
// outside. No connectivity is implied; `check_mesh` (mesh_io.hpp) says
// whether a soup is a usable surface. The same type as the cloth
// simulation's garment (simulators/cloth/polygon_mesh.hpp).
using PolygonMesh = cloth::PolygonMesh;

// The angle between a and b, radians in [0, pi]; 0 when either is zero.
double angle_between(const Vec3& a, const Vec3& b);

// Half-edge connectivity over a PolygonMesh that is an oriented 2-manifold
// (with or without boundary). Half-edge ids are dense: the half-edges of face
// f are face_start(f) .. face_start(f) + degree(f) - 1 in the face's corner
// order, half-edge face_start(f) + i going from corner i to corner i + 1.
// Constructing from a soup that is not an oriented manifold is a programming
// error (check it first) and throws std::logic_error.
class HalfedgeMesh {
 public:
  HalfedgeMesh() = default;
  explicit HalfedgeMesh(PolygonMesh mesh);

  const PolygonMesh& polygons() const { return mesh_; }
  const Vec3& position(int v) const { return mesh_.positions[at(v)]; }

  int num_vertices() const { return static_cast<int>(mesh_.positions.size()); }
  int num_faces() const { return static_cast<int>(mesh_.faces.size()); }
  int num_halfedges() const { return static_cast<int>(from_.size()); }
  int num_edges() const { return num_edges_; }

  int face_start(int f) const { return face_start_[at(f)]; }
  int degree(int f) const { return face_start_[at(f) + 1] - face_start_[at(f)]; }
  int face(int h) const { return face_[at(h)]; }
  int from(int h) const { return from_[at(h)]; }
  int to(int h) const { return from_[at(next(h))]; }
  int next(int h) const;
  int prev(int h) const;
  // The opposite half-edge, -1 on the mesh boundary.
  int twin(int h) const { return twin_[at(h)]; }
  int edge(int h) const { return edge_[at(h)]; }
  // One half-edge of an edge (the other is its twin, if any).
  int edge_halfedge(int e) const { return edge_halfedge_[at(e)]; }
  // Index of half-edge h inside its face (its corner number).
  int corner(int h) const { return h - face_start(face(h)); }
  bool is_boundary_vertex(int v) const { return boundary_vertex_[at(v)]; }
  bool is_boundary_edge(int e) const { return twin(edge_halfedge(e)) < 0; }

  // Outgoing half-edges of v in counter-clockwise order. For a boundary
  // vertex the list starts with the outgoing boundary half-edge (the one
  // with no face on its right) so the fan is walked without a gap.
  std::vector<int> outgoing(int v) const;

  double edge_length(int h) const { return (position(to(h)) - position(from(h))).norm(); }
  // Interior angle of face(h) at from(h), radians.
  double corner_angle(int h) const;
  Vec3 face_normal(int f) const;  // area-weighted (Newell), not normalised
  Vec3 face_center(int f) const;

  int count_boundary_loops() const;
  int euler_characteristic() const { return num_vertices() - num_edges() + num_faces(); }

 private:
  PolygonMesh mesh_;
  std::vector<int> face_start_{0};
  std::vector<int> face_;
  std::vector<int> from_;
  std::vector<int> twin_;
  std::vector<int> edge_;
  std::vector<int> edge_halfedge_;
  std::vector<int> vertex_out_;  // one outgoing half-edge; the boundary one if any
  std::vector<bool> boundary_vertex_;
  int num_edges_ = 0;
};

}  // namespace planner
