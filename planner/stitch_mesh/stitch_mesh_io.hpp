// The stitch-mesh stage's files in a plan folder, and the bridge from the
// cut stage (§4) to stitch meshing (§6).
#pragma once

#include <string>

#include "planner/cut/cut.hpp"
#include "planner/stitch_mesh/gauge.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "planner/stitch_mesh/stitch_mesher.hpp"

namespace planner {

// The cut disc with its side directions (cut.direction, per half-edge of the
// proxy, whose faces the disc keeps in order) and, for sides on a cut, the
// index of the cut-arc in cut.arcs (as in cuts.json).
LabelledDisc labelled_disc(const CutMesh& cut);

// stitch-mesh.obj: the faces as polygons, then `# type` comment lines
// (one per face: knit, increase, decrease, short-row).
void write_stitch_obj(std::ostream& out, const StitchMesh& mesh);

// What the stage adds to report.json under "stitch_mesh".
struct StitchMeshReport {
  StitchGauge gauge;
  StitchMeshFigures figures;
  StitchMeshStats stats;
  StabilityCounts stability;
  OffSurface off_surface;
  double disc_area_mm2 = 0;
  double seconds = 0;  // the whole stage: read, mesh, write
};

// Reads DIR/report.json (if any), sets its "stitch_mesh" member and writes it
// back atomically, keeping every other member. Returns an empty string or a
// message naming the file that could not be read or written.
std::string merge_stitch_report(const std::string& dir, const StitchMeshReport& report);

}  // namespace planner
