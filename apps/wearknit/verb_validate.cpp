// wearknit validate: run every instruction of knitout files through the
// needle-bed virtual machine and report what would go wrong, where.
#include <filesystem>
#include <iostream>
#include <ostream>
#include <string>
#include <vector>

#include "apps/wearknit/cli.hpp"
#include "knitout/diagnostic_reports.hpp"
#include "simulators/bed/profile.hpp"
#include "simulators/bed/validate.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_validate(const std::vector<std::string>& args, Context& context) {
  std::vector<std::string> inputs;
  std::string machine_name;
  std::string format_name;
  std::size_t max_repeats = 20;
  po::options_description options("options");
  options.add_options()("input", po::value<std::vector<std::string>>(&inputs)->required(),
                        "knitout files ('-' reads stdin)")(
      "machine,m", po::value<std::string>(&machine_name)->default_value("swg091n2"),
      ("machine profile: " + bed::profile_names()).c_str())(
      "werror", "treat warnings as errors (exit 1 when there are any)")(
      "format", po::value<std::string>(&format_name)->default_value("text"),
      "diagnostics as text (stderr), json, junit or github (stdout)")("json",
                                                                      "same as --format json")(
      "max-repeats", po::value<std::size_t>(&max_repeats)->default_value(20),
      "show at most this many warnings of one code per file (0 = all)");
  po::positional_options_description positional;
  positional.add("input", -1);
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("validate"), options, positional, values, context)) {
    return *code;
  }
  auto format = parse_diagnostic_format(values.count("json") ? "json" : format_name);
  if (!format) {
    context.err << "wearknit validate: --format takes text, json, junit or github, not '"
                << format_name << "'\n";
    return kExitUsage;
  }
  const bed::MachineProfile* profile = bed::find_profile(machine_name);
  if (profile == nullptr) {
    context.err << "wearknit validate: unknown machine '" << machine_name
                << "'; known machines: " << bed::profile_names() << "\n";
    return kExitUsage;
  }
  const bool werror = values.count("werror") != 0;

  std::vector<knitout::FileDiagnostics> results;
  bool io_error = false;
  for (const std::string& input : inputs) {
    knitout::DiagnosticSink sink;
    bed::MachineOptions machine_options;
    machine_options.max_repeats = max_repeats;
    bed::Stats stats;
    knitout::FileDiagnostics result;
    result.path = input == "-" ? "<stdin>" : input;
    if (input == "-") {
      stats = bed::validate_stream(std::cin, result.path, *profile, sink, machine_options);
    } else {
      if (!std::filesystem::is_regular_file(input)) {
        context.err << input << ": error: cannot open file (not a regular file)\n";
        io_error = true;
        continue;
      }
      stats = bed::validate_file(input, *profile, sink, machine_options);
      for (const knitout::Diagnostic& d : sink.diagnostics()) io_error |= d.code == "K090";
    }
    result.diagnostics = sink.sorted();
    result.errors = sink.error_count();
    result.warnings = sink.warning_count();
    result.instructions = stats.instructions;
    results.push_back(std::move(result));
  }

  bool any_failure = false;
  std::vector<knitout::Diagnostic> all;
  for (const knitout::FileDiagnostics& r : results) {
    any_failure |= r.fails(werror);
    all.insert(all.end(), r.diagnostics.begin(), r.diagnostics.end());
  }
  switch (*format) {
    case DiagnosticFormat::Text:
      knitout::print_text(context.err, all);
      for (const knitout::FileDiagnostics& r : results) {
        context.out << r.path << ": " << (r.fails(werror) ? "INVALID" : "valid") << " on "
                    << profile->name << " (" << r.instructions << " instructions, " << r.errors
                    << " errors, " << r.warnings << " warnings)\n";
      }
      break;
    case DiagnosticFormat::Json:
      knitout::print_json(context.out, all);
      break;
    case DiagnosticFormat::Junit:
      knitout::print_junit(context.out, results, werror, profile->name);
      break;
    case DiagnosticFormat::Github:
      knitout::print_github(context.out, results, werror);
      break;
  }
  if (io_error) return kExitUsage;
  return any_failure ? kExitInvalid : kExitOk;
}

}  // namespace wearknit::cli
