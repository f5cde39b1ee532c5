// The parts of the field-aligned remesher (remesh.hpp) that its sources
// share; not for use outside planner/proxy. field_aligned_remesh
// (remesh.cpp) runs them in this order:
//   remesh_sampling.cpp    sample_surface: the samples the fields live on
//   remesh_fields.cpp      solve_fields: orientation and position fields
//   remesh_extraction.cpp  extract_lattice: the lattice as polygons
//   remesh_cleanup.cpp     what the extraction leaves to repair: pinched
//                          vertices, folded quads, crumbs, holes
#pragma once

#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#include "planner/mesh/mesh.hpp"
#include "planner/proxy/remesh.hpp"

namespace planner::remesh_detail {

// Sorts `list` and drops its repeats.
inline void sort_unique(std::vector<int>& list) {
  std::sort(list.begin(), list.end());
  list.erase(std::unique(list.begin(), list.end()), list.end());
}

// The two fields per sample, as the extraction reads them.
struct LatticeFields {
  std::vector<Vec3> normal;
  std::vector<Vec3> orientation;  // 4-RoSy: one of the lattice's four axis directions
  std::vector<Vec3> origin;       // 4-PoSy: a lattice point near the sample
};

// The orientation field (`orientation_iterations` sweeps per level), then
// the position field of lattice spacing `s` (`position_iterations` sweeps
// per level), both solved coarse to fine over the hierarchy of the samples'
// graph. Deterministic.
LatticeFields solve_fields(const HalfedgeMesh& samples, double s, int orientation_iterations,
                           int position_iterations);

// The closest pair of lattice points of two neighbours near their middle
// (Instant Meshes' compat_position_extrinsic_4): p position, n normal, q
// orientation, o lattice origin, s spacing; q1 already matches q0.
std::pair<Vec3, Vec3> compatible_positions(const Vec3& p0, const Vec3& n0, const Vec3& q0,
                                           const Vec3& o0, const Vec3& p1, const Vec3& n1,
                                           const Vec3& q1, const Vec3& o1, double s);

// The lattice of the fields as polygons (Instant Meshes' extraction): the
// output graph, its edges shorter than params.merge_below lattice steps
// merged and dangling ones peeled, its faces traced. Its positions include
// vertices no face uses; pinches and folds are left to the clean-up.
PolygonMesh extract_lattice(const HalfedgeMesh& samples, LatticeFields fields,
                            const RemeshParams& params);

// A vertex whose faces form several fans (sheets touching at a point) gets
// one copy per fan, so the surface becomes a manifold there. Each copy, and
// the vertex itself, is then moved 2% of the way to its fan's centre, so
// the sheets no longer touch: later stages that weld the cut mesh's two
// sides by position (the wearability stage) must not merge them again.
void split_pinched_vertices(PolygonMesh& mesh);

// Folded quads welded (collapse_folded_quads), and any vertex the welds
// leave pinched split again, until none is left. Returns how many quads
// were welded.
int weld_folds(PolygonMesh& mesh, double ratio);

// Crumbs of a few faces left where the lattice folded are dropped; a
// second big component is kept (and fails the topology check).
void keep_largest_component(PolygonMesh& mesh);

// Where the tracing left a face out (a walk that did not close, a loop
// dropped as a spike) the extracted surface has a hole the input does not
// have. Every boundary loop but the `keep` longest is closed by one polygon
// (the proxy splits polygons into quads and triangles, §4.1); a hole wider
// than `max_corners` is left, and the topology check then rejects the mesh.
// Instant Meshes' extraction closes its holes the same way. Returns the
// number of holes closed. Vertices must not be pinched (one boundary gap
// each), so every boundary loop is simple.
int fill_holes(PolygonMesh& mesh, int keep, std::size_t max_corners);

}  // namespace planner::remesh_detail
