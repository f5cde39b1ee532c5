// The quad-dominant proxy Q of the garment surface (§4.1).
//
// With ProxyMethod::Field, the default, a surface that is not quad-dominant
// becomes the field-guided triangle proxy of field_proxy.hpp (the cut stage
// also replaces a quad-dominant input that is not clean by it, cut_stage.hpp).
// With ProxyMethod::Remesh:
// a quad-dominant input (more than half of its faces are quads) is used as
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

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "planner/mesh/mesh.hpp"

namespace planner {

// How Q is made of a surface that is not quad-dominant (docs/cutting.md, "The proxy Q").
enum class ProxyMethod : std::uint8_t { Field, Remesh };
// The method's name as `--proxy` and cut.json spell it: field or remesh.
const char* proxy_method_name(ProxyMethod method);
std::optional<ProxyMethod> proxy_method(std::string_view name);

struct ProxyParams {
  ProxyMethod method = ProxyMethod::Field;
  // Target edge length of a remeshed proxy, mm; 0 picks the length that
  // gives about `auto_faces` quads.
  double proxy_edge_mm = 0.0;
  int auto_faces = 3000;
  int field_iterations = 30;     // orientation-field smoothing sweeps
  int position_iterations = 30;  // position-field smoothing sweeps
  // Field: field_proxy.hpp's parameters.
  double flip_bend_deg = 30.0;
  int misfit_cost = 30;
  int singular_cost = 40;
  // Field: a quad-dominant input is kept only when it is clean against the
  // field's singularity count f: at most min(clean_ratio * f,
  // clean_bound_ratio * f + clean_bound_extra) singular vertices, of which
  // at most clean_pairs_ratio sit in adjacent +1/-1 pairs (cut_stage.cpp).
  double clean_ratio = 1.5;
  double clean_bound_ratio = 1.2;
  int clean_bound_extra = 4;
  double clean_pairs_ratio = 0.1;
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
  // "field": proxies made, at target edges a few percent apart, of which the
  // one with the fewest singular vertices is kept (field_proxy.hpp)
  int edge_candidates = 0;
  // "field" (field_proxy.hpp): every face a triangle, with these vanishing
  // corners (per face); empty for the other methods.
  std::vector<int> vanishing_corner;
  int valence_flips = 0;  // field: edges flipped toward valence 6
  int field_misfit = 0;   // field: quarter turns of Q's indices away from the field's
};

// More than half of the faces are quads.
bool is_quad_dominant(const PolygonMesh& mesh);

// Sum of the faces' areas (each polygon by its vector area).
double total_area(const PolygonMesh& mesh);

// Splits every face with more than 4 corners in place; returns how many were split.
int split_polygons(PolygonMesh& mesh);

// The proxy Q of a checked mesh (mesh_io.hpp check_mesh).
ProxyResult make_proxy(const PolygonMesh& input, const ProxyParams& params);

// The field-guided proxy of a checked mesh, whatever its faces.
ProxyResult make_field_proxy(const PolygonMesh& input, const ProxyParams& params);

}  // namespace planner
