// The assembly guide (DESIGN.md, planner stage 6): how to put the knit pieces
// of a finished plan folder together.
//
// Reads the stage files of DIR through the stages' readers
// (planner/pipeline.hpp): the cut (read_cut: where the cut-arcs run through
// the proxy), their labels sew|lace (read_wearability, §5; without
// wearability.json the arcs are unlabelled), the stitch mesh
// (read_stitch_mesh: faces, and the cut-arc of every boundary side) and the
// schedule (read_schedule: every piece laid flat, the wale seams and the
// scheduler's cuts, §7.1, §7.3). Files that are missing, unreadable or made
// from another cut or stitch mesh are refused, saying which verb to run; the
// folder's summaries (report.json, cuts.json) are not read. It writes:
//   DIR/assembly.svg, DIR/assembly.pdf  the same pages: a cover page with the
//       legend and the order to close the seams, then every piece laid flat
//       as it comes off the machine (x = needle, y = row, in the gauge's
//       proportions), seams numbered at both sides, sew solid blue, lace
//       dashed red; several pieces per page, large pieces scaled to fit.
//   DIR/assembly-3d.png  the garment (the stitch mesh) on its wearer from four
//       sides, seams coloured sew / lace (no wearer when wearer_path is empty).
// A seam is one stretch of boundary that is joined to another stretch: a part
// of a cut-arc (split where the scheduler's pieces split it), a scheduler cut
// (the rows it separated), or a wale seam (rows knit in opposite directions,
// §7.1). Seams to sew are numbered first (scheduler cuts, wale seams, then the
// arcs labelled sew), the laced ones after them: they are closed once the
// garment is on the wearer. docs/assembly.md describes the pages.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace planner {

// What a guide holds, for the verb's summary line and for tests.
struct AssemblySummary {
  int pieces = 0;
  int seams = 0;  // numbered seams (each part drawn at its two stretches)
  int parts = 0;  // seams and parts of seams, each joining one stretch to one other
  int sewn = 0;   // seams 1..sewn are sewn, the rest laced
  int laced = 0;
  double sewn_mm = 0;   // total length of the sewn seams (each the mean of its two stretches)
  double laced_mm = 0;  // the same for the laced ones
  int arcs = 0;         // cut-arcs of the cut (every one is listed)
  int pdf_pages = 0;
};

// Writes the guide; returns "" or the failure as `PATH: error: [A0xx]
// message` (codes in docs/diagnostics.md). Nothing is written when the
// folder cannot be read; every file is written atomically. The wearer's
// coordinates are multiplied by `wearer_mm_per_unit`, by default the units
// and scale the folder's cut recorded for the garment.
std::string write_assembly_guide(const std::filesystem::path& plan_dir,
                                 const std::string& wearer_path, AssemblySummary* summary = nullptr,
                                 std::optional<double> wearer_mm_per_unit = std::nullopt);

// One page of the guide (1-based, as in the PDF) as a PNG picture, for
// previews and documentation; `pixels_per_point` 1 gives 842 x 595 pixels.
std::string write_assembly_page_png(const std::filesystem::path& plan_dir, int page,
                                    const std::string& png_path, double pixels_per_point = 1.5);

}  // namespace planner
