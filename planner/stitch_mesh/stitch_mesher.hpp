// Anisotropic stitch meshing (§6): a labelled disc (the cut mesh of §4, or any
// disc with course/wale side labels) is remeshed into a StitchMesh whose faces
// have the target course x wale size.
//
// Method (docs/stitch-mesh.md has the pictures):
//  1. §6.1 field: every input face gives a wale direction (its +v sides, and
//     its +u sides turned a quarter turn); a scalar "row time" t is fitted to
//     it in least squares (|grad t| = 1 / wale_mm), then straightened
//     towards unit speed until it settles, so rows keep their height where
//     the labels curl.
//  2. Rows: t is cut at K-1 levels placed by height (area over level-curve
//     length per thin slab of t), so each band between levels is one row of
//     height ~wale_mm even where t is flat. Each band component
//     is a strip: bottom chain (the level below, or a cast-on boundary),
//     top chain (the level above, or a bind-off boundary) and at most two
//     side boundaries that become wale edges.
//  3. §6.2 labels: stitch vertices are placed along each chain every ~course_mm
//     (shared level curves are sampled once, so rows fit); bottom sides are
//     course-in, top sides course-out, sides between chains wale.
//  4. §6.3 faces: each strip is zipped into quads, pentagons (two bottom or two
//     top sides: decrease / increase) and, where a strip ends in a point,
//     short-row triangles. Zipping never makes another face as long as one
//     chain is at most twice the other; where a top chain needs more than a
//     fixed bottom can feed, a bind-off stretch becomes a wale side or a side
//     below is split (docs/stitch-mesh.md); faces it still cannot make valid
//     are reported.
//  5. Relaxing: the stitch vertices inside the sheet move over the cut mesh
//     towards their sides' target lengths (springs, Gauss-Seidel sweeps, each
//     vertex put back on the surface); the boundary, the faces and their
//     types stay as zipped.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "planner/mesh/mesh.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"

namespace planner {

// Side directions as in cut.hpp: 0 = +u (course), 1 = +v (wale), 2 = -u, 3 = -v,
// in the face's own frame; faces are counter-clockwise seen from the front.
// The disc's surface (positions in mm) with its side labels.
struct LabelledDisc : PolygonMesh {
  std::vector<std::vector<int>> directions;  // per face, per side (side i: corner i -> i+1)
  // Optional: per face, per side, the cut-arc of a boundary side (kNoArc if none).
  std::vector<std::vector<std::int32_t>> arcs;
  // Optional: the garment's surface (Cut::surface). Stitch vertices are
  // relaxed onto it, and the stitches off the surface measured against it;
  // empty: the disc itself.
  PolygonMesh surface;
};

// Problems that make a LabelledDisc unusable (sizes, indices, degenerate
// faces, faces with no course or no wale side). Empty when usable.
std::vector<std::string> check_disc(const LabelledDisc& disc);

struct StitchMeshParams {
  double course_mm = 42.0 / 40.0;
  double wale_mm = 115.0 / 40.0;
  // Step 1: at most this many fits towards unit row speed after the fit to
  // the labels; they stop once no vertex's row time moves by more than
  // straighten_tolerance_rows (docs/stitch-mesh.md measures both).
  int straighten_iterations = 100;
  double straighten_tolerance_rows = 0.01;
  // Weight of the labelled direction against the fitted one in each
  // straightening fit (0: rows only keep their height).
  double label_weight = 0.1;
  // A boundary side whose outward normal makes |cos| below this with the row
  // direction runs along the wale: it becomes a wale side, not a course chain.
  double side_cosine = 0.3;
  // Boundary-only course chains shorter than this times wale_mm, lying
  // between chains of the other kind, are steps of a jagged cut: wale sides.
  double step_mm_factor = 1.5;
  // Cost of an increase or decrease in the zip, against the squared relative
  // error of a wale side's length: higher keeps more knit stitches.
  double pentagon_cost = 0.05;
  // Cost of breaking one of the Fig. 7 rules of thumb in the zip
  // (docs/stitch-mesh.md): shaping at the fabric's edge, shaping on shaping,
  // an increase beside a decrease.
  double stability_cost = 1.0;
  // Extra cost of a wale side more than 15% off wale_mm in the zip.
  double outside_cost = 0.05;
  // A row whose bottom and top chains meet on the boundary (where the
  // boundary crosses the rows obliquely) ends instead in a wale side this
  // many wales long, cut from the boundary there (0: rows end in a point).
  double tip_side_wales = 0.9;
  // Step 2: saddles of the row time in X-shaped or lopsided strips are held
  // on a level by a bump of the rows this many wales across (flat for the
  // first 0.4 of it); 0 leaves them where the fit put them.
  double saddle_wales = 5.0;
  // Step 2: fits of the row time that drain its interior extrema (each
  // pit or peak sloped towards the point where it spills, and t fitted
  // again) before any left is levelled; 0 levels them at once. Fits stop
  // once no extremum is left (docs/stitch-mesh.md, step 2, "Interior
  // extrema", has what one fit and three leave on the shared meshes).
  int drain_fits = 3;
  // Step 5: at most this many sweeps moving the inner stitch vertices over
  // the surface so the sides come closer to their target lengths (0: as
  // zipped). docs/stitch-mesh.md measures the count.
  int relax_sweeps = 150;
};

struct StitchMeshStats {
  int rows = 0;            // K
  int strips = 0;          // band components
  int lenses_skipped = 0;  // strips of one side on each chain (nothing between them)
  int saddles_split = 0;   // X-shaped strips around a saddle of the row time, split in two
  int saddles_pinned = 0;  // saddles of the row time held on a level
  int invalid_faces = 0;   // faces the zip could not make valid (see problems)
  // Bind-off boundary stretches at a top chain's end made wale sides, because
  // the row below could not feed that many stitches.
  int boundary_sides = 0;
  // Sides of a level curve split after the row below was made (its knit
  // stitch there became an increase), because the row above needed more.
  int sides_split_below = 0;
  // Rows that end in a wale side cut from the boundary instead of a point.
  int tip_sides = 0;
  // Vertices whose row time was levelled because the fitted one had an
  // interior extremum (a strip with a hole); 0 when it had none.
  int row_time_levelled = 0;
  // Vertices of the interior extrema the row time was fitted again to drain.
  int row_time_drained = 0;
  // Step 1: straightening fits made, and the mean angle (by area) between
  // the rows' wale direction (grad t) and the labelled one, in degrees.
  int straighten_fits = 0;
  double label_deviation_deg = 0;
  // Step 5: sweeps made (fewer than asked once no vertex moves) and their time.
  int relax_sweeps = 0;
  double relax_seconds = 0;
  double solve_seconds = 0;
  double total_seconds = 0;
};

struct StitchMeshResult {
  StitchMesh mesh;
  StitchMeshStats stats;
  // Why the mesh is not a valid stitch mesh (strips of unexpected shape, and
  // every line of `check`); empty on success.
  std::vector<std::string> problems;
};

// Never throws on bad geometry: problems are returned. The input must pass
// check_disc (a programming error otherwise: std::invalid_argument).
StitchMeshResult make_stitch_mesh(const LabelledDisc& disc, const StitchMeshParams& params);

// Figures of a stitch mesh, for tests and reports.
struct EdgeLengthStats {
  int count = 0;
  double mean_mm = 0;
  double min_mm = 0;
  double max_mm = 0;
  double within_15_percent = 0;  // fraction of edges within 15% of the target
};
struct StitchMeshFigures {
  int faces = 0;
  int knit = 0;
  int increase = 0;
  int decrease = 0;
  int short_row = 0;
  int vertices = 0;
  int boundary_loops = 0;
  int euler_characteristic = 0;
  double area_mm2 = 0;
  double boundary_length_mm = 0;
  EdgeLengthStats course;  // sides with a course role, each edge once
  EdgeLengthStats wale;
};
StitchMeshFigures measure(const StitchMesh& mesh);

// §6.3, Fig. 7: configurations that knit unreliably, counted in a finished
// stitch mesh (docs/stitch-mesh.md has a picture of each).
struct StabilityCounts {
  int edge_shaping = 0;     // 1: increase/decrease with a wale side on the boundary
  int stacked_shaping = 0;  // 2: increase/decrease on a course side of one below
  int opposed_shaping = 0;  // 3: increase and decrease sharing a wale side
  int one_stitch_rows = 0;  // 4: two short-row triangles sharing their wale side
};
StabilityCounts count_stability_rules(const StitchMesh& mesh);

// Stitches that leave the surface: faces with a side whose midpoint is more
// than `tolerance_mm` from the disc (the cut mesh). A stitch mesh follows its
// surface to within a fraction of a stitch; a side that does not spans a gap
// of it (the fans across a hole, docs/stitch-mesh.md), and the knitted piece
// will not take the surface's shape there. Only sides longer than twice the
// tolerance can be that far off, so only those are measured.
struct OffSurface {
  std::vector<std::size_t> faces;  // ascending
  double max_offset_mm = 0;        // farthest side midpoint from the surface
  std::size_t farthest_face = 0;   // the face with that side (when `faces` is not empty)
  double tolerance_mm = 0;         // as given
};
OffSurface off_surface_faces(const StitchMesh& mesh, const LabelledDisc& disc, double tolerance_mm);

// Which of the cut's two field directions is knitted as the course. §4.1
// labels the seed quad's sides "using field directions" and says no more:
// the cross field has four, and a disc whose course and wale sides are
// swapped everywhere is labelled as consistently. Where the cuts run along
// the rows of one way, the rows of the other end at them instead, and the
// stitch mesh of one way can be much better than the other's
// (docs/stitch-mesh.md, "Which way the rows run").
enum class KnitDirection : std::uint8_t {
  Best,    // mesh both ways and keep the better (stitch_mesh_score)
  AsCut,   // the cut's course sides are the course
  Turned,  // the cut's wale sides are the course
};
const char* to_string(KnitDirection direction);  // "best", "as-cut", "turned"
std::optional<KnitDirection> parse_knit_direction(const std::string& text);

// The disc with every side's direction turned a quarter (course <-> wale).
LabelledDisc turned(const LabelledDisc& disc);

// The targets of a stitch mesh's size (docs/stitch-mesh.md, "Targets"): the
// mean course and the mean wale side within this fraction of their targets.
constexpr double kMeanSizeTolerance = 0.05;

// How well a stitch mesh keeps the stitch size: for course and for wale
// sides, the share within 15% of the target less how far their mean is off
// the target beyond kMeanSizeTolerance; the lower of the two, less the share
// of its stitches off the surface (off_surface_faces at one wale);
// -infinity for a mesh with problems.
double stitch_mesh_score(const StitchMeshResult& result, const LabelledDisc& disc,
                         const StitchMeshParams& params);

struct DirectedStitchMesh {
  StitchMeshResult result;
  bool turned = false;                        // made from turned(disc)
  bool compared = false;                      // both ways were made (KnitDirection::Best)
  double score_as_cut = 0, score_turned = 0;  // when compared
};

// make_stitch_mesh of the disc as cut, turned, or both and the better (the
// cut's way on a tie).
DirectedStitchMesh make_directed_stitch_mesh(const LabelledDisc& disc,
                                             const StitchMeshParams& params,
                                             KnitDirection direction);

// Area and boundary length of the disc (for the expected stitch count).
double disc_area_mm2(const LabelledDisc& disc);
double disc_boundary_length_mm(const LabelledDisc& disc);

}  // namespace planner
