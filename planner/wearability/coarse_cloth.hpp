// The elimination's cloth: the garment simplified to a given number of
// vertices with every cut-arc kept (docs/wearability.md, "The cloth's
// resolution").
//
// The proxy Q is as fine as the cut needs to follow the surface; the
// strip-off test needs far fewer vertices, and a step costs time in
// proportion to them. `coarsened` collapses edges, first those whose
// longest new edge is shortest (OpenMesh's decimater with a module that
// keeps the arcs), so the edges come out of about one length: a vertex off
// every arc and off the boundary may collapse into any neighbour; a vertex
// inside an arc or a boundary loop only along it, into its neighbour on
// it; arc ends, branch nodes and one vertex of every closed chain never
// move. The triangles are then paired into quads across edges off the
// arcs where the quad is convex and near-square, so that most of the
// cloth has §8.2's shear and bend springs. Arc indices and names are kept,
// so sew and lace answers on the coarse cloth are answers for the arcs of
// the garment.
#pragma once

#include "planner/wearability/wearability.hpp"

namespace planner {

// The mesh simplified to about `target_vertices` vertices (never fewer than
// the arcs' fixed vertices), every arc a chain of the result's edges. The
// mesh as given when it has at most `target_vertices` vertices, when the
// target is not positive, or when the simplified mesh fails `validate`.
CoverMesh coarsened(const CoverMesh& mesh, int target_vertices);

}  // namespace planner
