// wearknit schedule: the flat-sheet scheduler (paper §7) on a plan folder's
// stitch-mesh.smobj; the stage itself is planner::schedule_stitches
// (planner/pipeline.hpp): every piece through the needle-bed VM, then
// pieces/piece-N.{k,dat,svg,layout.json} and schedule.json.
#include <filesystem>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/stage_options.hpp"
#include "planner/pipeline.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;
namespace fs = std::filesystem;

int run_schedule(const std::vector<std::string>& args, Context& context) {
  std::string dir, format_name;
  ScheduleOptions schedule;
  po::options_description options("options");
  options.add_options()("dir", po::value<std::string>(&dir)->required(),
                        "plan folder holding stitch-mesh.smobj")(
      "seed", po::value<std::uint64_t>(&schedule.params.schedule.seed)->default_value(1),
      "random seed");
  add_schedule_options(options, schedule);
  add_threads_option(options, schedule.params.schedule.threads);
  options.add_options()("format", po::value<std::string>(&format_name)->default_value("text"),
                        "diagnostics as text (stderr) or json (stdout)")(
      "json", "same as --format json")("quiet,q", "print nothing on success");
  po::positional_options_description positional;
  positional.add("dir", 1);
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("schedule"), options, positional, values, context)) {
    return *code;
  }
  const auto format = text_or_json_format(values, format_name, "schedule", context);
  if (!format) return kExitUsage;
  if (const std::string problem = check_schedule_options(values, schedule); !problem.empty()) {
    context.err << "wearknit schedule: " << problem << '\n';
    return kExitUsage;
  }
  if (!fs::is_directory(dir)) {
    context.err << dir << ": error: not a folder\n";
    return kExitUsage;
  }
  knitout::DiagnosticSink sink;
  const auto stitches = planner::read_stitch_mesh(dir, sink);
  const std::string smobj = (fs::path(dir) / "stitch-mesh.smobj").string();
  std::optional<planner::ScheduleOutcome> outcome;
  if (stitches) outcome = planner::schedule_stitches(*stitches, schedule.params, smobj, sink);
  print_diagnostics(context, sink.diagnostics(), *format);
  if (!outcome) {
    // No stitch mesh at all is a usage problem; one that cannot be read or
    // scheduled is invalid input.
    return stitches || fs::exists(smobj) ? kExitInvalid : kExitUsage;
  }
  std::string failure = planner::write_schedule(dir, *outcome);
  if (failure.empty()) failure = planner::write_folder_summary(dir);
  if (!failure.empty()) {
    context.err << "wearknit schedule: " << failure << '\n';
    return kExitUsage;
  }
  if (!values.count("quiet"))
    context.out << planner::describe(*outcome, smobj, (fs::path(dir) / "pieces").string());
  return kExitOk;
}

}  // namespace wearknit::cli
