// The stitch-mesh stage's types (§6; the functions are in
// planner/pipeline.hpp): the cut disc remeshed into stitches of the
// machine's course x wale size (stitch_mesher.hpp), with its figures.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "knitout/diagnostic.hpp"
#include "planner/cut/cut_stage.hpp"
#include "planner/mesh/girth.hpp"
#include "planner/mesh/surface_distance.hpp"
#include "planner/stitch_mesh/gauge.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "planner/stitch_mesh/stitch_mesher.hpp"

namespace planner {

struct StitchMeshStageParams {
  StitchGauge gauge;        // the target course and wale lengths (§6.1, §8.1)
  StitchMeshParams mesher;  // its course_mm and wale_mm are the gauge's
  // Fine features (docs/stitch-mesh.md): parts of the garment whose girth
  // (the cut's girth_mm) is below this many of the larger stitch side.
  double min_girth_stitches = 3.0;
  // Stop with the list (P089) instead of knitting them at the gauge's
  // resolution with a warning (P088).
  bool refuse_fine_features = false;
  // Which way the rows run (KnitDirection, stitch_mesher.hpp).
  KnitDirection direction = KnitDirection::Best;
};

// The fine features of a cut at a stitch size: the parts of Q whose girth
// is below the bound, narrowest first.
struct FineFeatures {
  double bound_mm = 0.0;   // min_girth_stitches x the larger stitch side
  double stitch_mm = 0.0;  // that stitch side
  std::vector<NarrowPart> parts;
  // Longest side of the garment, mm (from the cut), for the size that
  // would knit every part at the bound.
  double size_mm = 0.0;
};
FineFeatures fine_features(const Cut& cut, const StitchMeshStageParams& params);

// The diagnostics of `found` into `sink` under `code`: one per part (the
// first ten), then what would knit them as they are.
void report_fine_features(const FineFeatures& found, bool refused, const std::string& source,
                          knitout::DiagnosticSink& sink);

// The stage's figures (stitch-mesh.json's "report", report.json's "stitch_mesh").
struct StitchMeshReport {
  StitchGauge gauge;
  StitchMeshFigures figures;
  StitchMeshStats stats;
  StabilityCounts stability;
  OffSurface off_surface;
  // How far the stitch vertices lie from the garment's surface (item 5 of
  // docs/stitch-mesh.md, "On the garment's surface"); measured against the
  // cut mesh where the cut folder does not record the garment
  // (`on_garment` false).
  SurfaceDistance shape;
  bool on_garment = false;
  // The way the rows run: the cut's course sides (false) or its wale sides;
  // with KnitDirection::Best, the scores of both ways.
  bool turned = false;
  bool compared = false;
  double score_as_cut = 0, score_turned = 0;
  FineFeatures fine;
  double disc_area_mm2 = 0;
  double seconds = 0;  // the whole stage
};

struct StitchMeshOutcome {
  StitchMesh mesh;
  StitchMeshReport report;
  std::uint64_t cut_id = 0;  // the cut it was made from (Cut::id)
};

// A stitch mesh as the scheduler reads it from a folder.
struct StitchMeshFile {
  StitchMesh mesh;
  std::uint64_t id = 0;      // fingerprint of stitch-mesh.smobj's bytes
  std::uint64_t cut_id = 0;  // from stitch-mesh.json; 0 when the folder has none
};

// The cut disc with its side directions (cut.direction, per half-edge of the
// proxy, whose faces the disc keeps in order) and, for sides on a cut, the
// index of the cut-arc in cut.arcs (as in cut.json).
LabelledDisc labelled_disc(const CutMesh& cut);

// stitch-mesh.obj: the faces as polygons, then `# type` comment lines
// (one per face: knit, increase, decrease, short-row).
void write_stitch_obj(std::ostream& out, const StitchMesh& mesh);

// "stitch mesh: N stitches (...) in R rows; course ...; wale ...; T s" as
// the verb prints it.
std::string describe(const StitchMeshOutcome& outcome);

}  // namespace planner
