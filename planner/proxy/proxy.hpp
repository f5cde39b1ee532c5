// The quad-dominant proxy Q of the garment surface (§4.1).
//
// A quad-dominant input (more than half of its faces are quads) is used as
// it is. Any other input (a triangle mesh, as users have) is remeshed with
// field-aligned extraction (remesh.hpp) at the target edge length, tried
// again at nearby spacings when the extraction is not clean; when none is,
// the resampled surface's triangles are paired into quads whose sides
// follow a smooth 4-fold orientation field. docs/cutting.md says where this
// differs from Instant Meshes.
// Either way faces with more than 4 corners are then split (§4.1): a
// pentagon by the edge that splits its largest corner, larger polygons by
// cutting quads off their largest corner.
#pragma once

#include <string>

#include "planner/mesh/mesh.hpp"

namespace planner {

struct ProxyParams {
  // Target edge length of a remeshed proxy, mm; 0 picks the length that
  // gives about `auto_faces` quads.
  double proxy_edge_mm = 0.0;
  int auto_faces = 3000;
  int field_iterations = 30;     // orientation-field smoothing sweeps
  int position_iterations = 30;  // position-field smoothing sweeps
};

struct ProxyResult {
  PolygonMesh mesh;  // quads and triangles only
  bool remeshed = false;
  double edge_mm = 0.0;  // the target edge length used (remeshed), else the mean edge length
  int polygons_split = 0;
  int triangles_paired = 0;
  // "input" (quad-dominant, kept), "instant-meshes" (field-aligned
  // extraction), or "paired" (the extraction failed; stats say why, and
  // triangles of the resampled surface were paired along the field instead).
  std::string method = "input";
  std::string remesh_failure;
  int samples = 0;        // remeshed: the surface samples the fields were solved on
  int holes_filled = 0;   // remeshed: holes of the extraction closed by a polygon
  int folds_removed = 0;  // remeshed: quads of nil area where the lattice folded, welded
  // remeshed: extractions tried (the first spacing, then 99, 101, 97, 103% of
  // it until one gives a clean surface)
  int remesh_attempts = 0;
};

// More than half of the faces are quads.
bool is_quad_dominant(const PolygonMesh& mesh);

// Sum of the faces' areas (each polygon by its vector area).
double total_area(const PolygonMesh& mesh);

// Splits every face with more than 4 corners in place; returns how many were split.
int split_polygons(PolygonMesh& mesh);

// The proxy Q of a checked mesh (mesh_io.hpp check_mesh).
ProxyResult make_proxy(const PolygonMesh& input, const ProxyParams& params);

}  // namespace planner
