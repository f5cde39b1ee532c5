// wearknit simulate: a dry run on the needle-bed virtual machine, with
// statistics, the bed view picture, the interactive bed view page and the
// knit graph.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "apps/wearknit/cli.hpp"
#include "backends/dat/pass_preview.hpp"
#include "knitout/output_file.hpp"
#include "knitout/parser.hpp"
#include "simulators/bed/bed_page.hpp"
#include "simulators/bed/bed_timeline.hpp"
#include "simulators/bed/bed_view.hpp"
#include "simulators/bed/knit_graph.hpp"
#include "simulators/bed/machine.hpp"
#include "simulators/bed/observer_pair.hpp"
#include "simulators/bed/profile.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_simulate(const std::vector<std::string>& args, Context& context) {
  std::string input;
  std::string machine_name;
  std::string bed_view_path;
  std::string knit_graph_path;
  std::string html_path;
  std::size_t max_repeats = 20;
  po::options_description options("options");
  options.add_options()("input", po::value<std::string>(&input)->required(),
                        "knitout file ('-' reads stdin)")(
      "machine,m", po::value<std::string>(&machine_name)->default_value("swg091n2"),
      ("machine profile: " + bed::profile_names()).c_str())(
      "stats", "print statistics (the default when nothing else is asked for)")(
      "json", "statistics and diagnostics as one JSON object on stdout")(
      "bed-view", po::value<std::string>(&bed_view_path),
      "write the needle x time bed view picture (.png or .svg)")(
      "html", po::value<std::string>(&html_path),
      "write the interactive bed view: one self-contained HTML page")(
      "knit-graph", po::value<std::string>(&knit_graph_path),
      "write every loop with its yarn and parents as JSON")(
      "passes", "with the statistics, list every carriage pass the DAT backend forms")(
      "max-repeats", po::value<std::size_t>(&max_repeats)->default_value(20),
      "show at most this many warnings of one code (0 = all)");
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("simulate"), options, positional, values, context)) {
    return *code;
  }
  const bed::MachineProfile* profile = bed::find_profile(machine_name);
  if (profile == nullptr) {
    context.err << "wearknit simulate: unknown machine '" << machine_name
                << "'; known machines: " << bed::profile_names() << "\n";
    return kExitUsage;
  }
  if (!bed_view_path.empty()) {
    const std::string ext = std::filesystem::path(bed_view_path).extension().string();
    if (ext != ".png" && ext != ".svg") {
      context.err << "wearknit simulate: --bed-view writes .png or .svg, not '" << bed_view_path
                  << "'\n";
      return kExitUsage;
    }
  }
  const bool json = values.count("json") != 0;
  const bool stats_wanted = values.count("stats") != 0 || json ||
                            (bed_view_path.empty() && knit_graph_path.empty() && html_path.empty());

  std::ifstream file;
  std::istream* in = &std::cin;
  const std::string source = input == "-" ? "<stdin>" : input;
  if (input != "-") {
    if (std::filesystem::is_regular_file(input)) file.open(input, std::ios::binary);
    if (!file.is_open() || !file) {
      context.err << input << ": error: cannot open file\n";
      return kExitUsage;
    }
    in = &file;
  }
  // The page shows the source text under the pointer: standard input is
  // read whole first (a file is read again when the page is written).
  std::string stdin_text;
  std::istringstream stdin_copy;
  if (!html_path.empty() && input == "-") {
    stdin_text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
    stdin_copy.str(stdin_text);
    in = &stdin_copy;
  }

  knitout::DiagnosticSink sink;
  bed::BedView bed_view;
  bed::KnitGraph knit_graph;
  bed::BedTimeline timeline;
  bed::ObserverPair pictures(bed_view_path.empty() ? nullptr : &bed_view,
                             knit_graph_path.empty() ? nullptr : &knit_graph);
  bed::ObserverPair observers(&pictures, html_path.empty() ? nullptr : &timeline);
  bed::MachineOptions machine_options;
  machine_options.max_repeats = max_repeats;
  if (!bed_view_path.empty() || !knit_graph_path.empty() || !html_path.empty()) {
    machine_options.observer = &observers;
  }

  knitout::Reader reader(*in, source, sink);
  std::optional<std::size_t> header_carriers;
  for (const knitout::Header& header : reader.headers()) {
    if (header.key == "Carriers") header_carriers = reader.carriers().size();
  }
  bed::Machine machine(*profile, sink, source, reader.carriers(), header_carriers, machine_options);
  machine.check_headers(reader.headers());
  // The carriage passes the DAT backend forms, beside the VM's statistics;
  // the VM's verdict is this verb's verdict.
  std::optional<dat::PassPreview> passes;
  if (stats_wanted) {
    passes.emplace(source, profile->name);
    passes->begin(reader.has_magic(), reader.headers());
  }
  knitout::Instruction instruction;
  while (reader.next(instruction)) {
    machine.step(instruction);
    if (passes) passes->add(instruction, reader.carriers(), reader.text());
  }
  const auto last_line = static_cast<std::uint32_t>(reader.lines_read());
  machine.finish(last_line);
  bed::Stats stats = machine.stats();
  std::vector<dat::CarriagePass> carriage_passes;
  if (passes) {
    if (auto formed = passes->finish(last_line)) {
      carriage_passes = std::move(*formed);
      stats.dat_passes = carriage_passes.size();
    }
  }
  stats.errors = sink.error_count();
  stats.warnings = sink.warning_count();

  const std::vector<knitout::Diagnostic> diagnostics = sink.sorted();
  if (json) {
    context.out << "{\"stats\": ";
    bed::write_stats_json(context.out, stats, source, profile->name);
    context.out << ", \"carriage_passes\": ";
    if (stats.dat_passes) {
      dat::write_carriage_passes_json(context.out, carriage_passes);
    } else {
      context.out << "null";
    }
    context.out << ", \"diagnostics\": ";
    knitout::print_json(context.out, diagnostics);
    context.out << "}\n";
  } else {
    knitout::print_text(context.err, diagnostics);
    if (stats_wanted) {
      bed::write_stats_text(context.out, stats, source, profile->name);
      if (stats.dat_passes) {
        context.out << "  ";
        dat::write_carriage_passes_text(context.out, carriage_passes, values.count("passes") != 0);
      } else if (!passes->why_none().empty()) {
        context.out << "  carriage passes: none formed (" << passes->why_none() << ")\n";
      }
    }
  }

  int status = sink.has_errors() ? kExitInvalid : kExitOk;
  if (!bed_view_path.empty()) {
    const std::string failure = bed_view.write(bed_view_path, machine, source);
    if (!failure.empty()) {
      context.err << "wearknit simulate: " << failure << "\n";
      status = kExitUsage;
    }
  }
  if (!html_path.empty()) {
    std::string file_text;
    if (input != "-") {
      std::ifstream again(input, std::ios::binary);
      file_text.assign(std::istreambuf_iterator<char>(again), std::istreambuf_iterator<char>());
    }
    bed::BedPageInput page;
    page.title = std::filesystem::path(source).filename().string();
    std::ostringstream subtitle;
    subtitle << "on " << profile->name << " · " << stats.lines << " lines, " << stats.sweeps
             << " sweeps · estimated " << std::lround(stats.estimated_time_s) << " s · "
             << (sink.has_errors() ? "INVALID" : "valid") << " (" << stats.errors
             << (stats.errors == 1 ? " error, " : " errors, ") << stats.warnings
             << (stats.warnings == 1 ? " warning)" : " warnings)");
    page.subtitle = subtitle.str();
    page.timeline = timeline.serialize(diagnostics);
    page.source_text = input == "-" ? std::string_view(stdin_text) : std::string_view(file_text);
    const std::string failure = knitout::write_file_atomically(
        html_path, [&](std::ostream& out) { bed::write_bed_page(out, page); });
    if (!failure.empty()) {
      context.err << "wearknit simulate: " << failure << "\n";
      status = kExitUsage;
    }
  }
  if (!knit_graph_path.empty()) {
    const std::string failure = knitout::write_file_atomically(
        knit_graph_path, [&](std::ostream& out) { knit_graph.write_json(out, machine); });
    if (!failure.empty()) {
      context.err << "wearknit simulate: " << failure << "\n";
      status = kExitUsage;
    }
  }
  return status;
}

}  // namespace wearknit::cli
