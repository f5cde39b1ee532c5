// How thick the garment is around each point: the girth of the surface's
// cross-section there, and the parts of the surface whose girth is below a
// bound (fine features: spikes, claws, fingers, thin handles).
//
// At a vertex, a ray along the inward normal measures the thickness t (the
// first crossing of the surface, as the shape diameter function does). From
// the middle of that chord, rays along four tangent lines (every 45 degrees)
// measure how wide the solid is across; the narrowest line gives the width
// w. A finger has t and w both about its diameter; a plate (an ear) has a
// small t but a wide w. The girth is the perimeter of the ellipse with
// those diameters, pi (t + w) / 2: a tube of diameter d has girth pi d. It is
// what a knitted tube round the feature has to span; docs/stitch-mesh.md
// ("Fine features") gives the rule the stitch-mesh stage applies to it.
#pragma once

#include <limits>
#include <vector>

#include "planner/mesh/mesh.hpp"

namespace planner {

// A girth no ray could measure: the ray left an open surface.
inline constexpr double kNoGirth = std::numeric_limits<double>::infinity();

// Per vertex of `mesh` (mm), then replaced by the median over the vertex
// and its neighbours to quiet single bad rays. Faces may be polygons; the
// orientation is taken from the sign of the enclosed volume.
std::vector<double> measure_girth(const PolygonMesh& mesh);

// The girth at each of `points`: that of the nearest vertex of `mesh`.
std::vector<double> girth_at(const PolygonMesh& mesh, const std::vector<double>& girth,
                             const std::vector<Vec3>& points);

// A connected part of the surface whose vertices all have a girth below
// the bound.
struct NarrowPart {
  int vertices = 0;
  int narrowest_vertex = -1;  // of the mesh measured
  Vec3 narrowest_at = Vec3::Zero();
  double girth_mm = 0.0;  // the narrowest girth of the part
  Vec3 centre = Vec3::Zero();
  double extent_mm = 0.0;  // the farthest of its vertices from the centre
};

// The parts of `mesh` whose girth is below `bound_mm`, narrowest first;
// vertices join a part across the edges of the faces.
std::vector<NarrowPart> narrow_parts(const PolygonMesh& mesh, const std::vector<double>& girth,
                                     double bound_mm);

}  // namespace planner
