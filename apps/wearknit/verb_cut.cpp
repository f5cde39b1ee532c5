// wearknit cut: garment mesh -> quad-dominant proxy -> one disc (§4).
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "planner/cut/cut.hpp"
#include "planner/cut/cut_io.hpp"
#include "planner/cut/cut_pictures.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/proxy/proxy.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_cut(const std::vector<std::string>& args, Context& context) {
  std::string input;
  std::string output;
  std::string units;
  std::string format_name;
  double scale = 1.0;
  double proxy_edge_mm = 0.0;
  std::string vanishing = "acute";
  double vanishing_slack_deg = 30.0;
  std::uint64_t seed = 1;
  int picture_px = 600;
  planner::CutParams params;
  po::options_description options("options");
  options.add_options()("garment", po::value<std::string>(&input)->required(),
                        "garment surface (OBJ, OFF, PLY or STL)")(
      "output,o", po::value<std::string>(&output)->required(), "write the cut folder here")(
      "seed", po::value<std::uint64_t>(&seed)->default_value(1),
      "picks the seed quad and breaks ties between equal scores")(
      "cs", po::value<double>(&params.cs)->default_value(1000.0),
      "straightness weight c_s (motorcycle-graph edges, §4.2)")(
      "co", po::value<double>(&params.co)->default_value(1.0), "overlap weight c_o (§4.2)")(
      "vanishing", po::value<std::string>(&vanishing)->default_value("acute"),
      "vanishing corner of each triangle: acute (its most acute corner, §4.1) or regular "
      "(a corner within --vanishing-slack of it that leaves fewer irregular vertices)")(
      "vanishing-slack", po::value<double>(&vanishing_slack_deg)->default_value(30.0),
      "degrees a regular vanishing corner may be wider than the most acute one")(
      "units", po::value<std::string>(&units)->default_value("mm"),
      "unit of the file's coordinates: mm, cm or m")(
      "scale", po::value<double>(&scale)->default_value(1.0), "multiply coordinates by this")(
      "proxy-edge-mm", po::value<double>(&proxy_edge_mm)->default_value(0.0),
      "edge length of the remeshed proxy for triangle input (0: about 3000 quads)")(
      "no-pictures", "do not draw cuts-3d.png and layout-2d.png")(
      "picture-px", po::value<int>(&picture_px)->default_value(600),
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
  if (!mm_per_unit) {
    context.err << "wearknit cut: --units takes mm, cm or m, not '" << units << "'\n";
    return kExitUsage;
  }
  if (!(scale > 0.0) || !std::isfinite(scale)) {
    context.err << "wearknit cut: --scale must be a positive number\n";
    return kExitUsage;
  }
  if (picture_px < 50 || picture_px > 4000) {
    context.err << "wearknit cut: --picture-px must be between 50 and 4000\n";
    return kExitUsage;
  }
  if (!(proxy_edge_mm >= 0.0) || params.cs < 0.0 || params.co < 0.0) {
    context.err << "wearknit cut: --proxy-edge-mm, --cs and --co must not be negative\n";
    return kExitUsage;
  }
  if (vanishing != "acute" && vanishing != "regular") {
    context.err << "wearknit cut: --vanishing takes acute or regular, not '" << vanishing << "'\n";
    return kExitUsage;
  }
  if (!(vanishing_slack_deg >= 0.0) || vanishing_slack_deg > 180.0) {
    context.err << "wearknit cut: --vanishing-slack must be between 0 and 180 degrees\n";
    return kExitUsage;
  }
  params.vanishing.fewest_irregular = vanishing == "regular";
  params.vanishing.slack_deg = vanishing_slack_deg;
  params.seed = seed;

  planner::CutReport report;
  report.input = input;
  report.units = units;
  report.scale = scale;
  report.params = params;
  knitout::DiagnosticSink sink;
  auto start = std::chrono::steady_clock::now();
  const bool input_exists = std::filesystem::is_regular_file(input);
  auto mesh = planner::load_mesh(input, {*mm_per_unit, scale}, sink);
  print_diagnostics(context, sink.diagnostics(), *format);
  if (!mesh) return input_exists ? kExitInvalid : kExitUsage;
  report.load_seconds = seconds_since(start);
  report.input_size_mm = planner::bounding_box_size(*mesh);
  report.input_vertices = static_cast<int>(mesh->positions.size());
  report.input_faces = static_cast<int>(mesh->faces.size());

  start = std::chrono::steady_clock::now();
  planner::ProxyParams proxy_params;
  proxy_params.proxy_edge_mm = proxy_edge_mm;
  planner::ProxyResult proxy = planner::make_proxy(*mesh, proxy_params);
  report.remeshed = proxy.remeshed;
  report.proxy_edge_mm = proxy.edge_mm;
  report.polygons_split = proxy.polygons_split;
  report.triangles_paired = proxy.triangles_paired;
  report.samples = proxy.samples;
  report.holes_filled = proxy.holes_filled;
  report.folds_removed = proxy.folds_removed;
  report.remesh_attempts = proxy.remesh_attempts;
  report.proxy_method = proxy.method;
  report.remesh_failure = proxy.remesh_failure;
  report.proxy_seconds = seconds_since(start);

  start = std::chrono::steady_clock::now();
  planner::CutMesh cut = planner::cut_surface(planner::HalfedgeMesh(std::move(proxy.mesh)), params);
  report.cut_seconds = seconds_since(start);
  const std::vector<std::string> problems = planner::verify_cut(cut);
  if (!problems.empty()) {
    // A broken invariant is a bug of ours, not of the input: say so loudly.
    context.err << "wearknit cut: internal error: the cut violates its guarantees:\n";
    for (const auto& p : problems) context.err << "  " << p << '\n';
    return kExitInvalid;
  }

  std::string failure = planner::write_cut_result(output, cut, report);
  if (failure.empty() && values.count("no-pictures") == 0) {
    failure = planner::draw_cuts_3d(cut, (std::filesystem::path(output) / "cuts-3d.png").string(),
                                    picture_px);
    if (failure.empty()) {
      failure = planner::draw_layout_2d(
          cut, (std::filesystem::path(output) / "layout-2d.png").string(), picture_px * 5 / 3);
    }
  }
  if (!failure.empty()) {
    context.err << "wearknit cut: " << failure << '\n';
    return kExitUsage;
  }
  if (values.count("quiet") == 0 && *format == DiagnosticFormat::Text) {
    const planner::CutSummary s = planner::summarize(cut);
    context.out << std::fixed << std::setprecision(1) << input << ": " << report.input_size_mm.x()
                << " x " << report.input_size_mm.y() << " x " << report.input_size_mm.z()
                << " mm; proxy " << cut.proxy.num_faces() << " faces"
                << (proxy.remeshed ? " (remeshed: " + proxy.method + ")"
                                   : std::string(" (input as is)"))
                << "\n"
                << "cut: " << s.irregular_vertices << " irregular vertices, " << s.cut_edges
                << " cut edges in " << s.arcs << " arcs, " << s.cut_length_mm << " mm, "
                << s.overlapping_faces << " overlapping faces, " << std::setprecision(3)
                << report.proxy_seconds + report.cut_seconds << " s\n"
                << "wrote " << output
                << "/{proxy.obj,cut-mesh.obj,cuts.json,labels.json,report.json"
                << (values.count("no-pictures") ? "" : ",cuts-3d.png,layout-2d.png") << "}\n";
  }
  return kExitOk;
}

}  // namespace wearknit::cli
