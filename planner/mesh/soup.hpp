// What the planner's stages do with a bare polygon soup (a PolygonMesh with
// no connectivity built): key its edges, number its corners, find the fans
// around its vertices and its connected components, and drop the vertices no
// face uses. The mesh checks (mesh_io.hpp) and the proxy's remesher share
// these, so a pinch or a component means the same thing to both.
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "planner/common/union_find.hpp"
#include "planner/mesh/mesh.hpp"

namespace planner {

// Two ints packed into one hashable key, `a` in the high 32 bits: a directed
// edge a -> b, or a cell (u, v) of a grid. Distinct pairs give distinct keys.
inline std::uint64_t pair_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

// The undirected edge between a and b, as (smaller, larger).
inline std::pair<int, int> undirected_edge(int a, int b) {
  return {std::min(a, b), std::max(a, b)};
}

// Corner numbering of a soup: the corners of face f are
// start[f] .. start[f + 1] - 1 in the face's order; start has one entry more
// than there are faces, the number of corners.
std::vector<int> corner_starts(const PolygonMesh& mesh);

// The fans of faces around each vertex: two corners of one vertex are joined
// when their faces share an edge out of it, so a vertex whose corners form
// more than one set is a pinch point (sheets touching at a point). Corners
// are numbered by `corner_start` (corner_starts). Faces with usable[f] false
// join nothing; an empty `usable` means every face.
UnionFind corner_fans(const PolygonMesh& mesh, const std::vector<int>& corner_start,
                      const std::vector<bool>& usable = {});

// Vertices joined through the faces that share them: the connected
// components of the surface. Faces with usable[f] false join nothing; an
// empty `usable` means every face.
UnionFind vertex_components(const PolygonMesh& mesh, const std::vector<bool>& usable = {});

// Drops the vertices no face uses; the others are renumbered in the order
// the faces first use them.
void drop_unused_vertices(PolygonMesh& mesh);

// Mean length of the faces' sides (an edge shared by two faces counts
// twice), 0 for a mesh without faces.
double mean_edge_length(const PolygonMesh& mesh);

// The vector area of a face: its normal times its area (Newell), not normalised.
Vec3 vector_area(const PolygonMesh& mesh, const std::vector<int>& face);

}  // namespace planner
