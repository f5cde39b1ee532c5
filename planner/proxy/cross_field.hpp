// The smoothest cross field of a surface (Knöppel, Crane, Pinkall, Schröder
// 2013, "Globally Optimal Direction Fields") and its singularities: the
// yardstick for how many singular vertices the proxy Q needs (§4.1; §9 names
// a mesher made for knitting as future work). The cut stage reports it next
// to Q's singular vertices (docs/cutting.md); nothing is built from it yet.
//
// Discretisation (face-based): the surface is a triangle mesh; each
// triangle f carries one unit complex number u_f = exp(4iφ_f), the fourth
// power of the field's angle φ_f in the triangle's own frame (its first
// side and the normal's cross product with it), so the four directions of a
// cross are one value. The discrete Levi-Civita connection unfolds two
// triangles about their shared edge: the angle ρ_fg = θ_g(e) − θ_f(e)
// between the edge's directions in the two frames carries an angle of f to
// one of g, and the transport of the fourth power is r_fg = exp(4iρ_fg).
// Singularities then sit at vertices, where Q's also sit.
#pragma once

#include <complex>
#include <map>
#include <vector>

#include "planner/mesh/mesh.hpp"

namespace planner {

struct CrossFieldParams {
  // The scale of the field, mm: the surface is first brought to edges of
  // about this length (remesh.hpp `resample`: a much finer mesh is
  // decimated, a much coarser one subdivided), so that detail far below it
  // makes no singularity. 0 takes the surface as it is (polygons are
  // fan-triangulated).
  double edge_mm = 0.0;
  // Weight w of the alignment with the principal curvature directions: 0
  // is the smoothest field; w > 0 gives Knöppel et al.'s field guided by
  // q, (A - λ_t M) u = M q, with λ_t = -w / edge² (edge: edge_mm, or the
  // mean edge when that is 0) and q the fourth power of each triangle's
  // principal direction, weighted by its curvature anisotropy. The larger
  // w, the closer the field follows the curvature (over lengths above
  // about edge / sqrt(w) smoothness wins).
  double curvature_weight = 0.0;
  int max_iterations = 200;  // inverse power iterations (the smoothest field)
};

struct CrossField {
  PolygonMesh surface;  // the triangles the field lives on, mm
  // Per triangle: u_f = exp(4iφ_f) in the triangle's frame (see above).
  std::vector<std::complex<double>> field;
  // Per triangle: one of the field's four directions, a unit tangent vector.
  std::vector<Vec3> direction;
  // Per vertex: the index in quarter turns (+1 at a valence-3 corner of a
  // quad mesh, -1 at a valence-5 one); 0 on the boundary, where none is
  // counted (a free boundary: the field meets it at any angle).
  std::vector<int> index;
  int euler_characteristic = 0;  // V - E + F of `surface`
  int boundary_loops = 0;
  int iterations = 0;   // inverse power iterations run (0 with curvature alignment)
  double energy = 0.0;  // u^H A u / u^H M u of the result, 1/mm²
};

// The smoothest cross field of `surface` (a checked mesh, mesh_io.hpp
// check_mesh, in mm) at the scale params.edge_mm: the eigenvector of the
// smallest eigenvalue of A u = λ M u (Knöppel et al.'s smoothest field),
// found by inverse power iteration with a sparse LDLᵀ factorisation of A + εM; or, with
// params.curvature_weight > 0, the curvature-aligned field. The indices of
// the interior vertices are integers by construction, and on a closed
// surface they sum to 4χ (Poincaré–Hopf); a violation is a bug and throws
// std::logic_error. Deterministic.
CrossField smoothest_cross_field(const PolygonMesh& surface, const CrossFieldParams& params);

// Each polygon as a fan of triangles from the first corner whose diagonals
// are not already edges of the mesh: a diagonal that repeats an edge (two
// quads sharing two sides at a valence-2 vertex) would join three
// triangles and break the manifold. Among those corners the first whose fan
// holds no flat triangle (twice the area under 0.01 of the longest side
// squared; a straight corner fanned from its neighbour makes one), else the
// least flat. `resample` fans polygons from their first corner whatever the
// diagonals; give it this mesh instead.
PolygonMesh fan_triangulated(const PolygonMesh& mesh);

// What the cut stage reports of a field.
struct FieldSingularities {
  int count = 0;                // interior vertices with a non-zero index
  int index_sum = 0;            // over interior vertices; 4χ on a closed surface
  std::map<int, int> by_index;  // index (quarter turns) -> vertices
};
FieldSingularities field_singularities(const CrossField& field);

}  // namespace planner
