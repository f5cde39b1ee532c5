// The vanishing corners of Q's triangles that leave Q as regular as it can
// be (§4.1 departs here: it takes each triangle's most acute corner; see
// docs/cutting.md, "Choosing the vanishing corners").
//
// A vertex's corner count is the number of face corners around it that do
// not vanish. Its misfit is |corner count - 4| for an interior vertex and 0
// on the mesh boundary; Q's misfit is the sum over its vertices.
#pragma once

#include <vector>

#include "planner/mesh/mesh.hpp"

namespace planner {

// Per face of q, the corner index of its vanishing corner (-1 for a face
// that is not a triangle), chosen so that:
//   1. Q's misfit is the least any choice gives (exactly: a min-cost flow);
//   2. among those choices, the vanishing corners' angles sum to the least
//      (to within 1/10000 of pi radians per triangle), so every triangle
//      keeps its most acute corner unless regularity asks otherwise;
//   3. then, where moving vanishing corners along a chain of triangles keeps
//      the misfit and lowers the number of singular interior vertices
//      (corner count % 4 != 0), they move; chains are taken until none is
//      left, so this last step lowers the count without promising its least.
// Deterministic. Time: a shortest-path search per triangle over the group of
// triangles it shares vertices with; quad-dominant meshes have small groups.
std::vector<int> optimal_vanishing_corners(const HalfedgeMesh& q);

// Q's misfit with the given vanishing corners (per face, -1 for quads).
int corner_misfit(const HalfedgeMesh& q, const std::vector<int>& vanishing_corner);

}  // namespace planner
