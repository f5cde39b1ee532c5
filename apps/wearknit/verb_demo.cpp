// wearknit demo: the main job on a built-in input, needing no data file.
//
// It generates knitout sheets (plain and seed), reads them back through the
// parser, writes the canonical form, checks that it reads back to the same
// program, and runs every instruction through the needle-bed virtual machine
// on the default machine profile.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "knitout/generate.hpp"
#include "knitout/output_file.hpp"
#include "knitout/parser.hpp"
#include "knitout/writer.hpp"
#include "simulators/bed/validate.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_demo(const std::vector<std::string>& args, Context& context) {
  std::string out_dir;
  po::options_description options("options");
  options.add_options()("output,o",
                        po::value<std::string>(&out_dir)->default_value("wearknit-demo"),
                        "folder to write into");
  po::positional_options_description positional;
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("demo"), options, positional, values, context)) {
    return *code;
  }
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) {
    context.err << "wearknit demo: cannot create " << out_dir << ": " << ec.message() << '\n';
    return kExitUsage;
  }
  struct Sample {
    std::string name;
    knitout::SheetParams params;
  };
  const Sample samples[] = {
      {"plain-sheet", {40, 30, "3", knitout::SheetPattern::Plain}},
      {"seed-sheet", {30, 30, "3", knitout::SheetPattern::Seed}},
  };
  bool all_ok = true;
  context.out << "wearknit demo: writing into " << out_dir << "/\n";
  for (const Sample& sample : samples) {
    const auto start = std::chrono::steady_clock::now();
    const std::string generated_path = out_dir + "/" + sample.name + ".k";
    std::string failure = knitout::write_file_atomically(
        generated_path, [&](std::ostream& out) { knitout::write_sheet(out, sample.params); });
    if (!failure.empty()) {
      context.err << "wearknit demo: " << failure << '\n';
      return kExitUsage;
    }
    knitout::DiagnosticSink sink;
    knitout::Program program = knitout::parse_file(generated_path, sink);
    const std::string canonical_path = out_dir + "/" + sample.name + ".fmt.k";
    failure = knitout::write_file_atomically(
        canonical_path, [&](std::ostream& out) { knitout::write(out, program); });
    if (!failure.empty()) {
      context.err << "wearknit demo: " << failure << '\n';
      return kExitUsage;
    }
    knitout::DiagnosticSink reread_sink;
    const knitout::Program reread = knitout::parse_file(canonical_path, reread_sink);
    const bool round_trip = reread == program;
    knitout::DiagnosticSink vm_sink;
    const bed::Stats stats =
        bed::validate(program, bed::default_profile(), vm_sink, generated_path);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    knitout::print_text(context.err, sink.diagnostics());
    knitout::print_text(context.err, vm_sink.diagnostics());
    const bool ok =
        !sink.has_errors() && !reread_sink.has_errors() && round_trip && !vm_sink.has_errors();
    all_ok = all_ok && ok;
    context.out << "  " << sample.name << ": " << program.instructions.size() << " instructions, "
                << sink.error_count() << " errors, " << sink.warning_count()
                << " warnings, canonical form " << (round_trip ? "reads back identical" : "DIFFERS")
                << "; virtual machine (" << bed::default_profile().name
                << "): " << vm_sink.error_count() << " errors, " << vm_sink.warning_count()
                << " warnings, " << stats.loops_made << " loops (" << ms << " ms)\n"
                << "    " << generated_path << "\n    " << canonical_path << '\n';
  }
  context.out << (all_ok ? "demo finished: open the .k files above in a knitout viewer\n"
                         : "demo FAILED\n");
  return all_ok ? kExitOk : kExitInvalid;
}

}  // namespace wearknit::cli
