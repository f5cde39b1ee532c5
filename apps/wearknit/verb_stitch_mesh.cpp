// wearknit stitch-mesh: cut folder -> anisotropic stitch mesh (§6); the
// stage itself is planner::mesh_stitches (planner/pipeline.hpp).
#include <filesystem>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/stage_options.hpp"
#include "planner/pipeline.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_stitch_mesh(const std::vector<std::string>& args, Context& context) {
  std::string dir, format_name;
  StitchMeshOptions stitch;
  po::options_description options("options");
  options.add_options()("dir", po::value<std::string>(&dir)->required(),
                        "a folder written by `wearknit cut`; the stitch mesh is written there");
  add_stitch_mesh_options(options, stitch);
  options.add_options()("no-picture", "do not draw stitch-mesh.png")(
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
  if (const std::string problem = check_stitch_mesh_options(values, stitch); !problem.empty()) {
    context.err << "wearknit stitch-mesh: " << problem << "\n";
    return kExitUsage;
  }

  knitout::DiagnosticSink sink;
  if (!std::filesystem::is_directory(dir)) {
    sink.error(dir, 0, 0, "P020", "no such folder (run `wearknit cut GARMENT -o DIR` first)");
    print_diagnostics(context, sink.diagnostics(), *format);
    return kExitUsage;
  }
  const std::optional<planner::Cut> cut = planner::read_cut(dir, sink);
  std::optional<planner::StitchMeshOutcome> outcome;
  if (cut) {
    const std::string source = (std::filesystem::path(dir) / "cut-mesh.obj").string();
    outcome = planner::mesh_stitches(*cut, stitch.params, source, sink);
  }
  print_diagnostics(context, sink.diagnostics(), *format);
  if (!outcome) return kExitInvalid;
  const bool picture = values.count("no-picture") == 0;
  std::string failure = planner::write_stitch_mesh(dir, *outcome, picture);
  if (failure.empty()) failure = planner::write_folder_summary(dir);
  if (!failure.empty()) {
    context.err << "wearknit stitch-mesh: " << failure << '\n';
    return kExitUsage;
  }
  if (values.count("quiet") == 0 && *format == DiagnosticFormat::Text) {
    context.out << planner::describe(*outcome) << "wrote " << dir
                << "/{stitch-mesh.smobj,stitch-mesh.obj" << (picture ? ",stitch-mesh.png" : "")
                << ",stitch-mesh.json} and updated " << dir << "/report.json\n";
  }
  return kExitOk;
}

}  // namespace wearknit::cli
