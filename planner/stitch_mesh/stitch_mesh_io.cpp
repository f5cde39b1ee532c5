#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "knitout/output_file.hpp"
#include "planner/common/hash.hpp"
#include "planner/common/index.hpp"
#include "planner/common/json_file.hpp"
#include "planner/pipeline.hpp"
#include "planner/stitch_mesh/stitch_mesh_picture.hpp"

namespace planner {

LabelledDisc labelled_disc(const CutMesh& cut) {
  LabelledDisc disc;
  disc.positions = cut.disc.positions;
  disc.faces = cut.disc.faces;
  std::map<std::pair<int, int>, std::int32_t> arc_of_edge;  // proxy vertices, sorted
  for (std::size_t a = 0; a < cut.arcs.size(); ++a) {
    const std::vector<int>& path = cut.arcs[a].vertices;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      arc_of_edge[{std::min(path[i], path[i + 1]), std::max(path[i], path[i + 1])}] =
          static_cast<std::int32_t>(a);
    }
  }
  // Boundary sides of the disc: directed sides with no reverse.
  std::map<std::pair<int, int>, int> directed;
  for (const std::vector<int>& face : disc.faces) {
    for (std::size_t i = 0; i < face.size(); ++i)
      ++directed[{face[i], face[(i + 1) % face.size()]}];
  }
  for (std::size_t f = 0; f < disc.faces.size(); ++f) {
    const std::vector<int>& face = disc.faces[f];
    std::vector<int> dir;
    std::vector<std::int32_t> arcs;
    const int start = cut.proxy.face_start(static_cast<int>(f));
    for (std::size_t i = 0; i < face.size(); ++i) {
      dir.push_back(cut.direction[at(start + static_cast<int>(i))]);
      const int a = face[i];
      const int b = face[(i + 1) % face.size()];
      std::int32_t arc = kNoArc;
      if (directed.find({b, a}) == directed.end()) {
        const int qa = cut.disc_source[at(a)];
        const int qb = cut.disc_source[at(b)];
        auto it = arc_of_edge.find({std::min(qa, qb), std::max(qa, qb)});
        if (it != arc_of_edge.end()) arc = it->second;
      }
      arcs.push_back(arc);
    }
    disc.directions.push_back(std::move(dir));
    disc.arcs.push_back(std::move(arcs));
  }
  return disc;
}

void write_stitch_obj(std::ostream& out, const StitchMesh& mesh) {
  std::ostringstream text;
  text << std::setprecision(10);
  text << "# stitch mesh (wearknit, paper §6), mm; course " << mesh.course_mm << " wale "
       << mesh.wale_mm << "\n";
  for (const Eigen::Vector3d& p : mesh.positions) {
    text << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  }
  for (const StitchFace& face : mesh.faces) {
    text << "f";
    for (std::uint32_t v : face.vertices) text << " " << v + 1;
    text << "\n";
  }
  for (const StitchFace& face : mesh.faces) text << "# type " << face_type_name(face.type) << "\n";
  out << text.str();
}

namespace {

namespace fs = std::filesystem;

using nlohmann::json;

// Which way the rows run, and with --knit-direction best how both ways
// scored (stitch_mesh_score).
json direction_json(const StitchMeshReport& report) {
  json d = {{"rows_along", report.turned ? "the cut's wale sides" : "the cut's course sides"},
            {"turned", report.turned}};
  if (report.compared)
    d["scores"] = {{"as_cut", report.score_as_cut}, {"turned", report.score_turned}};
  return d;
}

json lengths_json(const EdgeLengthStats& s, double target) {
  return {{"count", s.count},   {"target_mm", target}, {"mean_mm", s.mean_mm},
          {"min_mm", s.min_mm}, {"max_mm", s.max_mm},  {"within_15_percent", s.within_15_percent}};
}

nlohmann::json fine_features_json(const FineFeatures& fine) {
  nlohmann::json parts = nlohmann::json::array();
  for (const NarrowPart& part : fine.parts) {
    parts.push_back(
        {{"girth_mm", part.girth_mm},
         {"at_mm", {part.narrowest_at.x(), part.narrowest_at.y(), part.narrowest_at.z()}},
         {"proxy_vertex", part.narrowest_vertex},
         {"vertices", part.vertices},
         {"across_mm", 2 * part.extent_mm}});
  }
  return {{"bound_mm", fine.bound_mm}, {"stitch_mm", fine.stitch_mm}, {"parts", parts}};
}

nlohmann::json report_json(const StitchMeshReport& report) {
  const StitchMeshFigures& f = report.figures;
  const double stitch_area = report.gauge.course_mm * report.gauge.wale_mm;
  return {{"gauge",
           {{"needles_per_inch", report.gauge.needles_per_inch},
            {"course_mm", report.gauge.course_mm},
            {"wale_mm", report.gauge.wale_mm},
            {"from", report.gauge.source}}},
          {"faces",
           {{"total", f.faces},
            {"knit", f.knit},
            {"increase", f.increase},
            {"decrease", f.decrease},
            {"short_row", f.short_row}}},
          {"vertices", f.vertices},
          {"rows", report.stats.rows},
          {"strips", report.stats.strips},
          {"course_edges", lengths_json(f.course, report.gauge.course_mm)},
          {"wale_edges", lengths_json(f.wale, report.gauge.wale_mm)},
          {"cut_mesh_area_mm2", report.disc_area_mm2},
          {"expected_stitches", stitch_area > 0 ? report.disc_area_mm2 / stitch_area : 0.0},
          {"stability_rules",
           {{"edge_shaping", report.stability.edge_shaping},
            {"stacked_shaping", report.stability.stacked_shaping},
            {"opposed_shaping", report.stability.opposed_shaping},
            {"one_stitch_rows", report.stability.one_stitch_rows}}},
          {"saddles_split", report.stats.saddles_split},
          {"saddles_pinned", report.stats.saddles_pinned},
          {"lenses_glued", report.stats.lenses_skipped},
          {"bind_off_sides", report.stats.boundary_sides},
          {"sides_split_below", report.stats.sides_split_below},
          {"straighten_fits", report.stats.straighten_fits},
          {"label_deviation_deg", report.stats.label_deviation_deg},
          {"knit_direction", direction_json(report)},
          {"row_time_levelled", report.stats.row_time_levelled},
          {"row_time_drained", report.stats.row_time_drained},
          {"tip_sides", report.stats.tip_sides},
          {"relax_sweeps", report.stats.relax_sweeps},
          {"relax_seconds", report.stats.relax_seconds},
          {"off_surface",
           {{"faces", report.off_surface.faces.size()},
            {"max_offset_mm", report.off_surface.max_offset_mm},
            {"tolerance_mm", report.off_surface.tolerance_mm}}},
          {"surface_distance",
           {{"max_mm", report.shape.max_mm},
            {"mean_mm", report.shape.mean_mm},
            {"against", report.on_garment ? "garment" : "cut mesh"}}},
          {"fine_features", fine_features_json(report.fine)},
          {"boundary_loops", f.boundary_loops},
          {"euler_characteristic", f.euler_characteristic},
          {"remesh_seconds", report.stats.total_seconds},
          {"seconds", report.seconds}};
}

}  // namespace

std::string write_stitch_mesh(const std::string& dir, const StitchMeshOutcome& outcome,
                              bool picture) {
  const fs::path base(dir);
  std::ostringstream smobj;
  write_smobj(smobj, outcome.mesh);
  const std::string smobj_text = smobj.str();
  std::string failure = knitout::write_file_atomically(
      (base / "stitch-mesh.smobj").string(), [&](std::ostream& out) { out << smobj_text; });
  if (failure.empty()) {
    failure = knitout::write_file_atomically(
        (base / "stitch-mesh.obj").string(),
        [&](std::ostream& out) { write_stitch_obj(out, outcome.mesh); });
  }
  if (failure.empty() && picture)
    failure = draw_stitch_mesh(outcome.mesh, (base / "stitch-mesh.png").string());
  if (failure.empty()) {
    failure = write_json_file((base / "stitch-mesh.json").string(),
                              {{"format", "wearknit-stitch-mesh 1"},
                               {"cut_id", hex64(outcome.cut_id)},
                               {"stitch_mesh_id", hex64(fingerprint(smobj_text))},
                               {"report", report_json(outcome.report)}});
  }
  return failure;
}

std::optional<StitchMeshFile> read_stitch_mesh(const std::string& dir,
                                               knitout::DiagnosticSink& sink) {
  const fs::path base(dir);
  const std::string smobj = (base / "stitch-mesh.smobj").string();
  std::ifstream in(smobj, std::ios::binary);
  if (!in) {
    sink.error(smobj, 0, 0, "S900", "cannot open the stitch mesh (run wearknit stitch-mesh)");
    return std::nullopt;
  }
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream text(bytes);
  auto mesh = parse_smobj(text, smobj, sink);
  if (!mesh) return std::nullopt;
  StitchMeshFile file;
  file.mesh = std::move(*mesh);
  file.id = fingerprint(bytes);
  // The cut it was made from, when the stitch-mesh stage wrote it.
  if (const auto json = read_json_object_if_any((base / "stitch-mesh.json").string())) {
    parse_hex64(json->value("cut_id", std::string()), file.cut_id);
  }
  return file;
}

}  // namespace planner
