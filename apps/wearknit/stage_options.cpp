#include "apps/wearknit/stage_options.hpp"

#include <cmath>
#include <optional>

#include "planner/mesh/mesh_io.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

void add_cut_options(po::options_description& options, CutOptions& cut) {
  planner::CutParams& p = cut.params.cut;
  options.add_options()("cs", po::value<double>(&p.cs)->default_value(1000.0),
                        "straightness weight c_s (motorcycle-graph edges, §4.2)")(
      "co", po::value<double>(&p.co)->default_value(1.0), "overlap weight c_o (§4.2)")(
      "vanishing", po::value<std::string>(&cut.vanishing)->default_value("acute"),
      "vanishing corner of each triangle: optimal (the corners that leave the fewest corners "
      "off four around interior vertices, the most acute among those), acute (its most acute "
      "corner, §4.1) or regular (a corner within --vanishing-slack of it that leaves fewer "
      "irregular vertices)")(
      "vanishing-slack", po::value<double>(&cut.vanishing_slack_deg)->default_value(30.0),
      "degrees a regular vanishing corner may be wider than the most acute one")(
      "proxy-edge-mm", po::value<double>(&cut.params.proxy.proxy_edge_mm)->default_value(0.0),
      "edge length of the remeshed proxy for triangle input (0: about 3000 quads)")(
      "proxy", po::value<std::string>(&cut.proxy)->default_value(cut.proxy),
      "proxy of a surface that is not quad-dominant: field (triangles whose vanishing corners "
      "follow the smoothest cross field; it also replaces a quad-dominant input that carries "
      "avoidable singularities) or remesh (field-aligned quads, §4.1, a quad-dominant input "
      "kept as it is)")(
      "growth", po::value<std::string>(&cut.growth)->default_value(cut.growth),
      "order of equal cuttability scores: random (§4.2), square (the ring nearest the seed "
      "first) or auto (square with --proxy field, random with remesh)")(
      "arc-turn", po::value<double>(&p.arc_turn_deg)->default_value(p.arc_turn_deg),
      "a cut-arc ends where the cut turns by more than this many degrees")(
      "tighten", po::value<std::string>(&cut.tighten)->default_value(cut.tighten),
      "on: replace each stretch of the grown cut by the shortest one (along the labels where "
      "that is nearly as short) that still opens the surface into a disc, and move branch "
      "points onto the vertices the cut must reach; off: the cut as the patch growing leaves "
      "it (§4.2); auto: on with --proxy field, off with remesh");
}

std::string check_cut_options(CutOptions& cut) {
  planner::CutParams& p = cut.params.cut;
  if (!(cut.params.proxy.proxy_edge_mm >= 0.0) || !(p.cs >= 0.0) || !(p.co >= 0.0))
    return "--proxy-edge-mm, --cs and --co must not be negative";
  const auto method = planner::vanishing_method(cut.vanishing);
  if (!method) return "--vanishing takes optimal, acute or regular, not '" + cut.vanishing + "'";
  if (!(cut.vanishing_slack_deg >= 0.0) || cut.vanishing_slack_deg > 180.0)
    return "--vanishing-slack must be between 0 and 180 degrees";
  p.vanishing.method = *method;
  p.vanishing.slack_deg = cut.vanishing_slack_deg;
  const auto proxy = planner::proxy_method(cut.proxy);
  if (!proxy) return "--proxy takes field or remesh, not '" + cut.proxy + "'";
  cut.params.proxy.method = *proxy;
  if (cut.growth != "random" && cut.growth != "square" && cut.growth != "auto")
    return "--growth takes auto, random or square, not '" + cut.growth + "'";
  const bool field = cut.params.proxy.method == planner::ProxyMethod::Field;
  p.square_growth = cut.growth == "square" || (cut.growth == "auto" && field);
  if (cut.tighten != "on" && cut.tighten != "off" && cut.tighten != "auto")
    return "--tighten takes auto, on or off, not '" + cut.tighten + "'";
  p.tighten = cut.tighten == "on" || (cut.tighten == "auto" && field);
  if (!(p.arc_turn_deg >= 0.0) || p.arc_turn_deg > 180.0)
    return "--arc-turn must be between 0 and 180 degrees";
  return {};
}

void add_stitch_mesh_options(po::options_description& options, StitchMeshOptions& stitch) {
  planner::StitchMeshParams& p = stitch.params.mesher;
  options.add_options()(
      "gauge", po::value<double>(&stitch.params.gauge.needles_per_inch)->default_value(15.0),
      "machine gauge, needles per inch")(
      "swatch", po::value<std::string>(&stitch.swatch)->default_value(stitch.swatch),
      "measured swatch STITCHESxROWS:WIDTHxHEIGHT_MM (the paper's seed swatch, §8.1)")(
      "stitch-mm", po::value<std::string>(&stitch.stitch_mm),
      "stitch size COURSExWALE in mm, instead of --swatch")(
      "min-girth", po::value<double>(&stitch.params.min_girth_stitches)->default_value(3.0),
      "fine features are parts of the garment less than this many stitches (of the larger "
      "stitch side) round")(
      "fine-features", po::value<std::string>(&stitch.fine_features)->default_value("knit"),
      "knit: knit fine features at the gauge's resolution, with a warning (P088); refuse: stop "
      "with their list and a size or stitch that would knit them (P089)")(
      "straighten", po::value<int>(&p.straighten_iterations)->default_value(100),
      "at most this many fits of the row time towards unit row height after the fit to the "
      "labels; they stop once the row time moves less than 0.01 row")(
      "label-weight", po::value<double>(&p.label_weight)->default_value(0.1),
      "weight of the labelled wale direction in each straightening fit")(
      "pentagon-cost", po::value<double>(&p.pentagon_cost)->default_value(0.05),
      "cost of an increase or decrease against a wale side's squared relative length error")(
      "stability-cost", po::value<double>(&p.stability_cost)->default_value(1.0),
      "cost of breaking a Fig. 7 rule of thumb (docs/stitch-mesh.md); 0 ignores them")(
      "outside-cost", po::value<double>(&p.outside_cost)->default_value(0.05),
      "extra cost of a wale side more than 15% off its target length")(
      "row-end-wales", po::value<double>(&p.tip_side_wales)->default_value(0.9),
      "a row that meets an oblique boundary in a point ends in a wale side this many wales "
      "long instead; 0 keeps the point")(
      "knit-direction", po::value<std::string>(&stitch.knit_direction)->default_value("best"),
      "which of the cut's two field directions the rows run along: as-cut (its course sides), "
      "turned (its wale sides) or best (mesh both, keep the one with more sides of the stitch "
      "size)")(
      "saddle-wales", po::value<double>(&p.saddle_wales)->default_value(5.0),
      "hold the row time's saddles where rows would go round them on a level, moving the rows "
      "within this many wales of each; 0 leaves them")(
      "relax", po::value<int>(&p.relax_sweeps)->default_value(150),
      "at most this many sweeps moving the inner stitch vertices over the surface towards "
      "their sides' target lengths; 0 keeps them as zipped");
}

std::string check_stitch_mesh_options(const po::variables_map& values, StitchMeshOptions& stitch) {
  planner::StitchGauge& gauge = stitch.params.gauge;
  std::string problem;
  if (values.count("stitch-mm") != 0) {
    if (!values["swatch"].defaulted()) return "give --swatch or --stitch-mm, not both";
    problem = planner::parse_stitch_mm(stitch.stitch_mm, gauge);
  } else {
    problem = planner::parse_swatch(stitch.swatch, gauge);
  }
  if (problem.empty()) problem = planner::check_gauge(gauge);
  if (problem.empty() && stitch.fine_features != "knit" && stitch.fine_features != "refuse")
    problem = "--fine-features takes knit or refuse, not '" + stitch.fine_features + "'";
  if (problem.empty() && !(stitch.params.min_girth_stitches >= 0.0))
    problem = "--min-girth must not be negative";
  stitch.params.refuse_fine_features = stitch.fine_features == "refuse";
  if (const auto direction = planner::parse_knit_direction(stitch.knit_direction)) {
    stitch.params.direction = *direction;
  } else if (problem.empty()) {
    problem = "--knit-direction takes best, as-cut or turned, not '" + stitch.knit_direction + "'";
  }
  const planner::StitchMeshParams& p = stitch.params.mesher;
  if (problem.empty() &&
      (p.straighten_iterations < 0 || !(p.label_weight >= 0) || !(p.pentagon_cost >= 0) ||
       !(p.stability_cost >= 0) || !(p.outside_cost >= 0) || !(p.tip_side_wales >= 0) ||
       p.relax_sweeps < 0 || !(p.saddle_wales >= 0))) {
    problem =
        "--straighten, --label-weight, --pentagon-cost, --stability-cost, --outside-cost, "
        "--row-end-wales, --saddle-wales and --relax must not be negative";
  }
  return problem;
}

void add_wearability_options(po::options_description& options, WearabilityOptions& wear,
                             const char* trials_name) {
  planner::WearabilityStageParams& p = wear.params;
  options.add_options()(trials_name, po::value<int>(&p.test.trials)->default_value(p.test.trials),
                        "wearability: K trials per test, each with its own global-force "
                        "directions")(
      "runs", po::value<int>(&p.runs)->default_value(1),
      "wearability: R eliminations with different arc orders (probability of lacing, Fig. 18; "
      "the runs after the first take random orders)")(
      "recut-limit", po::value<int>(&p.recut_limit)->default_value(p.recut_limit),
      "wearability: re-cuts with other seeds when the garment with every cut open is not "
      "wearable (§5)")(
      "max-steps", po::value<int>(&p.test.cloth.max_steps)->default_value(p.test.cloth.max_steps),
      "wearability: steps before a trial counts as failed")(
      "resolution", po::value<int>(&p.sdf_resolution)->default_value(p.sdf_resolution),
      "wearability: distance-field cells along the wearer's longest side")(
      "check-trials", po::value<int>(&p.check_trials)->default_value(p.check_trials),
      "wearability: M trials of the final check: the labelled garment must come off in every "
      "one, at a finer cloth and with new seeds, else more arcs are laced (0 = no check)")(
      "cloth-vertices", po::value<int>(&p.cloth_vertices)->default_value(p.cloth_vertices),
      "wearability: subdivide a garment with fewer vertices until it has this many, so it can "
      "bend around the wearer (0 = never)")(
      "cloth-max-vertices",
      po::value<int>(&p.cloth_max_vertices)->default_value(p.cloth_max_vertices),
      "wearability: simplify a garment with more vertices to about this many for the "
      "elimination, every cut-arc kept (0 = never); the final check runs on a finer cloth")(
      "one-at-a-time",
      "wearability: test each arc on its own, as §5 does, instead of closing runs of arcs "
      "together while the garment keeps coming off")(
      "simulate-linked",
      "wearability: simulate every test, also of a garment with a curve linked around a "
      "handle of the wearer, which cannot come off (by default such a test fails without "
      "a simulation)")(
      "arc-order", po::value<std::string>(&wear.arc_order)->default_value("opening"),
      "wearability: the order the elimination takes the arcs in: opening (those whose sides "
      "parted least as the garment came off with every cut open first) or random (§5)");
}

void add_wearer_unit_options(po::options_description& options, WearerUnitOptions& wearer) {
  options.add_options()("wearer-units", po::value<std::string>(&wearer.units),
                        "units of the wearer's file: mm, cm or m (default: the garment's, as "
                        "the cut folder records them)")(
      "wearer-scale", po::value<double>(&wearer.scale),
      "factor on the wearer's coordinates (default: the garment's --scale, as the cut folder "
      "records it)");
}

double wearer_mm_per_unit(const po::variables_map& values, const WearerUnitOptions& wearer,
                          const std::string& dir, std::string& problem) {
  // As the garment: its units and scale are the cut folder's unless given
  // (`plan` reads both the same way).
  planner::CutUnits units = planner::read_cut_units(dir);
  if (values.count("wearer-units")) units.units = wearer.units;
  if (values.count("wearer-scale")) units.scale = wearer.scale;
  const std::optional<double> mm = planner::mm_per_unit(units.units);
  if (!mm) {
    problem = "--wearer-units takes mm, cm or m, not '" + units.units + "'";
    return 0;
  }
  if (!(units.scale > 0) || !std::isfinite(units.scale)) {
    problem = "--wearer-scale must be a positive number";
    return 0;
  }
  return *mm * units.scale;
}

std::string check_wearability_options(const po::variables_map& values, WearabilityOptions& wear) {
  const planner::WearabilityStageParams& p = wear.params;
  if (p.test.trials < 1 || p.runs < 1 || p.test.cloth.max_steps < 1 || p.sdf_resolution < 8 ||
      p.recut_limit < 0 || p.cloth_vertices < 0 || p.cloth_max_vertices < 0 || p.check_trials < 0) {
    return "the trials, --runs and --max-steps must be positive, --recut-limit, "
           "--check-trials, --cloth-vertices and --cloth-max-vertices not negative, "
           "--resolution at least 8";
  }
  wear.params.test.group_testing = values.count("one-at-a-time") == 0;
  wear.params.test.linking = values.count("simulate-linked") == 0;
  if (wear.arc_order == "opening") {
    wear.params.test.order = planner::ArcOrder::Opening;
  } else if (wear.arc_order == "random") {
    wear.params.test.order = planner::ArcOrder::Random;
  } else {
    return "--arc-order takes opening or random, not '" + wear.arc_order + "'";
  }
  return {};
}

void add_schedule_options(po::options_description& options, ScheduleOptions& schedule) {
  planner::ScheduleParams& p = schedule.params.schedule;
  options.add_options()("trials", po::value<int>(&p.trials)->default_value(p.trials),
                        "schedule: random knitting orders to try (§7.3)")(
      "time-budget", po::value<double>(&schedule.time_budget_s),
      "schedule: seconds to spend trying orders instead of a number of trials")(
      "pattern", po::value<std::string>(&schedule.pattern)->default_value("plain"),
      "stitch pattern: plain or seed")(
      "max-shift", po::value<int>(&p.max_patch_shift)->default_value(planner::kMaxPatchShift),
      "schedule: needles a patch may be moved sideways to clear held loops (0 to 8)")(
      "max-aside", po::value<int>(&p.max_aside)->default_value(planner::kMaxAside),
      "schedule: needles loops held for a later row may be moved out of a patch's way (0 to 8)")(
      "improve", po::value<int>(&p.improve)->default_value(p.improve),
      "schedule: best random orders refined by a local search that moves the patches of each "
      "cut (0: random orders only, as in §7.3)");
}

std::string check_schedule_options(const po::variables_map& values, ScheduleOptions& schedule) {
  planner::ScheduleParams& p = schedule.params.schedule;
  const bool budget = values.count("time-budget") != 0;
  if (budget && !values["trials"].defaulted()) return "give --trials or --time-budget, not both";
  if (budget && !(schedule.time_budget_s > 0)) return "--time-budget must be more than 0 seconds";
  if (p.trials < 1) return "--trials must be at least 1";
  if (p.improve < 0) return "--improve must not be negative";
  if (p.max_patch_shift < 0 || p.max_patch_shift > 8)
    return "--max-shift takes 0 to 8 (the racking limit)";
  if (p.max_aside < 0 || p.max_aside > 8) return "--max-aside takes 0 to 8 (the racking limit)";
  p.time_budget_s = budget ? schedule.time_budget_s : 0;
  if (schedule.pattern == "seed") {
    schedule.params.emit.pattern = planner::StitchPattern::Seed;
  } else if (schedule.pattern != "plain") {
    return "--pattern takes plain or seed, not '" + schedule.pattern + "'";
  }
  return {};
}

void add_threads_option(po::options_description& options, int& threads) {
  options.add_options()("threads", po::value<int>(&threads)->default_value(0),
                        "threads for the trials (0: all cores); results depend only on the seed");
}

}  // namespace wearknit::cli
