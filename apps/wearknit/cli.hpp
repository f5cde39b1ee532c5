// The `wearknit` command line: a table of verbs, each a function from its
// arguments to an exit code. Verbs print; only main() exits.
#pragma once

#include <boost/program_options.hpp>
#include <chrono>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "devices/job.hpp"
#include "knitout/diagnostic.hpp"

namespace planner::viewer {
struct PlanPageSummary;
}

namespace wearknit::cli {

// Exit codes (docs/cli.md).
inline constexpr int kExitOk = 0;
inline constexpr int kExitInvalid = 1;  // the input is invalid, or the job failed
inline constexpr int kExitUsage = 2;    // usage or I/O error

struct Context {
  std::ostream& out;
  std::ostream& err;
  bool out_is_terminal = false;
};

using VerbFunction = int (*)(const std::vector<std::string>& args, Context& context);

struct Verb {
  std::string_view name;
  std::string_view synopsis;  // "fmt FILE.k [-o OUT.k]"
  std::string_view summary;   // one line
  VerbFunction run;
};

const std::vector<Verb>& verbs();
const Verb* find_verb(std::string_view name);
void print_usage(std::ostream& out);

// Parses `args` for a verb. Adds --help. On --help prints the verb's help
// (options with their defaults) and returns kExitOk; on a bad option prints
// the problem and the usage and returns kExitUsage; otherwise returns
// nullopt and fills `values`.
std::optional<int> parse_options(
    const std::vector<std::string>& args, const Verb& verb,
    boost::program_options::options_description& options,
    const boost::program_options::positional_options_description& positional,
    boost::program_options::variables_map& values, Context& context);

// Wall-clock seconds since `start`, for the stage timings verbs report.
inline double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The whole content of a file, or nullopt when it cannot be opened.
std::optional<std::string> slurp(const std::string& path);

// Diagnostic output formats shared by the verbs that read input.
enum class DiagnosticFormat { Text, Json, Junit, Github };
std::optional<DiagnosticFormat> parse_diagnostic_format(std::string_view name);
// For verbs whose diagnostics are text or JSON (--format text|json, --json):
// the format asked for, or nullopt after printing the usage error.
std::optional<DiagnosticFormat> text_or_json_format(
    const boost::program_options::variables_map& values, const std::string& format_name,
    std::string_view verb_name, Context& context);
// Prints diagnostics: text to `err`, json to `out` (as --json asks).
void print_diagnostics(Context& context, const std::vector<knitout::Diagnostic>& diagnostics,
                       DiagnosticFormat format);

int run_fmt(const std::vector<std::string>& args, Context& context);
int run_demo(const std::vector<std::string>& args, Context& context);
int run_validate(const std::vector<std::string>& args, Context& context);
int run_simulate(const std::vector<std::string>& args, Context& context);
int run_dat(const std::vector<std::string>& args, Context& context);
int run_dat_info(const std::vector<std::string>& args, Context& context);
int run_wearability(const std::vector<std::string>& args, Context& context);
int run_schedule(const std::vector<std::string>& args, Context& context);
int run_send(const std::vector<std::string>& args, Context& context);
// What `wearknit send JOB --to URI` does once its options are read; also
// how `wearknit plan --send` sends each piece.
struct SendFileOptions {
  bool resume = false;
  int attempts = 8;  // reconnection attempts in a row before giving up
  bool quiet = false;
};
int send_file(const std::string& job_path, const std::string& to, const SendFileOptions& options,
              Context& context);
int run_status(const std::vector<std::string>& args, Context& context);
int run_devices(const std::vector<std::string>& args, Context& context);
int run_mock_device(const std::vector<std::string>& args, Context& context);

// The checks a device runs on a received job before knitting it, made of the
// project's own readers (verb_mock_device.cpp).
devices::JobCheckers project_job_checkers();
int run_cut(const std::vector<std::string>& args, Context& context);
int run_stitch_mesh(const std::vector<std::string>& args, Context& context);
int run_plan(const std::vector<std::string>& args, Context& context);
int run_assembly(const std::vector<std::string>& args, Context& context);
int run_view(const std::vector<std::string>& args, Context& context);
int run_batch(const std::vector<std::string>& args, Context& context);
// "open: DIR/index.html  (size; pieces, seams)": the line `view`, `plan` and
// `demo` print for the plan page (planner/viewer/plan_page.hpp).
void print_page_line(const std::string& dir, const planner::viewer::PlanPageSummary& summary,
                     Context& context);

}  // namespace wearknit::cli
