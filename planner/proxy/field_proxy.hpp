// The field-guided proxy Q (docs/cutting.md, "The field-guided proxy"): a
// triangle mesh of the garment whose vanishing corners (§4.1) are chosen so
// that Q's irregular vertices are where the smoothest cross field of the
// surface (cross_field.hpp) has its singularities, and nowhere else the
// count of corners allows. §9 names a meshing technique made for knitting as
// future work; this is ours.
//
// Every face of Q is a triangle, and a triangle with a vanishing corner is a
// quad with one side of nil length: its two sides at the vanishing corner run
// along one direction of the field, the side across it along the other. So
// the choice of one vanishing corner per triangle decides every vertex's
// corner count, c(v) = triangles around v - vanishing corners at v, and
// through it the vertex's index 4 - c(v) in quarter turns. The choice is a
// min-cost flow: each triangle sends one unit to one of its three corners;
// vertex v with x units has c(v) = valence(v) - x and costs
//   misfit_cost * |c(v) - (4 - k(v))| + singular_cost * (c(v) - 4)²
// where k(v) is the field's index at v (0 on the boundary, where nothing is
// charged). The cost is convex in x, so the flow is exact (LEMON's network
// simplex). With singular_cost above misfit_cost (40 against 30) an index
// placed where the field has its singularity costs 40 and anywhere else 70,
// so the indices the corner counts need (they sum to 4χ) go to the field's
// singularities; a +1/-1 pair of the field costs 80 kept and 60 cancelled,
// so pairs cancel unless the triangles' alignment (below) outweighs it, and
// Q ends near the fewest singular vertices its topology allows, placed by the
// field. Index ±2 costs four times ±1, so singularities are not merged.
// Each corner's own cost adds how badly the triangle would sit in the field
// with that corner vanishing. A +1 and a -1 vertex of Q at most pair_rings
// edges apart that the alignment kept are two ends of cut-arcs the surface
// does not need: every vertex within pair_rings edges of them then costs
// pair_cost more per quarter turn of index (the neighbourhood, so that the
// pair is cancelled, not moved a few edges apart) and the flow runs again,
// for at most pair_rounds rounds, until no such pair is left.
//
// Resampling a fine scan down to the proxy's edge (remesh.hpp `resample`,
// the decimater's long chain of collapses) is chaotic: the scale's ninth
// digit changes which triangles Q has, and with them the field's
// singularities and Q's singular vertices (12 to 22 on `gargoyle` at 100
// mm). So Q is made at the target edge and at edge_factors of it, and the
// one with the fewest singular vertices is kept (the first on a tie).
#pragma once

#include <vector>

#include "planner/mesh/mesh.hpp"

namespace planner {

struct FieldProxyParams {
  double edge_mm = 1.0;          // target edge of the triangles
  double flip_bend_deg = 30.0;   // equalize_valences: the most a flip may fold the surface
  double min_corner_deg = 10.0;  // equalize_valences: the least corner a flip may make
  int misfit_cost = 30;          // per quarter turn of index away from the field's
  int singular_cost = 40;        // times (c(v) - 4)²
  int alignment_cost = 10;       // a corner whose triangle lies at 45 degrees to the field
  int pair_cost = 40;            // per quarter turn near a pair (pair_rings), added each round
  int pair_rounds = 4;           // flows run again to cancel near pairs (0: none)
  int pair_rings = 2;            // a +1 and a -1 this many edges apart or nearer are a pair
  // Further proxies at these multiples of edge_mm (none: the one alone).
  std::vector<double> edge_factors{0.97, 1.03, 0.94, 1.06};
  int threads = 0;  // for the proxies at the edges; 0: OpenMP's count (cloth::resolve_threads)
};

struct FieldProxy {
  PolygonMesh mesh;                   // triangles only
  std::vector<int> vanishing_corner;  // per face: the corner index that vanishes
  int valence_flips = 0;              // edges flipped by equalize_valences
  int field_singularities = 0;        // of the field on `mesh`
  int misfit = 0;                     // sum over interior vertices of |c(v) - (4 - k(v))|
  double mean_alignment = 0.0;        // mean misalignment of the chosen corners, 0..1
  int singular_vertices = 0;          // interior vertices whose corners are not a multiple of 4
  double edge_mm = 0.0;               // the target edge of the one kept
  int candidates = 1;                 // proxies made (1 + edge_factors)
};

// Flips edges of a triangle mesh toward valence 6 inside and 4 on the
// boundary (a flip is made when it lowers the sum of squared deviations of
// its four vertices), only where the two new triangles fold by at most
// `bend_deg`, no corner falls below `min_corner_deg` and the new edge is not
// already there. Sweeps until none is made; returns the flips made.
int equalize_valences(PolygonMesh& triangles, double bend_deg, double min_corner_deg);

// How badly triangle f of `mesh` sits in a cross field with corner `corner`
// vanishing: the side across the corner and the line from the corner to
// that side's middle should each run along a direction of the cross
// (`direction`: one of its directions, tangent to f). 0 when both do, 1 when
// both lie at 45 degrees to it.
double vanishing_misalignment(const PolygonMesh& mesh, int f, int corner, const Vec3& direction);

// The proxy of a checked surface: resampled to triangles of about
// params.edge_mm, valences equalized, the smoothest cross field solved on
// those triangles and the vanishing corners chosen by the flow above; made
// at each edge of params.edge_factors too (params.threads share them), and the one
// with the fewest singular vertices kept. Deterministic.
FieldProxy field_guided_proxy(const PolygonMesh& surface, const FieldProxyParams& params);

// The flow alone (and its rounds against near pairs), on a triangle mesh
// with its field's per-vertex index (in quarter turns) and one field
// direction per triangle.
std::vector<int> field_vanishing_corners(const PolygonMesh& triangles,
                                         const std::vector<int>& field_index,
                                         const std::vector<Vec3>& field_direction,
                                         const FieldProxyParams& params);

}  // namespace planner
