// The planner, stage by stage (DESIGN.md; paper "Wearable 3D Machine
// Knitting", section numbers below). Every stage is a free function from its
// inputs and its Params to its typed output, and every output has its file
// round trip in a plan folder (write_X / read_X), so a stage can run,
// be inspected and be tested alone; `wearknit VERB` runs one stage on a
// folder and `wearknit plan` runs them all (run_plan). docs/architecture.md
// has the stage -> function -> types -> files table, docs/plan.md the folder.
//
//   garment ─ cut_garment ─┬─ label_arcs (wearability) ──────────────────────┐
//   (mm)        (§4)       └─ mesh_stitches (§6) ─ schedule_stitches (§7) ──┴─ write_assembly_guide
//                                                                              (assembly)
//
// Errors: a stage reports bad input as diagnostics with a stable code
// (docs/diagnostics.md) in the sink it is given and returns nullopt; a
// broken invariant of the planner itself throws std::logic_error. Writers
// return an empty string or the failure, naming the file; every file is
// written atomically, so a stage that fails leaves the files of the stages
// that finished as they were.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "knitout/diagnostic.hpp"
#include "planner/assembly/assembly.hpp"
#include "planner/cut/cut_stage.hpp"
#include "planner/mesh/mesh.hpp"
#include "planner/schedule/schedule_stage.hpp"
#include "planner/stitch_mesh/stitch_mesh_stage.hpp"
#include "planner/wearability/wearability_stage.hpp"

namespace planner {

// ---- 1-2. Quad proxy and surface cutting (§4.1-4.2) ------------------------
// planner/cut/: cut_stage.hpp (Cut, CutStageParams), proxy/proxy.hpp,
// cut.hpp (CutMesh). Files: proxy.obj, cut-mesh.obj, labels.json, cut.json,
// cuts-3d.png, layout-2d.png (docs/cutting.md).

// The proxy of `garment` (a checked surface in mm, mesh/mesh_io.hpp
// load_mesh) cut into one disc. The report's input fields (file, units,
// scale, load time) are the caller's to fill.
Cut cut_garment(const PolygonMesh& garment, const CutStageParams& params);
// §5: the same proxy cut again with another seed.
Cut recut(const Cut& cut, std::uint64_t seed);
// `id`, when given, receives the id the files record (Cut::id on reading).
std::string write_cut(const std::string& dir, const Cut& cut, const CutPictures& pictures = {},
                      std::uint64_t* id = nullptr);
// P020 missing file, P021 malformed JSON, P022 files that disagree.
std::optional<Cut> read_cut(const std::string& dir, knitout::DiagnosticSink& sink);
// The units and scale the garment was read with, as the cut folder `dir`
// records them (cut.json, report.input): what a wearer given later is read
// with too, so that garment and wearer agree as `plan` makes them agree. mm
// and 1 for a folder that records none (a garment made by hand).
struct CutUnits {
  std::string units = "mm";
  double scale = 1.0;
};
CutUnits read_cut_units(const std::string& dir);

// ---- 3. Wearability (§5, §8.2) ---------------------------------------------
// planner/wearability/: wearability_stage.hpp (Wearability,
// WearabilityStageParams), wearability.hpp (the test and the elimination).
// Files: wearability.json, wearability.png; wearability.journal while it runs.

// Labels every cut-arc of `cut` sew or lace by stripping the garment off
// `wearer` (wearer_field) in simulation. When the garment with every cut
// open does not come off, the proxy is cut again (recut) up to
// params.recut_limit times; the result then holds the cut its labels
// belong to, for the caller to write (write_cut) before the labels.
Wearability label_arcs(const Cut& cut, const cloth::SignedDistanceField& wearer,
                       const WearabilityStageParams& params,
                       const WearabilityCallbacks& callbacks = {});
// `labelled_cut_id`: the id of the cut the labels belong to (the re-cut's,
// once written, when there is one).
std::string write_wearability(const std::string& dir, const Wearability& result,
                              std::uint64_t labelled_cut_id, bool picture = true);
// W020 codes and others: docs/diagnostics.md.
std::optional<WearabilityRecord> read_wearability(const std::string& dir,
                                                  knitout::DiagnosticSink& sink);

// ---- 4. Anisotropic stitch mesh (§6) ---------------------------------------
// planner/stitch_mesh/: stitch_mesh_stage.hpp (StitchMeshStageParams,
// StitchMeshOutcome), stitch_mesh.hpp (StitchMesh), stitch_mesher.hpp.
// Files: stitch-mesh.smobj, stitch-mesh.obj, stitch-mesh.png, stitch-mesh.json.

// P085 a disc the mesher cannot read, P086 no valid stitch mesh (errors);
// P087 stitches off the surface (warning).
std::optional<StitchMeshOutcome> mesh_stitches(const Cut& cut, const StitchMeshStageParams& params,
                                               const std::string& source,
                                               knitout::DiagnosticSink& sink);
std::string write_stitch_mesh(const std::string& dir, const StitchMeshOutcome& outcome,
                              bool picture = true);
// S900 no stitch-mesh.smobj, P081-P084 an unreadable one.
std::optional<StitchMeshFile> read_stitch_mesh(const std::string& dir,
                                               knitout::DiagnosticSink& sink);

// ---- 5. Flat-sheet schedule, tracing and knitout (§7) -----------------------
// planner/schedule/: schedule_stage.hpp (ScheduleStageParams,
// ScheduleOutcome), schedule.hpp (Schedule, §7.1-7.3), knitout_emit.hpp
// (§7.4-7.5). Every piece is run through the needle-bed VM and compiled to
// DAT before anything is written. Files: pieces/piece-N.{k,dat,svg,layout.json},
// schedule.json.

// S910 a stitch mesh the scheduler cannot read. A piece the VM or the DAT
// backend rejects is a bug of the scheduler: std::logic_error.
std::optional<ScheduleOutcome> schedule_stitches(const StitchMeshFile& stitches,
                                                 const ScheduleStageParams& params,
                                                 const std::string& source,
                                                 knitout::DiagnosticSink& sink);
std::string write_schedule(const std::string& dir, const ScheduleOutcome& outcome);
// S920 missing or malformed schedule files.
std::optional<ScheduleRecord> read_schedule(const std::string& dir, knitout::DiagnosticSink& sink);

// ---- 6. Assembly guide -------------------------------------------------------
// planner/assembly/assembly.hpp: reads the folder's cut, labels, stitch mesh
// and schedule files and writes assembly.svg, assembly.pdf, assembly-3d.png
// (write_assembly_guide). assembly.json holds the guide's figures:
std::string write_assembly_record(const std::string& dir, const AssemblySummary& summary);

// ---- The folder's summary ------------------------------------------------------
// report.json (every stage's figures) and cuts.json (the cut-arcs with their
// labels and the scheduler's cuts) are made from the stage files above each
// time a stage ends; no stage reads them. Returns "" or the failure.
std::string write_folder_summary(const std::string& dir);

}  // namespace planner
