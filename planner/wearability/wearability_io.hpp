// Reading and writing what the wearability stage consumes and produces.
//
// cuts.json (written by `wearknit cut`, read and extended by `wearknit
// wearability`; docs/wearability.md has the full description):
//
//   { "arcs": [ { "id": 0, "edges": [[a, b], [b, c], ...] }, ... ] }
//
// Vertex indices are 0-based indices of the vertices of cut-mesh.obj. An arc
// may give "vertices": [a, b, c, ...] (a path) instead of "edges". The cut
// mesh may be split along its cuts or not: read_cover_mesh() welds vertices
// that coincide, so both sides of a cut become one vertex and the arc's edges
// name the welded edge. Other fields are kept as they are; the stage adds
// "label" ("sew" or "lace") and "wearability" (its test) to every arc and a
// top-level "wearability" summary.
#pragma once

#include <iosfwd>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "knitout/diagnostic.hpp"
#include "planner/mesh/mesh.hpp"
#include "planner/wearability/wearability.hpp"

namespace planner {

// A mesh the wearability stage reads (the cut mesh, the wearer): any format
// read_polygon_soup reads (planner/mesh/mesh_io.hpp), with its diagnostics;
// W004 when the file cannot be opened, W003 when it has no faces.
std::optional<PolygonMesh> read_stage_mesh(const std::string& path, knitout::DiagnosticSink& sink);

// The CoverMesh of a cut-mesh and its cuts.json document. Diagnostics: W010
// cuts.json is not the expected shape, W011 an arc edge that is not an edge
// of the mesh (or another invalid element), both naming the arc.
std::optional<CoverMesh> read_cover_mesh(const PolygonMesh& cut_mesh, const nlohmann::json& cuts,
                                         const std::string& cuts_source,
                                         knitout::DiagnosticSink& sink);

// Trial records as cuts.json and report.json write them:
// [{"seed", "success", "steps", "stalled", "min_distance"}, ...].
nlohmann::json trials_json(const std::vector<TrialOutcome>& trials);

// Adds the results to the cuts.json document (see the header comment).
// `study` holds R runs; the labels are those of the first run.
void annotate_cuts(nlohmann::json& cuts, const LacingStudy& study, const WearabilityParams& params);

}  // namespace planner
