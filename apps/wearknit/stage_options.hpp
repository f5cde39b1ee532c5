// The options of each planner stage, shared by the stage's verb and by
// `wearknit plan`, which takes them under the same names (the wearability
// stage's --trials as --wear-trials, beside the scheduler's --trials).
// Each `add_*` registers the options into a description with their
// defaults; each `check_*` checks what was given and fills the stage's
// Params, returning "" or the problem (a usage error).
#pragma once

#include <boost/program_options.hpp>
#include <string>

#include "planner/pipeline.hpp"

namespace wearknit::cli {

struct CutOptions {
  planner::CutStageParams params;
  std::string vanishing = "acute";
  std::string proxy = "field";
  std::string growth = "auto";
  std::string tighten = "auto";
  double vanishing_slack_deg = 30.0;
};
void add_cut_options(boost::program_options::options_description& options, CutOptions& cut);
std::string check_cut_options(CutOptions& cut);

struct StitchMeshOptions {
  planner::StitchMeshStageParams params;
  std::string swatch = "40x40:42x115";
  std::string stitch_mm;
  std::string fine_features = "knit";
  std::string knit_direction = "best";
};
void add_stitch_mesh_options(boost::program_options::options_description& options,
                             StitchMeshOptions& stitch);
std::string check_stitch_mesh_options(const boost::program_options::variables_map& values,
                                      StitchMeshOptions& stitch);

struct WearabilityOptions {
  planner::WearabilityStageParams params;
  std::string arc_order;  // --arc-order, read into params by check_wearability_options
};
// `trials_name`: "trials" for the verb, "wear-trials" for the plan.
// --wearer-units and --wearer-scale (wearability, assembly): the wearer's
// file read like the garment of the cut folder unless they are given.
struct WearerUnitOptions {
  std::string units;
  double scale = 0;
};
void add_wearer_unit_options(boost::program_options::options_description& options,
                             WearerUnitOptions& wearer);
// Millimetres per unit of the wearer's file: the options given, else the
// units and scale the cut folder `dir` recorded. Sets `problem` (and
// returns 0) for units other than mm, cm or m or a scale that is not a
// positive number.
double wearer_mm_per_unit(const boost::program_options::variables_map& values,
                          const WearerUnitOptions& wearer, const std::string& dir,
                          std::string& problem);

void add_wearability_options(boost::program_options::options_description& options,
                             WearabilityOptions& wear, const char* trials_name);
std::string check_wearability_options(const boost::program_options::variables_map& values,
                                      WearabilityOptions& wear);

struct ScheduleOptions {
  planner::ScheduleStageParams params;
  std::string pattern = "plain";
  double time_budget_s = 0;
};
void add_schedule_options(boost::program_options::options_description& options,
                          ScheduleOptions& schedule);
std::string check_schedule_options(const boost::program_options::variables_map& values,
                                   ScheduleOptions& schedule);

// --threads for the stages that run trials in parallel (wearability, schedule).
void add_threads_option(boost::program_options::options_description& options, int& threads);

}  // namespace wearknit::cli
