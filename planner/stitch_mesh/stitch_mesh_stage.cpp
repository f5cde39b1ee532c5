#include "planner/stitch_mesh/stitch_mesh_stage.hpp"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <sstream>

#include "planner/common/index.hpp"
#include "planner/pipeline.hpp"

namespace planner {

namespace {

// Problems are many when a disc cannot be meshed; the first ones say why.
constexpr std::size_t kProblemsShown = 20;

// Fine features listed one by one; the rest are counted.
constexpr std::size_t kFineFeaturesShown = 10;

std::string point_text(const Vec3& p) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(1) << "(" << p.x() << ", " << p.y() << ", " << p.z()
       << ") mm";
  return text.str();
}

}  // namespace

FineFeatures fine_features(const Cut& cut, const StitchMeshStageParams& params) {
  FineFeatures found;
  found.stitch_mm = std::max(params.gauge.course_mm, params.gauge.wale_mm);
  found.bound_mm = params.min_girth_stitches * found.stitch_mm;
  found.size_mm = cut.report.input_size_mm.maxCoeff();
  if (cut.girth_mm.size() == at(cut.mesh.proxy.num_vertices()))
    found.parts = narrow_parts(cut.mesh.proxy.polygons(), cut.girth_mm, found.bound_mm);
  return found;
}

void report_fine_features(const FineFeatures& found, bool refused, const std::string& source,
                          knitout::DiagnosticSink& sink) {
  if (found.parts.empty()) return;
  const char* code = refused ? "P089" : "P088";
  auto say = [&](const std::string& text) {
    if (refused) {
      sink.error(source, 0, 0, code, text);
    } else {
      sink.warning(source, 0, 0, code, text);
    }
  };
  const std::size_t count = found.parts.size();
  for (std::size_t i = 0; i < count && i < kFineFeaturesShown; ++i) {
    const NarrowPart& part = found.parts[i];
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << "fine feature " << i + 1 << " of " << count
         << ": " << part.girth_mm << " mm round (" << part.girth_mm / found.stitch_mm
         << " stitches of " << std::setprecision(2) << found.stitch_mm << " mm; at least "
         << std::setprecision(1) << found.bound_mm << " mm are needed) at "
         << point_text(part.narrowest_at) << " (vertex " << part.narrowest_vertex + 1
         << " of proxy.obj)";
    if (part.vertices > 1)
      text << ", in a part of " << part.vertices << " vertices " << 2 * part.extent_mm
           << " mm across";
    say(text.str());
  }
  if (count > kFineFeaturesShown)
    say("... and " + std::to_string(count - kFineFeaturesShown) + " more fine features");
  // What knits the narrowest part at the bound: a larger garment or a
  // smaller stitch, by the same factor.
  const double girth = found.parts.front().girth_mm;
  std::ostringstream text;
  text << std::fixed << std::setprecision(1);
  if (refused) {
    text << "not knitted: ";
  } else {
    text << "knitted at the gauge's resolution: these parts come out blunter and thicker than "
            "the garment; ";
  }
  if (girth > 0) {
    const double factor = found.bound_mm / girth;
    text << "to knit them as they are, make the garment " << std::setprecision(2) << factor
         << " times larger";
    if (found.size_mm > 0)
      text << std::setprecision(0) << " (" << found.size_mm * factor
           << " mm along its longest side: plan --size-mm, cut --scale)";
    text << std::setprecision(2) << ", or use stitches at most " << found.stitch_mm / factor
         << " mm on their larger side (--swatch, --stitch-mm: a finer gauge)";
  } else {
    text << "parts with no measurable girth cannot be knitted as they are";
  }
  if (!refused) text << "; --fine-features refuse stops here instead";
  say(text.str());
}

std::optional<StitchMeshOutcome> mesh_stitches(const Cut& cut, const StitchMeshStageParams& params,
                                               const std::string& source,
                                               knitout::DiagnosticSink& sink) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t errors_before = sink.error_count();
  // Fine features are judged before meshing: refused, nothing is meshed.
  FineFeatures fine = fine_features(cut, params);
  report_fine_features(fine, params.refuse_fine_features, source, sink);
  if (sink.error_count() != errors_before) return std::nullopt;
  LabelledDisc disc = labelled_disc(cut.mesh);
  disc.surface = cut.surface;
  for (const std::string& p : check_disc(disc)) sink.error(source, 0, 0, "P085", p);
  if (sink.error_count() != errors_before) return std::nullopt;
  StitchMeshParams mesher = params.mesher;
  mesher.course_mm = params.gauge.course_mm;
  mesher.wale_mm = params.gauge.wale_mm;
  DirectedStitchMesh directed = make_directed_stitch_mesh(disc, mesher, params.direction);
  StitchMeshResult& result = directed.result;
  if (!result.problems.empty()) {
    // The cut mesh was read fine but could not be meshed into valid stitches.
    std::size_t shown = 0;
    for (const std::string& p : result.problems) {
      if (++shown > kProblemsShown) {
        sink.error(source, 0, 0, "P086",
                   "... and " + std::to_string(result.problems.size() - kProblemsShown) +
                       " more problems");
        break;
      }
      sink.error(source, 0, 0, "P086", "no valid stitch mesh: " + p);
    }
    // The rows depend on where the cuts run: another cut of the same
    // garment usually meshes.
    std::string change =
        "what to change: cut the garment again with another --seed (or at another size); the "
        "rows follow the cut, and another cut gives other rows";
    if (!fine.parts.empty()) {
      std::ostringstream text;
      text << std::fixed << std::setprecision(1) << "; the garment has " << fine.parts.size()
           << " fine features narrower than " << fine.bound_mm
           << " mm round (P088 above), where rows have little room: a larger size helps most";
      change += text.str();
    }
    sink.error(source, 0, 0, "P086", change);
    return std::nullopt;
  }
  StitchMeshOutcome outcome;
  outcome.cut_id = cut.id;
  StitchMeshReport& report = outcome.report;
  report.gauge = params.gauge;
  report.fine = std::move(fine);
  report.turned = directed.turned;
  report.compared = directed.compared;
  report.score_as_cut = directed.score_as_cut;
  report.score_turned = directed.score_turned;
  // Stitches more than a wale off the cut mesh span a gap of it
  // (docs/stitch-mesh.md, "Fans").
  report.off_surface = off_surface_faces(result.mesh, disc, params.gauge.wale_mm);
  if (!report.off_surface.faces.empty()) {
    std::ostringstream message;
    message << std::fixed << std::setprecision(1) << report.off_surface.faces.size()
            << " stitches have a side more than one wale (" << params.gauge.wale_mm
            << " mm) off the cut mesh's surface, up to " << report.off_surface.max_offset_mm
            << " mm (at the stitch of `f` line " << report.off_surface.farthest_face + 1
            << " of stitch-mesh.smobj): they span a gap of it, and the knitted piece will not "
               "take the surface's shape there (docs/stitch-mesh.md, \"Fans\")";
    sink.warning(source, 0, 0, "P087", message.str());
  }
  // The shape: how far the stitches lie from the garment (or the cut mesh).
  report.on_garment = !cut.surface.faces.empty();
  {
    PolygonMesh vertices;
    vertices.positions = result.mesh.positions;
    report.shape = distance_to_surface(vertices, report.on_garment ? cut.surface : cut.mesh.disc);
  }
  if (report.shape.max_mm > 0.5 * params.gauge.wale_mm) {
    std::ostringstream message;
    message << std::fixed << std::setprecision(2) << "stitch vertices lie up to "
            << report.shape.max_mm << " mm from the "
            << (report.on_garment ? "garment's surface"
                                  : "cut mesh (the cut folder has no surface.obj)")
            << ", more than half a wale (" << 0.5 * params.gauge.wale_mm
            << " mm): the knitted piece departs from the shape there";
    sink.warning(source, 0, 0, "P090", message.str());
  }
  report.figures = measure(result.mesh);
  report.stats = result.stats;
  report.stability = count_stability_rules(result.mesh);
  report.disc_area_mm2 = disc_area_mm2(disc);
  outcome.mesh = std::move(result.mesh);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return outcome;
}

std::string describe(const StitchMeshOutcome& outcome) {
  const StitchMeshFigures& f = outcome.report.figures;
  const StitchGauge& gauge = outcome.report.gauge;
  std::ostringstream text;
  text << std::fixed << std::setprecision(3) << "stitch mesh: " << f.faces << " stitches ("
       << f.knit << " knit, " << f.increase << " increase, " << f.decrease << " decrease, "
       << f.short_row << " short-row) in " << outcome.report.stats.rows << " rows; course "
       << f.course.mean_mm << " mm (target " << gauge.course_mm << "), wale " << f.wale.mean_mm
       << " mm (target " << gauge.wale_mm << "); " << std::setprecision(2) << outcome.report.seconds
       << " s\n";
  return text.str();
}

}  // namespace planner
