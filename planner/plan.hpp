// The whole planner on one garment and its wearer, into a plan folder, as
// `wearknit plan` and `wearknit demo` run it (Fig. 2):
//
//   cut ──┬── wearability ─────────────────────┐
//         └── stitch mesh ── schedule ─────────┴── assembly guide
//
// Each stage is its function of planner/pipeline.hpp, and each writes its
// own files as it ends. The two branches after the cut run on two threads
// (the paper runs its wearability test concurrently with stitch meshing and
// scheduling). Every stage reads what its predecessor's files hold (written,
// then read back), exactly what the stage's verb reads from the folder, so a
// plan gives the same files as the verbs run one after the other. When the
// wearability stage cut the proxy again (§5), the stitch mesh and schedule
// are made again from the new cut.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "knitout/diagnostic.hpp"
#include "planner/pipeline.hpp"

namespace planner {

struct PlanInputs {
  std::string garment;  // any format the mesh reader takes (OBJ, OFF, PLY, STL)
  std::string wearer;   // the same, in the garment's units
  // File coordinates * millimetres per unit * scale; size_mm > 0 instead
  // scales both so the garment's longest side is size_mm.
  std::string units = "mm";
  double scale = 1.0;
  double size_mm = 0.0;
};

// One stage as the plan ran it.
struct StageRun {
  std::string name;    // "cut", "wearability", "stitch-mesh", "schedule", "assembly"
  std::string branch;  // "main", "wear" or "knit"
  // 0 done; 1 the input is invalid (diagnostics say why); 2 an I/O failure
  // or an internal error (text says which).
  int exit_code = -1;
  double seconds = 0;
  std::string out;  // what its verb prints on success
  std::string err;  // diagnostics and failures, one per line
};

struct PlanParams {
  CutStageParams cut;
  WearabilityStageParams wearability;
  StitchMeshStageParams stitch_mesh;
  ScheduleStageParams schedule;
  bool pictures = true;
  bool restart = false;  // ignore the tests a plan cut short kept (wearability.journal)
  // An optional last stage, "send", once every other stage ended well: it
  // gets each piece's DAT (paths, in knitting order), fills its run, returns
  // its exit code and lists what it did in `sent` (recorded in plan.json).
  std::function<int(const std::vector<std::string>& dat_paths, StageRun& run, nlohmann::json& sent)>
      deliver;
};

// Told as the plan runs; called from the plan's two threads, never at once.
class PlanObserver {
 public:
  virtual ~PlanObserver() = default;
  virtual void stage_started(const std::string& /*name*/, const std::string& /*branch*/) {}
  virtual void stage_finished(const StageRun& /*run*/) {}
  virtual void wearability_progress(const Progress& /*progress*/) {}
};

struct PlanResult {
  std::vector<StageRun> stages;  // in the order they started
  bool ok() const;               // every stage that ran ended with 0
  double scale = 1.0;            // the scale the garment and wearer were read at
  bool recut = false;            // the wearability stage cut the proxy again
  double total_seconds = 0;
  // Each piece's DAT, relative to the folder, in knitting order (empty
  // unless every stage ended well).
  std::vector<std::string> dat_files;
  // plan.json's "plan" member: inputs, stages, the figures that sum up the
  // result (report.json holds it too).
  nlohmann::json record;
};

// Runs the pipeline into `dir` (created). Stages that fail leave the files
// of the stages that finished; plan.json, plan.log, report.json and
// cuts.json are written in any case (plan.log: everything each stage
// printed). A plan cut short and run again resumes its wearability stage
// from DIR/wearability.journal unless params.restart.
PlanResult run_plan(const PlanInputs& inputs, const PlanParams& params, const std::string& dir,
                    PlanObserver& observer);

// The plan's closing line: "N pieces, S stitches, s seams sewn (X mm), l
// laced (Y mm), P passes, about M min on the machine", the seams as the
// assembly guide numbers them; "a arcs sewn, l laced" instead when the
// folder has no guide.
std::string describe(const PlanResult& result);

}  // namespace planner
