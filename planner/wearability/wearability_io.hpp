// Reading and writing what the wearability stage consumes and produces.
//
// OBJ: `v x y z` and `f i j k ...` lines (1-based or negative indices,
// `i/t/n` forms accepted, everything else ignored).
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
#include "planner/wearability/wearability.hpp"

namespace planner {

struct PolygonMesh {
  std::vector<Vec3> vertices;
  std::vector<std::vector<int>> faces;
};

// Diagnostics (docs/diagnostics.md): W001 malformed OBJ line, W002 face
// index out of range, W003 mesh without faces.
std::optional<PolygonMesh> read_obj(std::istream& in, const std::string& source,
                                    knitout::DiagnosticSink& sink);
std::optional<PolygonMesh> read_obj_file(const std::string& path, knitout::DiagnosticSink& sink);
void write_obj(std::ostream& out, const std::vector<Vec3>& vertices,
               const std::vector<std::vector<int>>& faces);

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
