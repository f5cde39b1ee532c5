// wearknit stitch-mesh: cut folder -> anisotropic stitch mesh (§6).
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "apps/wearknit/cli.hpp"
#include "knitout/output_file.hpp"
#include "planner/cut/cut_io.hpp"
#include "planner/stitch_mesh/gauge.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "planner/stitch_mesh/stitch_mesh_io.hpp"
#include "planner/stitch_mesh/stitch_mesh_picture.hpp"
#include "planner/stitch_mesh/stitch_mesher.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_stitch_mesh(const std::vector<std::string>& args, Context& context) {
  std::string dir;
  std::string swatch;
  std::string stitch_mm;
  std::string format_name;
  planner::StitchGauge gauge;
  planner::StitchMeshParams params;
  po::options_description options("options");
  options.add_options()("dir", po::value<std::string>(&dir)->required(),
                        "a folder written by `wearknit cut`; the stitch mesh is written there")(
      "gauge", po::value<double>(&gauge.needles_per_inch)->default_value(15.0),
      "machine gauge, needles per inch")(
      "swatch", po::value<std::string>(&swatch)->default_value("40x40:42x115"),
      "measured swatch STITCHESxROWS:WIDTHxHEIGHT_MM (the paper's seed swatch, §8.1)")(
      "stitch-mm", po::value<std::string>(&stitch_mm),
      "stitch size COURSExWALE in mm, instead of --swatch")(
      "straighten", po::value<int>(&params.straighten_iterations)->default_value(100),
      "at most this many fits of the row time towards unit row height after the fit to the "
      "labels; they stop once the row time moves less than 0.01 row")(
      "label-weight", po::value<double>(&params.label_weight)->default_value(0.1),
      "weight of the labelled wale direction in each straightening fit")(
      "pentagon-cost", po::value<double>(&params.pentagon_cost)->default_value(0.05),
      "cost of an increase or decrease against a wale side's squared relative length error")(
      "stability-cost", po::value<double>(&params.stability_cost)->default_value(1.0),
      "cost of breaking a Fig. 7 rule of thumb (docs/stitch-mesh.md); 0 ignores them")(
      "outside-cost", po::value<double>(&params.outside_cost)->default_value(0.05),
      "extra cost of a wale side more than 15% off its target length")(
      "row-end-wales", po::value<double>(&params.tip_side_wales)->default_value(0.9),
      "a row that meets an oblique boundary in a point ends in a wale side this many wales "
      "long instead; 0 keeps the point")(
      "saddle-wales", po::value<double>(&params.saddle_wales)->default_value(5.0),
      "hold the row time's saddles where rows would go round them on a level, moving the rows "
      "within this many wales of each; 0 leaves them")(
      "relax", po::value<int>(&params.relax_sweeps)->default_value(150),
      "at most this many sweeps moving the inner stitch vertices over the surface "
      "towards their sides' target lengths; 0 keeps them as zipped")("no-picture",
                                                                     "do not draw stitch-mesh.png")(
      "format", po::value<std::string>(&format_name)->default_value("text"),
      "diagnostics as text (stderr) or json (stdout)")("json", "same as --format json")(
      "quiet,q", "print nothing on success");
  po::positional_options_description positional;
  positional.add("dir", 1);
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("stitch-mesh"), options, positional, values, context)) {
    return *code;
  }
  const auto format = text_or_json_format(values, format_name, "stitch-mesh", context);
  if (!format) return kExitUsage;
  std::string problem;
  if (values.count("stitch-mm") != 0) {
    if (!values["swatch"].defaulted()) {
      context.err << "wearknit stitch-mesh: give --swatch or --stitch-mm, not both\n";
      return kExitUsage;
    }
    problem = planner::parse_stitch_mm(stitch_mm, gauge);
  } else {
    problem = planner::parse_swatch(swatch, gauge);
  }
  if (problem.empty()) problem = planner::check_gauge(gauge);
  if (problem.empty() && (params.straighten_iterations < 0 || !(params.label_weight >= 0) ||
                          !(params.pentagon_cost >= 0) || !(params.stability_cost >= 0) ||
                          !(params.outside_cost >= 0) || !(params.tip_side_wales >= 0) ||
                          params.relax_sweeps < 0 || !(params.saddle_wales >= 0))) {
    problem =
        "--straighten, --label-weight, --pentagon-cost, --stability-cost, --outside-cost, "
        "--row-end-wales, --saddle-wales and --relax must not be negative";
  }
  if (!problem.empty()) {
    context.err << "wearknit stitch-mesh: " << problem << "\n";
    return kExitUsage;
  }

  const auto start = std::chrono::steady_clock::now();
  knitout::DiagnosticSink sink;
  if (!std::filesystem::is_directory(dir)) {
    sink.error(dir, 0, 0, "P020", "no such folder (run `wearknit cut GARMENT -o DIR` first)");
    print_diagnostics(context, sink.diagnostics(), *format);
    return kExitUsage;
  }
  std::optional<planner::CutMesh> cut = planner::read_cut_result(dir, sink);
  if (!cut) {
    print_diagnostics(context, sink.diagnostics(), *format);
    return kExitInvalid;
  }
  const std::string cut_name = (std::filesystem::path(dir) / "cut-mesh.obj").string();
  const planner::LabelledDisc disc = planner::labelled_disc(*cut);
  for (const std::string& p : planner::check_disc(disc)) sink.error(cut_name, 0, 0, "P085", p);
  if (sink.has_errors()) {
    print_diagnostics(context, sink.diagnostics(), *format);
    return kExitInvalid;
  }
  params.course_mm = gauge.course_mm;
  params.wale_mm = gauge.wale_mm;
  const planner::StitchMeshResult result = planner::make_stitch_mesh(disc, params);
  if (!result.problems.empty()) {
    // The cut mesh was read fine but could not be meshed into valid stitches.
    std::size_t shown = 0;
    for (const std::string& p : result.problems) {
      if (++shown > 20) {
        sink.error(cut_name, 0, 0, "P086",
                   "... and " + std::to_string(result.problems.size() - 20) + " more problems");
        break;
      }
      sink.error(cut_name, 0, 0, "P086", "no valid stitch mesh: " + p);
    }
    print_diagnostics(context, sink.diagnostics(), *format);
    return kExitInvalid;
  }
  // Stitches more than a wale off the cut mesh span a gap of it (docs/stitch-mesh.md, "Fans").
  const planner::OffSurface off_surface =
      planner::off_surface_faces(result.mesh, disc, gauge.wale_mm);
  if (!off_surface.faces.empty()) {
    std::ostringstream message;
    message << std::fixed << std::setprecision(1) << off_surface.faces.size()
            << " stitches have a side more than one wale (" << gauge.wale_mm
            << " mm) off the cut mesh's surface, up to " << off_surface.max_offset_mm
            << " mm (at the stitch of `f` line " << off_surface.farthest_face + 1
            << " of stitch-mesh.smobj): they span a gap of it, and the knitted piece will not "
               "take the surface's shape there (docs/stitch-mesh.md, \"Fans\")";
    sink.warning(cut_name, 0, 0, "P087", message.str());
  }
  print_diagnostics(context, sink.diagnostics(), *format);

  const std::filesystem::path base(dir);
  std::string failure = knitout::write_file_atomically(
      (base / "stitch-mesh.smobj").string(),
      [&](std::ostream& out) { planner::write_smobj(out, result.mesh); });
  if (failure.empty()) {
    failure = knitout::write_file_atomically(
        (base / "stitch-mesh.obj").string(),
        [&](std::ostream& out) { planner::write_stitch_obj(out, result.mesh); });
  }
  if (failure.empty() && values.count("no-picture") == 0) {
    failure = planner::draw_stitch_mesh(result.mesh, (base / "stitch-mesh.png").string());
  }
  planner::StitchMeshReport report;
  report.gauge = gauge;
  report.figures = planner::measure(result.mesh);
  report.stats = result.stats;
  report.stability = planner::count_stability_rules(result.mesh);
  report.off_surface = off_surface;
  report.disc_area_mm2 = planner::disc_area_mm2(disc);
  report.seconds = seconds_since(start);
  if (failure.empty()) failure = planner::merge_stitch_report(dir, report);
  if (!failure.empty()) {
    context.err << "wearknit stitch-mesh: " << failure << '\n';
    return kExitUsage;
  }
  if (values.count("quiet") == 0 && *format == DiagnosticFormat::Text) {
    const planner::StitchMeshFigures& f = report.figures;
    context.out << std::fixed << std::setprecision(3) << "stitch mesh: " << f.faces << " stitches ("
                << f.knit << " knit, " << f.increase << " increase, " << f.decrease << " decrease, "
                << f.short_row << " short-row) in " << result.stats.rows << " rows; course "
                << f.course.mean_mm << " mm (target " << gauge.course_mm << "), wale "
                << f.wale.mean_mm << " mm (target " << gauge.wale_mm << "); "
                << std::setprecision(2) << report.seconds << " s\n"
                << "wrote " << dir << "/{stitch-mesh.smobj,stitch-mesh.obj"
                << (values.count("no-picture") ? "" : ",stitch-mesh.png") << "} and updated " << dir
                << "/report.json\n";
  }
  return kExitOk;
}

}  // namespace wearknit::cli
