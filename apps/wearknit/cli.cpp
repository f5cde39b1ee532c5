#include "apps/wearknit/cli.hpp"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>

namespace wearknit::cli {

namespace po = boost::program_options;

const std::vector<Verb>& verbs() {
  static const std::vector<Verb> kVerbs = {
      {"fmt", "fmt FILE.k [-o OUT.k] [--check]", "write a knitout file in canonical form", run_fmt},
      {"validate", "validate FILE.k... [--machine M] [--werror] [--format text|json|junit|github]",
       "run every instruction through the needle-bed virtual machine", run_validate},
      {"simulate",
       "simulate FILE.k [--stats] [--passes] [--json] [--bed-view OUT.png|OUT.svg] "
       "[--html OUT.html] [--knit-graph OUT.json] [--machine M]",
       "dry run: statistics, estimated machine time, bed views (picture, page), knit graph",
       run_simulate},
      {"dat", "dat FILE.k -o OUT.dat [--machine M] [--verify]",
       "knitout -> Shima Seiki DAT (swg091n2), byte for byte as knitout-to-dat.js", run_dat},
      {"dat-info", "dat-info FILE.dat [--passes] [--png OUT.png]",
       "read a DAT back: size, position, passes, picture", run_dat_info},
      {"demo", "demo [-o DIR]", "run the built-in example end to end and say what to open",
       run_demo},
      {"wearability",
       "wearability DIR --wearer WEARER.obj [--wearer-units U] [--wearer-scale S] [--trials K] "
       "[--runs R] [--seed N] [--threads T] "
       "[--recut-limit N] [--frames OUT/]",
       "label each cut-arc sew or lace by stripping the garment off the wearer; re-cut an "
       "unwearable cut (§5)",
       run_wearability},
      {"schedule", "schedule DIR [--trials N | --time-budget S] [--pattern plain|seed] [--seed N]",
       "knitting schedule and knitout pieces for a plan folder's stitch mesh (§7)", run_schedule},
      {"devices", "devices", "list serial ports and USB devices", run_devices},
      {"send", "send JOB --to URI [--resume]",
       "send a job (DAT or knitout) to a machine, with progress", run_send},
      {"status", "status --to URI [--pause | --continue | --cancel] [--json]",
       "show a machine's job and counters; pause, continue or cancel it", run_status},
      {"mock-device", "mock-device --listen URI --store DIR [--fault SPEC] [--rows-per-s N]",
       "the loopback mock knitting machine", run_mock_device},
      {"cut",
       "cut GARMENT -o DIR [--seed N] [--cs 1000] [--co 1] [--units mm|cm|m] [--scale S] "
       "[--proxy-edge-mm L]",
       "cut a garment surface into one disc with consistent course/wale labels (paper §4)",
       run_cut},
      {"stitch-mesh",
       "stitch-mesh DIR [--gauge N] [--swatch SxR:WxH_MM | --stitch-mm CxW] "
       "[--fine-features knit|refuse] [--no-picture]",
       "remesh a cut folder into a stitch mesh of course x wale faces (paper §6)", run_stitch_mesh},
      {"plan",
       "plan GARMENT --wearer WEARER -o DIR [--seed N] [--pattern plain|seed] [--units U] "
       "[--scale S | --size-mm L] [--gauge N] [--swatch S | --stitch-mm CxW] [--trials N] "
       "[--wear-trials K] [--send URI]",
       "the whole pipeline: cut, wearability beside stitch mesh and schedule, assembly guide",
       run_plan},
      {"assembly",
       "assembly DIR [--wearer WEARER.obj [--wearer-units U] [--wearer-scale S]] [--page-png "
       "N:OUT.png]",
       "the assembly guide of a plan folder: pieces laid flat, seams numbered, sew and lace",
       run_assembly},
      {"view", "view DIR",
       "write DIR/index.html: the plan in a browser (3D, seams, pieces, figures), offline",
       run_view},
      {"batch", "batch MANIFEST.csv -o DIR [--jobs N] [--threads T]",
       "a plan per manifest row, --jobs at a time; summary, resume (docs/batch.md)", run_batch},
  };
  return kVerbs;
}

const Verb* find_verb(std::string_view name) {
  for (const Verb& verb : verbs()) {
    if (verb.name == name) return &verb;
  }
  return nullptr;
}

void print_usage(std::ostream& out) {
  out << "usage: wearknit VERB [OPTIONS] [ARGS]\n"
         "       wearknit --version | --help\n\n"
         "verbs:\n";
  std::size_t width = 0;
  for (const Verb& verb : verbs()) width = std::max(width, verb.name.size());
  for (const Verb& verb : verbs()) {
    out << "  " << std::left << std::setw(static_cast<int>(width + 2)) << verb.name << verb.summary
        << '\n';
  }
  out << "\n'wearknit VERB --help' shows a verb's options and defaults.\n"
         "Exit codes: 0 success, 1 invalid input or failed job, 2 usage or I/O error.\n";
}

std::optional<int> parse_options(const std::vector<std::string>& args, const Verb& verb,
                                 po::options_description& options,
                                 const po::positional_options_description& positional,
                                 po::variables_map& values, Context& context) {
  options.add_options()("help,h", "show this help");
  try {
    po::store(po::command_line_parser(args).options(options).positional(positional).run(), values);
    if (values.count("help") != 0) {
      context.out << "usage: wearknit " << verb.synopsis << "\n\n"
                  << verb.summary << "\n\n"
                  << options;
      return kExitOk;
    }
    po::notify(values);
  } catch (const po::error& e) {
    context.err << "wearknit " << verb.name << ": " << e.what() << "\n"
                << "usage: wearknit " << verb.synopsis << "\n"
                << "'wearknit " << verb.name << " --help' lists the options.\n";
    return kExitUsage;
  }
  return std::nullopt;
}

std::optional<DiagnosticFormat> parse_diagnostic_format(std::string_view name) {
  if (name == "text") return DiagnosticFormat::Text;
  if (name == "json") return DiagnosticFormat::Json;
  if (name == "junit") return DiagnosticFormat::Junit;
  if (name == "github") return DiagnosticFormat::Github;
  return std::nullopt;
}

std::optional<DiagnosticFormat> text_or_json_format(const po::variables_map& values,
                                                    const std::string& format_name,
                                                    std::string_view verb_name, Context& context) {
  auto format = parse_diagnostic_format(values.count("json") != 0 ? "json" : format_name);
  if (!format || *format == DiagnosticFormat::Junit || *format == DiagnosticFormat::Github) {
    context.err << "wearknit " << verb_name << ": --format takes text or json, not '" << format_name
                << "'\n";
    return std::nullopt;
  }
  return format;
}

void print_diagnostics(Context& context, const std::vector<knitout::Diagnostic>& diagnostics,
                       DiagnosticFormat format) {
  switch (format) {
    case DiagnosticFormat::Json:
      knitout::print_json(context.out, diagnostics);
      return;
    case DiagnosticFormat::Text:
    default:
      knitout::print_text(context.err, diagnostics);
      return;
  }
}

std::optional<std::string> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace wearknit::cli
