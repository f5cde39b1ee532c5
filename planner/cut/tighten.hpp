// Tightening a cut graph (docs/cutting.md, "Tightening the cut"): where the
// patch fronts of §4.2 met in a ragged line, each stretch of the cut is
// replaced by the shortest one that still opens Q into a disc.
#pragma once

#include <vector>

#include "planner/cut/cut.hpp"
#include "planner/mesh/mesh.hpp"

namespace planner {

// Shortens the cut of a disc. The disc stays one disc and keeps every
// vertex that must be on the cut (singular, on the mesh boundary) on it. `cut_edge` is per
// edge of q and is changed in place; returns the number of moves.
//
// Paths are measured by a cost: an edge's length, up to four times that
// for an edge at 45° to the labels' directions (tighten.cpp).
// Two kinds of move, repeated until neither changes the cut:
//  - every path of the cut between two nodes is replaced by the shortest
//    path between its ends that still leaves Q one disc (on Q cut along the
//    rest of the cut, an annulus, the new path must join its two boundary
//    loops, or reach an end inside it);
//  - a branch node at a vertex that need not be on the cut moves onto the
//    node at the far end of one of its paths (the others rerouted there),
//    so that the arcs end where the surface needs them to.
int tighten_cut(const HalfedgeMesh& q, const FieldLabels& labels, std::vector<bool>& cut_edge);

}  // namespace planner
