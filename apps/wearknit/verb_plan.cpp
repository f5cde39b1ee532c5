// wearknit plan: garment + wearer -> the whole plan folder (Fig. 2), by
// running the stage verbs (plan_pipeline.hpp).
#include <cmath>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/plan_pipeline.hpp"
#include "planner/stitch_mesh/gauge.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

namespace {

// An option handed to a stage as it is: the plan's name, the stage's name.
struct Passed {
  const char* plan_name;
  const char* stage_name;
  const char* help;
};

}  // namespace

int run_plan(const std::vector<std::string>& args, Context& context) {
  PlanOptions plan;
  std::string pattern;
  po::options_description options("options");
  options.add_options()("garment", po::value<std::string>(&plan.garment)->required(),
                        "garment surface (OBJ, OFF, PLY or STL)")(
      "wearer", po::value<std::string>(&plan.wearer)->required(),
      "the rigid object that wears it (same formats and units as the garment)")(
      "output,o", po::value<std::string>(&plan.dir)->required(), "write the plan folder here")(
      "seed", po::value<std::uint64_t>(&plan.seed)->default_value(1),
      "seed of every stochastic stage (cut, wearability, schedule)")(
      "pattern", po::value<std::string>(&pattern)->default_value("plain"),
      "stitch pattern: plain or seed")("units",
                                       po::value<std::string>(&plan.units)->default_value("mm"),
                                       "unit of both files' coordinates: mm, cm or m")(
      "scale", po::value<double>(&plan.scale)->default_value(1.0),
      "multiply both files' coordinates by this")(
      "size-mm", po::value<double>(&plan.size_mm),
      "instead of --scale: scale both so the garment's longest side is this many mm")(
      "send", po::value<std::string>(&plan.send_uri),
      "send every piece's DAT to this machine as `wearknit send` does (tcp://, serial:, usb://, "
      "dir:PATH, loopback:)")("no-pictures", "draw no pictures (cut, stitch mesh)")(
      "quiet,q", "no progress display and no summary");
  static const std::vector<Passed> kCut = {
      {"cs", "cs", "cut: straightness weight c_s (default 1000)"},
      {"co", "co", "cut: overlap weight c_o (default 1)"},
      {"vanishing", "vanishing", "cut: vanishing corners, acute (§4.1) or regular (default acute)"},
      {"vanishing-slack", "vanishing-slack",
       "cut: degrees a regular vanishing corner may exceed the most acute (default 30)"},
      {"proxy-edge-mm", "proxy-edge-mm",
       "cut: proxy edge length for triangle input (default: "
       "about 3000 quads)"}};
  static const std::vector<Passed> kStitch = {
      {"gauge", "gauge", "stitch mesh: machine gauge, needles per inch (default 15)"},
      {"swatch", "swatch", "stitch mesh: measured swatch SxR:WxH_MM (default 40x40:42x115)"},
      {"stitch-mm", "stitch-mm",
       "stitch mesh: stitch size COURSExWALE in mm, instead of --swatch"}};
  static const std::vector<Passed> kWear = {
      {"wear-trials", "trials", "wearability: trials per test K (default 4)"},
      {"runs", "runs", "wearability: eliminations with different arc orders (default 1)"},
      {"max-steps", "max-steps", "wearability: steps before a trial fails (default 3000)"},
      {"resolution", "resolution", "wearability: distance-field cells along the wearer's side"},
      {"cloth-vertices", "cloth-vertices",
       "wearability: subdivide a coarser garment to this many vertices (default 500)"},
      {"recut-limit", "recut-limit",
       "wearability: re-cuts with other seeds when not wearable (default 3)"}};
  static const std::vector<Passed> kSchedule = {
      {"trials", "trials", "schedule: random knitting orders to try (default 100)"},
      {"time-budget", "time-budget", "schedule: seconds for orders instead of --trials"},
      {"improve", "improve", "schedule: best random orders refined by local search (default 8)"}};
  for (const auto* group : {&kCut, &kStitch, &kWear, &kSchedule}) {
    for (const Passed& p : *group)
      options.add_options()(p.plan_name, po::value<std::string>(), p.help);
  }
  options.add_options()("threads", po::value<std::string>(),
                        "wearability and schedule: threads (default 0: all cores)")(
      "one-at-a-time", "wearability: test each arc on its own (§5) instead of runs of arcs")(
      "restart",
      "wearability: ignore the tests of a plan cut short (kept in DIR/wearability.journal) and "
      "start again");
  po::positional_options_description positional;
  positional.add("garment", 1);
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("plan"), options, positional, values, context)) {
    return *code;
  }
  if (pattern != "plain" && pattern != "seed") {
    context.err << "wearknit plan: --pattern takes plain or seed, not '" << pattern << "'\n";
    return kExitUsage;
  }
  if (values.count("size-mm") != 0) {
    if (!values["scale"].defaulted()) {
      context.err << "wearknit plan: give --scale or --size-mm, not both\n";
      return kExitUsage;
    }
    if (!(plan.size_mm > 0) || !std::isfinite(plan.size_mm)) {
      context.err << "wearknit plan: --size-mm must be a positive number\n";
      return kExitUsage;
    }
  }
  // The gauge is checked now rather than after the cut, beside a running
  // wearability test.
  planner::StitchGauge gauge;
  std::string problem;
  if (values.count("swatch") && values.count("stitch-mm")) {
    problem = "give --swatch or --stitch-mm, not both";
  } else if (values.count("stitch-mm")) {
    problem = planner::parse_stitch_mm(values["stitch-mm"].as<std::string>(), gauge);
  } else if (values.count("swatch")) {
    problem = planner::parse_swatch(values["swatch"].as<std::string>(), gauge);
  }
  if (!problem.empty()) {
    context.err << "wearknit plan: " << problem << '\n';
    return kExitUsage;
  }
  if (values.count("trials") && values.count("time-budget")) {
    context.err << "wearknit plan: give --trials or --time-budget, not both\n";
    return kExitUsage;
  }

  auto pass = [&](const auto& group, std::vector<std::string>& to) {
    for (const Passed& p : group) {
      if (values.count(p.plan_name) == 0) continue;
      to.push_back(std::string("--") + p.stage_name);
      to.push_back(values[p.plan_name].as<std::string>());
    }
  };
  pass(kCut, plan.cut_args);
  pass(kStitch, plan.stitch_mesh_args);
  pass(kWear, plan.wearability_args);
  pass(kSchedule, plan.schedule_args);
  plan.schedule_args.insert(plan.schedule_args.end(), {"--pattern", pattern});
  if (values.count("threads")) {
    for (auto* to : {&plan.wearability_args, &plan.schedule_args}) {
      to->push_back("--threads");
      to->push_back(values["threads"].as<std::string>());
    }
  }
  if (values.count("one-at-a-time")) plan.wearability_args.push_back("--one-at-a-time");
  if (values.count("restart")) plan.wearability_args.push_back("--restart");
  plan.pictures = values.count("no-pictures") == 0;
  plan.quiet = values.count("quiet") != 0;
  return run_plan_pipeline(plan, context);
}

}  // namespace wearknit::cli
