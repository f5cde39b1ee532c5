#include "planner/stitch_mesh/stitch_mesh_stage.hpp"

#include <chrono>
#include <iomanip>
#include <sstream>

#include "planner/pipeline.hpp"

namespace planner {

namespace {

// Problems are many when a disc cannot be meshed; the first ones say why.
constexpr std::size_t kProblemsShown = 20;

}  // namespace

std::optional<StitchMeshOutcome> mesh_stitches(const Cut& cut, const StitchMeshStageParams& params,
                                               const std::string& source,
                                               knitout::DiagnosticSink& sink) {
  const auto start = std::chrono::steady_clock::now();
  const LabelledDisc disc = labelled_disc(cut.mesh);
  const std::size_t errors_before = sink.error_count();
  for (const std::string& p : check_disc(disc)) sink.error(source, 0, 0, "P085", p);
  if (sink.error_count() != errors_before) return std::nullopt;
  StitchMeshParams mesher = params.mesher;
  mesher.course_mm = params.gauge.course_mm;
  mesher.wale_mm = params.gauge.wale_mm;
  StitchMeshResult result = make_stitch_mesh(disc, mesher);
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
    sink.error(source, 0, 0, "P086",
               "what to change: cut the garment again with another --seed (or at another size); "
               "the rows follow the cut, and another cut gives other rows");
    return std::nullopt;
  }
  StitchMeshOutcome outcome;
  outcome.cut_id = cut.id;
  StitchMeshReport& report = outcome.report;
  report.gauge = params.gauge;
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
