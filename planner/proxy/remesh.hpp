// Field-aligned quad-dominant remeshing in the manner of Instant Meshes
// (Jakob, Tarini, Panozzo, Sorkine-Hornung 2015): a 4-RoSy orientation
// field and a 4-PoSy position field are smoothed on a dense sampling of the
// surface, then the lattice is extracted: samples whose lattice points
// coincide collapse into one output vertex, samples one lattice step apart
// give an output edge, and faces are traced around the edges in their
// angular order. proxy.hpp decides when to use it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "planner/mesh/mesh.hpp"

namespace planner {

// A triangle mesh of the checked surface `input` with edges about
// `target_mm` long: polygons are fan-triangulated, a coarse mesh is
// subdivided 1-to-4 while its mean edge exceeds 2 * target_mm; a mesh whose
// mean edge is still below keep_above * target_mm is decimated (OpenMesh's
// decimater, shortest edges first; its link condition keeps the topology,
// normal flips are refused). The result is checked like any input.
PolygonMesh resample(const PolygonMesh& input, double target_mm, double keep_above = 0.5);

// The samples the remesher's fields live on: `resample`, then every edge
// longer than 1.25 * target_mm split at its midpoint; where a fifth of the
// edges or more are shorter than half the target (slivers of a CAD mesh cut
// up by subdivision and splits) they are collapsed and the long ones split
// again. Scaling the input and the target together scales the result.
PolygonMesh sample_surface(const PolygonMesh& input, double target_mm);

// Of the four directions o, n x o, -o, -n x o: the one closest to `target`.
Vec3 closest_representative(const Vec3& o, const Vec3& n, const Vec3& target);

// Smooth 4-RoSy orientation field per vertex (tangent unit vectors) and the
// vertex normals it is tangent to; deterministic.
std::vector<Vec3> orientation_field(const HalfedgeMesh& mesh, std::vector<Vec3>& normals,
                                    int iterations);

struct RemeshParams {
  double edge_mm = 1.0;             // lattice spacing: the target edge length
  int orientation_iterations = 30;  // smoothing sweeps per level of the hierarchy
  int position_iterations = 30;
  double sample_ratio = 0.4;  // sample spacing as a fraction of edge_mm
  double merge_below = 0.3;   // lattice edges shorter than this fraction of edge_mm are merged
  double fold_ratio = 0.1;    // quads with one diagonal shorter than this times the other are
                              // folds of the lattice: the short diagonal is welded
};

struct RemeshStats {
  int samples = 0;        // vertices of the sampled input the fields live on
  int holes_filled = 0;   // holes of the extraction closed by a polygon
  int folds_removed = 0;  // quads of nil area welded along their short diagonal
  std::string failure;    // why extraction gave no usable mesh (empty on success)
};

// Where the position field folds, the extraction can leave a quad whose two
// opposite corners lie almost on one point: a flap that doubles back over its
// neighbours (two such quads make a Z-fold; a corner shared with the sheet
// under the flap is then pinched and split). Its area is nil, and every stage
// after it sees a surface that turns back on itself: cut boundaries that run
// out and back along a needle-thin face, level curves that cross it in
// slivers. Such a quad is removed by welding its short diagonal (edge
// collapse, the quad's two other sides become one), when the diagonal is
// shorter than `ratio` times the other one, the two corners have no
// neighbour in common but the quad's other corners and no face but the quad,
// and they are not both on the boundary (which would pinch it). The welded
// vertex sits at their midpoint (at the boundary one's place when one is).
// Returns how many quads were removed.
int collapse_folded_quads(PolygonMesh& mesh, double ratio);

// A quad-dominant mesh of `input` (a checked surface; polygons are
// triangulated) with the same Euler characteristic and number of boundary
// loops, or nullopt (with stats.failure saying why) when the extraction did
// not give one connected, consistently oriented manifold of that topology.
std::optional<PolygonMesh> field_aligned_remesh(const PolygonMesh& input,
                                                const RemeshParams& params, RemeshStats& stats);

}  // namespace planner
