// The whole planner pipeline on one garment and its wearer, as `wearknit
// plan` and `wearknit demo` run it (Fig. 2):
//
//   cut ──┬── wearability ───────────────────┐
//         └── stitch mesh ── schedule ───────┴── merge ── assembly guide ── [send]
//
// Each stage is its verb (run_cut, run_wearability, ...) called with an
// argument vector and a Context of its own, so a stage behaves exactly as it
// does on the command line. The two branches after the cut run on two
// threads. Both read-modify-write cuts.json and report.json, so each branch
// works in a staging copy of the cut folder (DIR/.plan-wear, DIR/.plan-knit)
// and the plan merges the branches' results into DIR when both are done.
// When the wearability stage re-cut the proxy (the garment with every cut
// open was not wearable, §5), the stitch-mesh branch worked on a stale cut and
// is run again on the new one.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "apps/wearknit/cli.hpp"

namespace wearknit::cli {

struct PlanOptions {
  std::string garment;     // any format `wearknit cut` reads
  std::string wearer;      // any format `wearknit cut` reads; scaled as the garment
  std::string dir;         // the plan folder (created)
  std::uint64_t seed = 1;  // every stochastic stage's seed
  // Unit options of `cut`: file coordinates * mm_per_unit(units) * scale;
  // size_mm > 0 instead scales the garment so its longest side is size_mm.
  std::string units = "mm";
  double scale = 1.0;
  double size_mm = 0.0;
  // Options handed to the stages as they are (name without "--", value);
  // the stage checks them.
  std::vector<std::string> cut_args;
  std::vector<std::string> wearability_args;
  std::vector<std::string> stitch_mesh_args;
  std::vector<std::string> schedule_args;
  std::string send_uri;  // empty: do not send
  bool pictures = true;
  bool quiet = false;  // no progress display and no summary
};

// Runs the pipeline into options.dir. Returns kExitOk; kExitInvalid when a
// stage failed (the message names the stage; DIR keeps the outputs of every
// stage that finished); kExitUsage on a bad option or an I/O error of the
// plan itself. Progress is shown on a terminal unless options.quiet.
int run_plan_pipeline(const PlanOptions& options, Context& context);

}  // namespace wearknit::cli
