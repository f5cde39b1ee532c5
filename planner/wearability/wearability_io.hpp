// Reading and writing what the wearability stage consumes and produces
// (docs/wearability.md has the formats).
//
// The garment's arcs, as cut.json lists them:
//
//   { "arcs": [ { "id": 0, "edges": [[a, b], [b, c], ...] }, ... ] }
//
// Vertex indices are 0-based indices of the vertices of the cut mesh. An arc
// may give "vertices": [a, b, c, ...] (a path) instead of "edges". The cut
// mesh may be split along its cuts or not: read_cover_mesh() welds vertices
// that coincide, so both sides of a cut become one vertex and the arc's edges
// name the welded edge.
//
// wearability.json (write_wearability, planner/pipeline.hpp): the id of the
// cut its labels belong to, a "summary" of the stage, and per arc its
// "label" ("sew" or "lace") and "wearability" (the test that decided it).
#pragma once

#include <iosfwd>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "knitout/diagnostic.hpp"
#include "planner/mesh/mesh.hpp"
#include "planner/wearability/wearability.hpp"
#include "planner/wearability/wearability_stage.hpp"

namespace planner {

// A mesh the wearability stage reads (the cut mesh, the wearer): any format
// read_polygon_soup reads (planner/mesh/mesh_io.hpp), with its diagnostics;
// W004 when the file cannot be opened, W003 when it has no faces.
std::optional<PolygonMesh> read_stage_mesh(const std::string& path, knitout::DiagnosticSink& sink);

// W005 (a warning): the garment's and the wearer's bounding boxes differ in
// size (their diagonals) by more than 25%, which a wearer read in other
// units or at another scale than the garment makes. Empty when they agree.
std::string size_disagreement(const PolygonMesh& garment, const PolygonMesh& wearer);

// The CoverMesh of a cut-mesh and its cuts.json document. Diagnostics: W010
// cuts.json is not the expected shape, W011 an arc edge that is not an edge
// of the mesh (or another invalid element), both naming the arc.
std::optional<CoverMesh> read_cover_mesh(const PolygonMesh& cut_mesh, const nlohmann::json& cuts,
                                         const std::string& cuts_source,
                                         knitout::DiagnosticSink& sink);

// The garment of a folder made by hand: DIR/cut-mesh.obj and the arcs of
// DIR/cut.json (read_stage_mesh, read_cover_mesh), subdivided for the cloth
// until it has `min_vertices` vertices (refined_for_cloth). Diagnostics:
// W003, W004, W010, W011 (docs/diagnostics.md).
std::optional<CoverMesh> read_garment(const std::string& dir, int min_vertices,
                                      knitout::DiagnosticSink& sink);

// Trial records as cuts.json and report.json write them:
// [{"seed", "success", "steps", "stalled", "min_distance"}, ...].
nlohmann::json trials_json(const std::vector<TrialOutcome>& trials);

// The content of wearability.json for `result`, whose labels belong to the
// cut with id `labelled_cut_id`.
nlohmann::json wearability_json(const Wearability& result, std::uint64_t labelled_cut_id);

}  // namespace planner
