// `wearknit plan` and `wearknit demo` around planner::run_plan: the progress
// display, the summary, the failure report and sending the pieces.
#pragma once

#include <boost/program_options.hpp>
#include <cstdint>
#include <string>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/stage_options.hpp"
#include "planner/plan.hpp"

namespace wearknit::cli {

struct PlanRunOptions {
  std::string send_uri;  // empty: do not send
  bool quiet = false;    // no progress display and no summary
};

// Everything `wearknit plan` reads from its command line.
struct PlanVerbOptions {
  planner::PlanInputs inputs;
  std::string dir;
  std::uint64_t seed = 1;
  int threads = 0;
  PlanRunOptions run;
  CutOptions cut;
  StitchMeshOptions stitch;
  WearabilityOptions wear;
  ScheduleOptions schedule;
};

// The options of `wearknit plan`, bound to `v`; `wearknit batch` checks its
// manifest's columns against the same table.
void add_plan_options(boost::program_options::options_description& options, PlanVerbOptions& v);

// Runs the plan into `dir`. On a terminal (and without quiet) one status
// line is redrawn a few times a second and a line is printed as each stage
// ends; the summary follows. Returns kExitOk, or kExitInvalid when a stage
// failed (its messages are printed, and where the finished stages' outputs
// are), or kExitUsage for an I/O failure of the plan's own files.
int run_plan_and_report(const planner::PlanInputs& inputs, planner::PlanParams params,
                        const std::string& dir, const PlanRunOptions& options, Context& context);

}  // namespace wearknit::cli
