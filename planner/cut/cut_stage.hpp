// The cut stage's types (§4; the functions are in planner/pipeline.hpp): the
// garment's quad-dominant proxy Q (§4.1, proxy/proxy.hpp) cut into one
// topological disc whose faces agree on the course and wale directions
// (§4.1-4.2, cut.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "planner/cut/cut.hpp"
#include "planner/mesh/mesh.hpp"
#include "planner/proxy/cross_field.hpp"
#include "planner/proxy/proxy.hpp"

namespace planner {

// The smoothest cross field of the garment at the proxy's scale
// (proxy/cross_field.hpp): the singularities the surface needs, to set
// beside Q's irregular vertices. Reported only; Q is not built from it.
struct FieldReport {
  double edge_mm = 0.0;  // the scale: the surface was brought to edges of about this
  int faces = 0;         // triangles of that surface
  int euler_characteristic = 0;
  int boundary_loops = 0;
  FieldSingularities singularities;
  int iterations = 0;  // inverse power iterations
};

// What the stage says about a run besides the CutMesh itself.
struct CutReport {
  std::string input;  // the garment's file, as the user named it
  std::string units = "mm";
  double scale = 1.0;
  Vec3 input_size_mm = Vec3::Zero();
  int input_vertices = 0;
  int input_faces = 0;
  bool remeshed = false;
  double proxy_edge_mm = 0.0;
  int polygons_split = 0;
  int triangles_paired = 0;
  int samples = 0;          // surface samples the remesh solved its fields on
  int holes_filled = 0;     // holes of the extraction closed by a polygon
  int folds_removed = 0;    // quads of nil area where the lattice folded, welded
  int remesh_attempts = 0;  // extractions tried, at spacings a few percent apart
  int edge_candidates = 0;  // field proxies made, at target edges a few percent apart
  std::string proxy_method = "input";
  std::string remesh_failure;
  // With --proxy field and a quad-dominant input: why it was kept or
  // replaced by the field-guided proxy (cut_stage.cpp); else empty.
  std::string input_verdict;
  int valence_flips = 0;  // field proxy: edges flipped toward valence 6
  int field_misfit = 0;   // field proxy: quarter turns of Q's indices away from the field's
  // How far Q (its vertices and face centroids) lies from the garment's
  // surface, mm: the stitch mesh is built on Q's disc.
  double surface_distance_max_mm = 0.0;
  double surface_distance_mean_mm = 0.0;
  FieldReport field;
  CutParams params;
  int picture_px = 0;  // the size of cuts-3d.png's views as cut.json records it; 0 = not drawn
  double load_seconds = 0.0;
  double proxy_seconds = 0.0;
  double field_seconds = 0.0;
  double cut_seconds = 0.0;
  double girth_seconds = 0.0;
};

// A cut and its report: the stage's output, and what later stages read.
struct Cut {
  CutMesh mesh;
  CutReport report;
  // The fingerprint of the cut as its files hold it, set by read_cut (0 for
  // a cut not read from a folder). Later stages record the id of the cut
  // they used, so a folder tells when their files belong to another cut.
  std::uint64_t id = 0;
  // The garment's girth (mesh/girth.hpp) at each vertex of Q, mm, measured
  // on the garment itself (kNoGirth where no ray could measure it): the
  // stitch-mesh stage finds the fine features in it. Empty for a cut
  // folder that does not record it.
  std::vector<double> girth_mm;
  // The garment's surface as it was cut (scaled, in mm): the stitch mesh is
  // laid on it, so the knitted piece keeps the garment's shape rather than
  // Q's facets (surface.obj in the folder). Empty for a cut folder that
  // does not record it; the stitch mesh then lies on the cut mesh.
  PolygonMesh surface;
};

// The cut's parameters for the field-guided proxy: square growth, tightened.
inline CutParams field_cut_params() {
  CutParams params;
  params.square_growth = true;
  params.tighten = true;
  return params;
}

// The defaults are `wearknit cut`'s: the field-guided proxy, its patch
// grown as a square and its cut tightened (docs/cutting.md). With
// ProxyMethod::Remesh the CLI turns both off (§4.2's random growth).
struct CutStageParams {
  ProxyParams proxy;
  CutParams cut = field_cut_params();
};

// The pictures of Fig. 5 (cut_pictures.hpp) that write_cut draws.
struct CutPictures {
  bool draw = true;
  int panel_px = 600;  // one of the 2x2 views of cuts-3d.png; layout-2d.png is 5/3 of it
};

// Q's irregular vertices (interior, corner count other than 4) by their
// index in quarter turns, 4 minus their corners (§4.1): the figures to set
// beside the field's singularities. On a closed Q the indices sum to 4χ.
FieldSingularities proxy_singularities(const CutMesh& cut);

// The stage's summary, three lines as `wearknit cut` prints them: the input
// and proxy, the field's singularities beside Q's, then the cut.
std::string describe(const Cut& cut);

}  // namespace planner
