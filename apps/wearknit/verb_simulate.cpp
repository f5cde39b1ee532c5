// wearknit simulate: a dry run on the needle-bed virtual machine, with
// statistics, the bed view picture and the knit graph.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/wearknit/cli.hpp"
#include "backends/dat/passes.hpp"
#include "knitout/output_file.hpp"
#include "knitout/parser.hpp"
#include "simulators/bed/bed_view.hpp"
#include "simulators/bed/knit_graph.hpp"
#include "simulators/bed/machine.hpp"
#include "simulators/bed/profile.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

namespace {

// Passes each event to two observers.
class Tee : public bed::Observer {
 public:
  Tee(bed::Observer* a, bed::Observer* b) : a_(a), b_(b) {}
  void loop_made(const bed::LoopEvent& e) override {
    if (a_) a_->loop_made(e);
    if (b_) b_->loop_made(e);
  }
  void loops_moved(knitout::Needle from, knitout::Needle to, int count,
                   std::uint32_t line) override {
    if (a_) a_->loops_moved(from, to, count, line);
    if (b_) b_->loops_moved(from, to, count, line);
  }
  void loops_dropped(knitout::Needle needle, std::span<const bed::LiveLoop> loops,
                     std::uint32_t line) override {
    if (a_) a_->loops_dropped(needle, loops, line);
    if (b_) b_->loops_dropped(needle, loops, line);
  }
  void racked(double racking, std::uint32_t line) override {
    if (a_) a_->racked(racking, line);
    if (b_) b_->racked(racking, line);
  }
  void sweep_ended(const bed::Machine& machine, std::uint32_t line) override {
    if (a_) a_->sweep_ended(machine, line);
    if (b_) b_->sweep_ended(machine, line);
  }

 private:
  bed::Observer* a_;
  bed::Observer* b_;
};

}  // namespace

int run_simulate(const std::vector<std::string>& args, Context& context) {
  std::string input;
  std::string machine_name;
  std::string bed_view_path;
  std::string knit_graph_path;
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
  const bool stats_wanted =
      values.count("stats") != 0 || json || (bed_view_path.empty() && knit_graph_path.empty());

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

  knitout::DiagnosticSink sink;
  bed::BedView bed_view;
  bed::KnitGraph knit_graph;
  Tee tee(bed_view_path.empty() ? nullptr : &bed_view,
          knit_graph_path.empty() ? nullptr : &knit_graph);
  bed::MachineOptions machine_options;
  machine_options.max_repeats = max_repeats;
  if (!bed_view_path.empty() || !knit_graph_path.empty()) machine_options.observer = &tee;

  knitout::Reader reader(*in, source, sink);
  std::optional<std::size_t> header_carriers;
  for (const knitout::Header& header : reader.headers()) {
    if (header.key == "Carriers") header_carriers = reader.carriers().size();
  }
  bed::Machine machine(*profile, sink, source, reader.carriers(), header_carriers, machine_options);
  machine.check_headers(reader.headers());
  // The carriage passes the DAT backend forms, for machines it writes
  // (`--stats` reports them beside the VM's figures). Its diagnostics stay
  // apart: the VM's verdict is this verb's verdict; a program the DAT
  // backend refuses just has no passes to report.
  const dat::Profile* dat_profile = dat::find_profile(profile->name);
  knitout::DiagnosticSink dat_sink;
  std::optional<dat::PassBuilder> pass_builder;
  if (stats_wanted && dat_profile != nullptr) {
    pass_builder.emplace(source, dat_sink, *dat_profile);
    pass_builder->begin(reader.has_magic(), reader.headers());
  }
  knitout::Instruction instruction;
  while (reader.next(instruction)) {
    machine.step(instruction);
    if (pass_builder && !pass_builder->failed()) {
      pass_builder->add(instruction, reader.carriers(), reader.text());
    }
  }
  const auto last_line = static_cast<std::uint32_t>(reader.lines_read());
  machine.finish(last_line);
  bed::Stats stats = machine.stats();
  std::vector<dat::CarriagePass> carriage_passes;
  std::string no_passes_reason =
      dat_profile == nullptr ? "the DAT backend does not write for " + profile->name : "";
  if (pass_builder) {
    pass_builder->finish(last_line);
    if (!pass_builder->failed()) {
      carriage_passes = dat::summarize(pass_builder->passes());
      stats.dat_passes = carriage_passes.size();
    } else if (!dat_sink.diagnostics().empty()) {
      no_passes_reason =
          "the DAT backend refuses the program: " + knitout::format(dat_sink.sorted().front());
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
      } else if (!no_passes_reason.empty()) {
        context.out << "  carriage passes: none formed (" << no_passes_reason << ")\n";
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
