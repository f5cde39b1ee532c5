// The cut stage's output folder (docs/cutting.md has the full format):
//   proxy.obj      Q, the quad-dominant proxy (quads and triangles), in mm
//   cut-mesh.obj   the disc: Q's faces in the same order, vertices duplicated along cuts
//   cuts.json      the cut-arcs: edges as 0-based vertex index pairs of proxy.obj, length in mm
//   labels.json    per face: frame, vanishing corner, side directions, (u, v); per edge:
//   course|wale report.json    input size, proxy, irregular vertices, cut edges, arcs, cut length,
//   overlaps, time
// Later stages (wearability, stitch mesh) read it with read_cut_result.
#pragma once

#include <optional>
#include <string>

#include "knitout/diagnostic.hpp"
#include "planner/cut/cut.hpp"
#include "planner/proxy/proxy.hpp"

namespace planner {

// What the report says about the run besides the CutMesh itself.
struct CutReport {
  std::string input;
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
  std::string proxy_method = "input";
  std::string remesh_failure;
  CutParams params;
  double load_seconds = 0.0;
  double proxy_seconds = 0.0;
  double cut_seconds = 0.0;
};

// Writes proxy.obj, cut-mesh.obj, cuts.json, labels.json and report.json
// into `dir` (created if missing), each atomically. Returns an empty string,
// or a message naming the file that could not be written.
std::string write_cut_result(const std::string& dir, const CutMesh& cut, const CutReport& report);

// Reads a folder written by write_cut_result. Problems are diagnostics
// (P020 missing or unreadable file, P021 malformed JSON, P022 files that do
// not agree with each other) and give nullopt.
std::optional<CutMesh> read_cut_result(const std::string& dir, knitout::DiagnosticSink& sink);

}  // namespace planner
