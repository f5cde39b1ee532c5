// wearknit plan: garment + wearer -> the whole plan folder (Fig. 2), by
// planner::run_plan (planner/plan.hpp). Every stage's options are the ones
// its own verb takes (stage_options.hpp).
#include <cmath>
#include <filesystem>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/plan_display.hpp"
#include "apps/wearknit/stage_options.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/viewer/plan_page.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

void add_plan_options(po::options_description& options, PlanVerbOptions& v) {
  options.add_options()("garment", po::value<std::string>(&v.inputs.garment)->required(),
                        "garment surface (OBJ, OFF, PLY or STL)")(
      "wearer", po::value<std::string>(&v.inputs.wearer)->required(),
      "the rigid object that wears it (same formats and units as the garment)")(
      "output,o", po::value<std::string>(&v.dir)->required(), "write the plan folder here")(
      "seed", po::value<std::uint64_t>(&v.seed)->default_value(1),
      "seed of every stochastic stage (cut, wearability, schedule)")(
      "units", po::value<std::string>(&v.inputs.units)->default_value("mm"),
      "unit of both files' coordinates: mm, cm or m")(
      "scale", po::value<double>(&v.inputs.scale)->default_value(1.0),
      "multiply both files' coordinates by this")(
      "size-mm", po::value<double>(&v.inputs.size_mm),
      "instead of --scale: scale both so the garment's longest side is this many mm")(
      "send", po::value<std::string>(&v.run.send_uri),
      "send every piece's DAT to this machine as `wearknit send` does (tcp://, serial:, usb://, "
      "dir:PATH, loopback:)")("no-pictures", "draw no pictures (cut, stitch mesh)")(
      "restart",
      "wearability: ignore the tests of a plan cut short (kept in DIR/wearability.journal) and "
      "start again")("quiet,q", "no progress display and no summary");
  add_cut_options(options, v.cut);
  add_stitch_mesh_options(options, v.stitch);
  add_wearability_options(options, v.wear, "wear-trials");
  add_schedule_options(options, v.schedule);
  add_threads_option(options, v.threads);
}

int run_plan(const std::vector<std::string>& args, Context& context) {
  PlanVerbOptions v;
  planner::PlanInputs& inputs = v.inputs;
  std::string& dir = v.dir;
  std::uint64_t& seed = v.seed;
  int& threads = v.threads;
  PlanRunOptions& run = v.run;
  CutOptions& cut = v.cut;
  StitchMeshOptions& stitch = v.stitch;
  WearabilityOptions& wear = v.wear;
  ScheduleOptions& schedule = v.schedule;
  po::options_description options("options");
  add_plan_options(options, v);
  po::positional_options_description positional;
  positional.add("garment", 1);
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("plan"), options, positional, values, context)) {
    return *code;
  }
  // Every option is checked now rather than after the cut, beside a running
  // wearability test.
  std::string problem = check_schedule_options(values, schedule);
  if (problem.empty()) problem = check_cut_options(cut);
  if (problem.empty()) problem = check_stitch_mesh_options(values, stitch);
  if (problem.empty()) problem = check_wearability_options(values, wear);
  if (problem.empty() && !planner::mm_per_unit(inputs.units))
    problem = "--units takes mm, cm or m, not '" + inputs.units + "'";
  if (problem.empty() && values.count("size-mm") != 0) {
    if (!values["scale"].defaulted()) {
      problem = "give --scale or --size-mm, not both";
    } else if (!(inputs.size_mm > 0) || !std::isfinite(inputs.size_mm)) {
      problem = "--size-mm must be a positive number";
    }
  }
  if (problem.empty() && (!(inputs.scale > 0) || !std::isfinite(inputs.scale)))
    problem = "--scale must be a positive number";
  if (!problem.empty()) {
    context.err << "wearknit plan: " << problem << '\n';
    return kExitUsage;
  }
  planner::PlanParams params;
  params.cut = cut.params;
  params.cut.cut.seed = seed;
  params.stitch_mesh = stitch.params;
  params.wearability = wear.params;
  params.wearability.test.seed = seed;
  params.wearability.test.threads = threads;
  params.schedule = schedule.params;
  params.schedule.schedule.seed = seed;
  params.schedule.schedule.threads = threads;
  params.pictures = values.count("no-pictures") == 0;
  params.restart = values.count("restart") != 0;
  run.quiet = values.count("quiet") != 0;
  const int code = run_plan_and_report(inputs, params, dir, run, context);
  // The page shows whatever the plan wrote, also when a stage failed.
  if (!std::filesystem::is_directory(dir)) return code;
  planner::viewer::PlanPageSummary page;
  const std::string failure = planner::viewer::write_plan_page(dir, &page);
  if (!failure.empty()) {
    context.err << "wearknit plan: " << failure << '\n';
    return code == kExitOk ? kExitUsage : code;
  }
  if (!run.quiet) print_page_line(dir, page, context);
  return code;
}

}  // namespace wearknit::cli
