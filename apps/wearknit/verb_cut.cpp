// wearknit cut: garment mesh -> quad-dominant proxy -> one disc (§4); the
// stage itself is planner::cut_garment (planner/pipeline.hpp).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/stage_options.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/pipeline.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_cut(const std::vector<std::string>& args, Context& context) {
  std::string input, output, units, format_name;
  double scale = 1.0;
  CutOptions cut;
  planner::CutPictures pictures;
  po::options_description options("options");
  options.add_options()("garment", po::value<std::string>(&input)->required(),
                        "garment surface (OBJ, OFF, PLY or STL)")(
      "output,o", po::value<std::string>(&output)->required(), "write the cut folder here")(
      "seed", po::value<std::uint64_t>(&cut.params.cut.seed)->default_value(1),
      "picks the seed quad and breaks ties between equal scores")(
      "units", po::value<std::string>(&units)->default_value("mm"),
      "unit of the file's coordinates: mm, cm or m")(
      "scale", po::value<double>(&scale)->default_value(1.0), "multiply coordinates by this");
  add_cut_options(options, cut);
  options.add_options()("no-pictures", "do not draw cuts-3d.png and layout-2d.png")(
      "picture-px", po::value<int>(&pictures.panel_px)->default_value(600),
      "size of one 3D view in cuts-3d.png (2x2 views); layout-2d.png is 5/3 of it")(
      "format", po::value<std::string>(&format_name)->default_value("text"),
      "diagnostics as text (stderr) or json (stdout)")("json", "same as --format json")(
      "quiet,q", "print nothing on success");
  po::positional_options_description positional;
  positional.add("garment", 1);
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("cut"), options, positional, values, context)) {
    return *code;
  }
  const auto format = text_or_json_format(values, format_name, "cut", context);
  if (!format) return kExitUsage;
  const auto mm_per_unit = planner::mm_per_unit(units);
  std::string problem = check_cut_options(cut);
  if (!mm_per_unit) problem = "--units takes mm, cm or m, not '" + units + "'";
  if (!(scale > 0.0) || !std::isfinite(scale)) problem = "--scale must be a positive number";
  if (pictures.panel_px < 50 || pictures.panel_px > 4000)
    problem = "--picture-px must be between 50 and 4000";
  if (!problem.empty()) {
    context.err << "wearknit cut: " << problem << '\n';
    return kExitUsage;
  }
  pictures.draw = values.count("no-pictures") == 0;

  knitout::DiagnosticSink sink;
  const auto start = std::chrono::steady_clock::now();
  const bool input_exists = std::filesystem::is_regular_file(input);
  auto mesh = planner::load_mesh(input, {*mm_per_unit, scale}, sink);
  print_diagnostics(context, sink.diagnostics(), *format);
  if (!mesh) return input_exists ? kExitInvalid : kExitUsage;
  const double load_seconds = seconds_since(start);

  planner::Cut result = planner::cut_garment(*mesh, cut.params);
  result.report.input = input;
  result.report.units = units;
  result.report.scale = scale;
  result.report.load_seconds = load_seconds;
  std::string failure = planner::write_cut(output, result, pictures);
  if (failure.empty()) failure = planner::write_folder_summary(output);
  if (!failure.empty()) {
    context.err << "wearknit cut: " << failure << '\n';
    return kExitUsage;
  }
  if (values.count("quiet") == 0 && *format == DiagnosticFormat::Text) {
    context.out << planner::describe(result) << "wrote " << output
                << "/{proxy.obj,cut-mesh.obj,cut.json,labels.json"
                << (pictures.draw ? ",cuts-3d.png,layout-2d.png" : "")
                << "} and the folder's report.json, cuts.json\n";
  }
  return kExitOk;
}

}  // namespace wearknit::cli
