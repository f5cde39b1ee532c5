// wearknit schedule: the flat-sheet scheduler (paper §7) on a plan folder's
// stitch-mesh.smobj; every piece is run through the needle-bed VM, then
// pieces/piece-N.k and its bed view pieces/piece-N.svg are written, the
// scheduling cuts go into cuts.json and the figures (time estimates from the
// VM) into report.json (both merged with what is there).
#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "apps/wearknit/cli.hpp"
#include "backends/dat/passes.hpp"
#include "backends/dat/raster.hpp"
#include "knitout/output_file.hpp"
#include "knitout/parser.hpp"
#include "planner/schedule/knitout_emit.hpp"
#include "planner/schedule/piece_layout.hpp"
#include "planner/schedule/schedule.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "simulators/bed/bed_view.hpp"
#include "simulators/bed/machine.hpp"
#include "simulators/bed/profile.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Reads a JSON object from `path`; an absent file gives an empty object, a
// file that is not a JSON object gives nullopt (it is left alone).
std::optional<json> read_object(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return json::object();
  json value = json::parse(in, nullptr, false);
  if (value.is_discarded() || !value.is_object()) return std::nullopt;
  return value;
}

// Removes the files of pieces numbered above `count` (piece-N.k, .dat, .svg,
// .layout.json) that an earlier run making more pieces left in `dir`, so the
// folder holds exactly this schedule's pieces and nobody sends a stale one.
// Other files are left alone. Returns an error message, or "".
std::string remove_stale_pieces(const fs::path& dir, std::size_t count) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("piece-", 0) != 0) continue;
    std::size_t end = 6;
    while (end < name.size() && end < 15 && std::isdigit(static_cast<unsigned char>(name[end])))
      ++end;
    const std::string kind = name.substr(end);
    if (end == 6 || (kind != ".k" && kind != ".dat" && kind != ".svg" && kind != ".layout.json"))
      continue;
    if (std::stoul(name.substr(6, end - 6)) > count) stale.push_back(entry.path());
  }
  if (ec) return dir.string() + ": " + ec.message();
  for (const fs::path& path : stale) {
    fs::remove(path, ec);
    if (ec) return path.string() + ": cannot remove a piece of an earlier run: " + ec.message();
  }
  return {};
}

}  // namespace

int run_schedule(const std::vector<std::string>& args, Context& context) {
  std::string dir;
  int trials = 100;
  double time_budget = 0;
  std::string pattern_name = "plain";
  std::uint64_t seed = 1;
  int threads = 0;
  int max_shift = planner::kMaxPatchShift;
  int max_aside = planner::kMaxAside;
  int improve = planner::ScheduleParams{}.improve;
  std::string format_name;
  po::options_description options("options");
  options.add_options()("dir", po::value<std::string>(&dir)->required(),
                        "plan folder holding stitch-mesh.smobj")(
      "trials", po::value<int>(&trials)->default_value(100),
      "random knitting orders to try (§7.3)")(
      "time-budget", po::value<double>(&time_budget),
      "seconds to spend trying orders instead of a number of trials")(
      "pattern", po::value<std::string>(&pattern_name)->default_value("plain"),
      "stitch pattern: plain or seed")("seed", po::value<std::uint64_t>(&seed)->default_value(1),
                                       "random seed")(
      "threads", po::value<int>(&threads)->default_value(0),
      "threads for the trials (0: all cores); results depend only on the seed and trials")(
      "max-shift", po::value<int>(&max_shift)->default_value(planner::kMaxPatchShift),
      "needles a patch may be moved sideways to clear held loops (0 to 8)")(
      "max-aside", po::value<int>(&max_aside)->default_value(planner::kMaxAside),
      "needles loops held for a later row may be moved out of a patch's way (0 to 8)")(
      "improve", po::value<int>(&improve)->default_value(improve),
      "best random orders refined by a local search that moves the patches of each cut "
      "(0: random orders only, as in §7.3)")(
      "format", po::value<std::string>(&format_name)->default_value("text"),
      "diagnostics as text (stderr) or json (stdout)")("json", "same as --format json")(
      "quiet,q", "print nothing on success");
  po::positional_options_description positional;
  positional.add("dir", 1);
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("schedule"), options, positional, values, context)) {
    return *code;
  }
  const auto format = text_or_json_format(values, format_name, "schedule", context);
  if (!format) return kExitUsage;
  if (values.count("time-budget") && !values["trials"].defaulted()) {
    context.err << "wearknit schedule: give --trials or --time-budget, not both\n";
    return kExitUsage;
  }
  if (values.count("time-budget") && !(time_budget > 0)) {
    context.err << "wearknit schedule: --time-budget must be more than 0 seconds\n";
    return kExitUsage;
  }
  if (trials < 1) {
    context.err << "wearknit schedule: --trials must be at least 1\n";
    return kExitUsage;
  }
  if (improve < 0) {
    context.err << "wearknit schedule: --improve must not be negative\n";
    return kExitUsage;
  }
  if (max_shift < 0 || max_shift > 8) {
    context.err << "wearknit schedule: --max-shift takes 0 to 8 (the racking limit)\n";
    return kExitUsage;
  }
  if (max_aside < 0 || max_aside > 8) {
    context.err << "wearknit schedule: --max-aside takes 0 to 8 (the racking limit)\n";
    return kExitUsage;
  }
  planner::EmitParams emit;
  if (pattern_name == "seed") {
    emit.pattern = planner::StitchPattern::Seed;
  } else if (pattern_name != "plain") {
    context.err << "wearknit schedule: --pattern takes plain or seed, not '" << pattern_name
                << "'\n";
    return kExitUsage;
  }

  const auto start = std::chrono::steady_clock::now();
  const fs::path folder(dir);
  const std::string smobj = (folder / "stitch-mesh.smobj").string();
  if (!fs::is_directory(folder)) {
    context.err << dir << ": error: not a folder\n";
    return kExitUsage;
  }
  knitout::DiagnosticSink sink;
  // The stitch stage's own reader (planner/stitch_mesh/stitch_mesh.hpp): the scheduler
  // reads exactly what `wearknit stitch-mesh` writes, cut-arcs included.
  std::ifstream smobj_in(smobj, std::ios::binary);
  if (!smobj_in) {
    sink.error(smobj, 0, 0, "S900", "cannot open the stitch mesh");
    print_diagnostics(context, sink.diagnostics(), *format);
    return kExitUsage;
  }
  const std::optional<planner::StitchMesh> read = planner::parse_smobj(smobj_in, smobj, sink);
  if (!read) {
    print_diagnostics(context, sink.diagnostics(), *format);
    return kExitInvalid;
  }
  const planner::StitchMesh& mesh = *read;
  planner::ScheduleParams params;
  params.trials = trials;
  params.time_budget_s = values.count("time-budget") ? time_budget : 0;
  params.seed = seed;
  params.threads = threads;
  params.max_patch_shift = max_shift;
  params.max_aside = max_aside;
  params.improve = improve;
  planner::Schedule schedule;
  std::vector<planner::EmittedPiece> pieces;
  try {
    schedule = planner::schedule(mesh, params);
    for (std::size_t p = 0; p < schedule.pieces.size(); ++p) {
      pieces.push_back(planner::emit_piece(mesh, schedule, p, emit));
    }
  } catch (const planner::ScheduleError& e) {
    sink.error(smobj, 0, 0, "S910", e.what());
    print_diagnostics(context, sink.diagnostics(), *format);
    return kExitInvalid;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // Every piece runs through the needle-bed VM before anything is written:
  // an error there is a bug of the scheduler, never the user's.
  struct Judged {
    bed::Stats stats;
    std::size_t warnings = 0;
    bed::BedView view;
    std::unique_ptr<knitout::Program> program;
    std::unique_ptr<knitout::DiagnosticSink> sink;
    std::unique_ptr<bed::Machine> machine;
  };
  std::vector<Judged> judged(pieces.size());
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    Judged& j = judged[p];
    const std::string name = "piece-" + std::to_string(p + 1) + ".k";
    j.sink = std::make_unique<knitout::DiagnosticSink>();
    j.program =
        std::make_unique<knitout::Program>(knitout::parse_string(pieces[p].knitout, name, *j.sink));
    std::optional<std::size_t> header_carriers;
    if (auto carriers = j.program->header("Carriers")) {
      std::istringstream names{std::string(*carriers)};
      std::string word;
      std::size_t n = 0;
      while (names >> word) ++n;
      header_carriers = n;
    }
    bed::MachineOptions machine_options;
    machine_options.observer = &j.view;
    j.machine =
        std::make_unique<bed::Machine>(bed::default_profile(), *j.sink, name, j.program->carriers,
                                       header_carriers, machine_options);
    j.machine->check_headers(j.program->headers);
    for (const knitout::Instruction& instruction : j.program->instructions)
      j.machine->step(instruction);
    j.machine->finish(static_cast<std::uint32_t>(pieces[p].stats.lines));
    if (j.sink->has_errors()) {
      context.err << "wearknit schedule: internal error: the needle-bed VM rejects " << name
                  << ":\n";
      knitout::print_text(context.err, j.sink->sorted());
      return kExitUsage;
    }
    j.stats = j.machine->stats();
    j.warnings = j.sink->warning_count();
  }

  // Pieces.
  std::error_code ec;
  fs::create_directories(folder / "pieces", ec);
  if (ec) {
    context.err << (folder / "pieces").string() << ": error: " << ec.message() << '\n';
    return kExitUsage;
  }
  json piece_list = json::array();
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const std::string name = "piece-" + std::to_string(p + 1);
    const std::string path = (folder / "pieces" / (name + ".k")).string();
    const std::string failure =
        knitout::write_file_atomically(path, [&](std::ostream& out) { out << pieces[p].knitout; });
    if (!failure.empty()) {
      context.err << "wearknit schedule: " << failure << '\n';
      return kExitUsage;
    }
    // The DAT the Shima machine takes (issue: pieces/NAME.dat). A piece the
    // DAT backend refuses is a scheduler bug, like a VM error above.
    knitout::DiagnosticSink dat_sink;
    std::optional<std::vector<std::uint8_t>> dat_bytes;
    if (auto passes = dat::form_passes(*judged[p].program, name + ".k", dat_sink)) {
      dat_bytes = dat::write_dat(*passes, dat_sink);
    }
    if (!dat_bytes) {
      context.err << "wearknit schedule: internal error: the DAT backend rejects " << name
                  << ".k:\n";
      knitout::print_text(context.err, dat_sink.sorted());
      return kExitUsage;
    }
    const std::string dat_path = (folder / "pieces" / (name + ".dat")).string();
    const std::string dat_failure =
        knitout::write_file_atomically(dat_path, [&](std::ostream& out) {
          out.write(reinterpret_cast<const char*>(dat_bytes->data()),
                    static_cast<std::streamsize>(dat_bytes->size()));
        });
    if (!dat_failure.empty()) {
      context.err << "wearknit schedule: " << dat_failure << '\n';
      return kExitUsage;
    }
    const std::string view_path = (folder / "pieces" / (name + ".svg")).string();
    const std::string view_failure =
        judged[p].view.write(view_path, *judged[p].machine, name + ".k");
    if (!view_failure.empty()) {
      context.err << "wearknit schedule: " << view_failure << '\n';
      return kExitUsage;
    }
    const planner::PieceStats& st = pieces[p].stats;
    std::size_t faces = 0;
    for (int r : schedule.pieces[p].rows)
      faces += schedule.rows[static_cast<std::size_t>(r)].faces.size();
    piece_list.push_back({{"name", name},
                          {"knitout", "pieces/" + name + ".k"},
                          {"dat", "pieces/" + name + ".dat"},
                          {"rows", st.rows},
                          {"stitches", faces},
                          {"passes", st.passes},
                          {"knit_passes", st.knit_passes},
                          {"transfer_passes", st.transfer_passes},
                          {"transfers", st.transfers},
                          {"racks", st.racks},
                          {"width_needles", st.width_needles},
                          {"yarn_ins", st.yarn_ins},
                          {"lines", st.lines},
                          {"bed_view", "pieces/" + name + ".svg"},
                          {"vm_warnings", judged[p].warnings},
                          {"estimated_knit_time_s", judged[p].stats.estimated_time_s},
                          {"planner_time_model_s", st.knit_time_s}});
  }

  // Each piece laid flat, for the assembly guide (planner/schedule/piece_layout.hpp).
  if (const std::string failure =
          planner::write_piece_layouts((folder / "pieces").string(), schedule);
      !failure.empty()) {
    context.err << "wearknit schedule: " << failure << '\n';
    return kExitUsage;
  }
  if (const std::string failure = remove_stale_pieces(folder / "pieces", pieces.size());
      !failure.empty()) {
    context.err << "wearknit schedule: " << failure << '\n';
    return kExitUsage;
  }

  // Cuts from scheduling: seams labelled sew (§7.3).
  json cuts = json::array();
  for (const auto& [lower, upper] : schedule.cut_rows) {
    json edges = json::array();
    for (const planner::CourseEdge& e : schedule.edges) {
      if (!e.cut) continue;
      if (schedule.face_row[static_cast<std::size_t>(e.lower)] != lower ||
          schedule.face_row[static_cast<std::size_t>(e.upper)] != upper)
        continue;
      edges.push_back({e.lower, e.upper});
    }
    cuts.push_back(
        {{"label", "sew"}, {"lower_row", lower}, {"upper_row", upper}, {"faces", edges}});
  }
  auto cuts_json = read_object(folder / "cuts.json");
  if (!cuts_json) {
    context.err << (folder / "cuts.json").string()
                << ": error: not a JSON object; the scheduling cuts cannot be added\n";
    return kExitInvalid;
  }
  (*cuts_json)["schedule_cuts"] = cuts;

  json trials_json = json::array();
  for (const planner::TrialResult& t : schedule.trials) trials_json.push_back(t.cuts);
  auto report = read_object(folder / "report.json");
  if (!report) {
    context.err << (folder / "report.json").string() << ": error: not a JSON object\n";
    return kExitInvalid;
  }
  (*report)["schedule"] = {
      {"seed", seed},
      {"pattern", pattern_name},
      {"threads", threads > 0 ? static_cast<unsigned>(threads)
                              : std::max(1u, std::thread::hardware_concurrency())},
      {"trials", schedule.trials.size()},
      {"cuts_per_trial", trials_json},
      {"best_trial", schedule.best_trial},
      {"random_cuts", schedule.random_cuts},
      {"improve", improve},
      {"cuts", schedule.cuts},
      {"max_shift", max_shift},
      {"patches_moved", std::count_if(schedule.patch_shift.begin(), schedule.patch_shift.end(),
                                      [](int shift) { return shift != 0; })},
      {"max_aside", max_aside},
      {"loops_set_aside", schedule.aside_moves.size()},
      {"rows", schedule.rows.size()},
      {"patches", schedule.patches.size()},
      {"wale_seams", schedule.wale_seams.size()},
      {"pieces", piece_list},
      {"time_s", seconds}};
  for (const auto& [name, value] :
       {std::pair{"cuts.json", &*cuts_json}, std::pair{"report.json", &*report}}) {
    const std::string failure = knitout::write_file_atomically(
        (folder / name).string(), [&](std::ostream& out) { out << value->dump(2) << '\n'; });
    if (!failure.empty()) {
      context.err << "wearknit schedule: " << failure << '\n';
      return kExitUsage;
    }
  }
  if (!values.count("quiet")) {
    double total = 0;
    for (const auto& j : judged) total += j.stats.estimated_time_s;
    context.out << smobj << ": " << mesh.faces.size() << " stitches, " << schedule.rows.size()
                << " rows, " << schedule.patches.size() << " patches; " << schedule.trials.size()
                << " orders tried, best has " << schedule.cuts << " cut"
                << (schedule.cuts == 1 ? "" : "s") << "; " << pieces.size() << " piece"
                << (pieces.size() == 1 ? "" : "s") << " in " << (folder / "pieces").string() << " ("
                << pattern_name << ", about " << static_cast<int>(total / 60 + 0.5)
                << " min on the machine)\n";
  }
  return kExitOk;
}

}  // namespace wearknit::cli
