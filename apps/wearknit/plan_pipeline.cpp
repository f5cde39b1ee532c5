#include "apps/wearknit/plan_pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "knitout/output_file.hpp"
#include "planner/assembly/assembly.hpp"
#include "planner/mesh/mesh_io.hpp"

namespace wearknit::cli {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

// ---------------------------------------------------------------- stages

enum class StageState { Pending, Running, Done, Failed };

struct StageRecord {
  std::string name;    // "cut", "wearability", ...
  std::string branch;  // "main", "wear" or "knit"
  StageState state = StageState::Pending;
  int exit_code = -1;
  double seconds = 0;
  Clock::time_point start;
  std::string out;  // what the verb printed
  std::string err;
};

// The stage list and the progress display. On a terminal (and without
// --quiet) one status line is redrawn a few times a second and a line is
// printed as each stage ends; otherwise nothing is shown while the plan runs.
class StageBoard {
 public:
  StageBoard(Context& context, bool live) : context_(context), live_(live) {}
  ~StageBoard() { stop(); }

  std::size_t add(const std::string& name, const std::string& branch) {
    std::lock_guard lock(mutex_);
    StageRecord record;
    record.name = name;
    record.branch = branch;
    stages_.push_back(std::move(record));
    return stages_.size() - 1;
  }

  void start_display() {
    if (!live_) return;
    ticker_ = std::thread([this] {
      std::unique_lock lock(mutex_);
      while (!stopping_) {
        draw_locked();
        wake_.wait_for(lock, std::chrono::milliseconds(250));
      }
    });
  }

  void stop() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (ticker_.joinable()) ticker_.join();
    std::lock_guard lock(mutex_);
    if (live_ && line_shown_) {
      context_.out << "\r\033[K" << std::flush;
      line_shown_ = false;
    }
  }

  void begin(std::size_t id) {
    std::lock_guard lock(mutex_);
    stages_[id].state = StageState::Running;
    stages_[id].start = Clock::now();
  }

  void end(std::size_t id, int exit_code, std::string out, std::string err) {
    std::lock_guard lock(mutex_);
    StageRecord& s = stages_[id];
    s.seconds = seconds_since(s.start);
    s.exit_code = exit_code;
    s.state = exit_code == kExitOk ? StageState::Done : StageState::Failed;
    s.out = std::move(out);
    s.err = std::move(err);
    if (live_) {
      context_.out << "\r\033[K" << std::left << std::setw(22) << s.name
                   << (s.state == StageState::Done ? "done   " : "FAILED ") << std::right
                   << std::fixed << std::setprecision(1) << std::setw(7) << s.seconds << " s\n";
      line_shown_ = false;
      draw_locked();
    }
  }

  // Runs `verb` as stage `id` with a Context of its own.
  int run(std::size_t id, VerbFunction verb, const std::vector<std::string>& args) {
    begin(id);
    std::ostringstream out, err;
    Context stage_context{out, err, false};
    int code = kExitUsage;
    try {
      code = verb(args, stage_context);
    } catch (const std::exception& e) {
      err << "internal error: " << e.what() << '\n';
      code = kExitUsage;
    }
    end(id, code, out.str(), err.str());
    return code;
  }

  // Stage messages name the plan folder, not the staging folder they ran in.
  void rename_paths(const std::string& from, const std::string& to) {
    std::lock_guard lock(mutex_);
    for (StageRecord& s : stages_) {
      for (std::string* text : {&s.out, &s.err}) {
        for (std::size_t at = text->find(from); at != std::string::npos;
             at = text->find(from, at + to.size()))
          text->replace(at, from.size(), to);
      }
    }
  }

  std::vector<StageRecord> snapshot() const {
    std::lock_guard lock(mutex_);
    return stages_;
  }

 private:
  void draw_locked() {
    if (!live_) return;
    std::ostringstream line;
    line << "plan:";
    for (const StageRecord& s : stages_) {
      if (s.state != StageState::Running) continue;
      line << "  " << s.name << ' ' << std::fixed << std::setprecision(0) << seconds_since(s.start)
           << " s...";
    }
    context_.out << "\r\033[K" << line.str() << std::flush;
    line_shown_ = true;
  }

  Context& context_;
  bool live_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::thread ticker_;
  bool stopping_ = false;
  bool line_shown_ = false;
  std::vector<StageRecord> stages_;
};

// ---------------------------------------------------------------- files

// A JSON object from `path`: empty when absent or not an object.
json read_object(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return json::object();
  json value = json::parse(in, nullptr, false);
  return value.is_object() ? value : json::object();
}

std::string write_text(const fs::path& path, const std::string& text) {
  return knitout::write_file_atomically(path.string(), [&](std::ostream& out) { out << text; });
}

// The wearability stage's record of its tests: it lives in the plan folder
// itself, outside the staging folders (which every plan empties), so a plan
// cut short resumes its wearability stage; the stage deletes it when done.
constexpr const char* kJournal = "wearability.journal";

// Copies the regular files at the top of `from` (not its folders, not the
// journal) into `to`, which is made empty first.
std::string make_staging(const fs::path& from, const fs::path& to) {
  std::error_code ec;
  fs::remove_all(to, ec);
  fs::create_directories(to, ec);
  if (ec) return to.string() + ": cannot create folder: " + ec.message();
  for (const auto& entry : fs::directory_iterator(from, ec)) {
    if (!entry.is_regular_file() || entry.path().filename() == kJournal) continue;
    fs::copy_file(entry.path(), to / entry.path().filename(), ec);
    if (ec) return entry.path().string() + ": cannot copy: " + ec.message();
  }
  return ec ? from.string() + ": " + ec.message() : "";
}

// Puts every file under `staging` that is new or differs from its namesake
// under `dir` into `dir` (atomically, one by one), except the JSON files the
// plan merges itself. A "pieces" folder replaces the old one as a whole.
std::string take_files(const fs::path& staging, const fs::path& dir) {
  std::error_code ec;
  if (fs::is_directory(staging / "pieces")) {
    fs::remove_all(dir / "pieces", ec);
    fs::create_directories(dir / "pieces", ec);
    if (ec) return (dir / "pieces").string() + ": " + ec.message();
  }
  for (auto it = fs::recursive_directory_iterator(staging, ec);
       !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (!it->is_regular_file()) continue;
    const fs::path relative = fs::relative(it->path(), staging);
    if (relative == "cuts.json" || relative == "report.json") continue;
    const auto bytes = slurp(it->path());
    if (!bytes) return it->path().string() + ": cannot read";
    if (slurp(dir / relative) == bytes) continue;
    fs::create_directories((dir / relative).parent_path(), ec);
    if (ec) return (dir / relative).parent_path().string() + ": " + ec.message();
    if (auto failure = write_text(dir / relative, *bytes); !failure.empty()) return failure;
  }
  return ec ? staging.string() + ": " + ec.message() : "";
}

// Sets in `merged` every top-level member that `after` changed or added
// relative to `before`.
void apply_changes(json& merged, const json& before, const json& after) {
  for (const auto& [key, value] : after.items()) {
    if (!before.contains(key) || before.at(key) != value) merged[key] = value;
  }
}

std::string format_seconds(double seconds) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(seconds < 10 ? 2 : 1) << seconds << " s";
  return text.str();
}

// The first non-empty line of a stage's error text, else of its output.
std::string first_line(const StageRecord& s) {
  for (const std::string* text : {&s.err, &s.out}) {
    std::istringstream lines(*text);
    std::string line;
    while (std::getline(lines, line)) {
      if (!line.empty()) return line;
    }
  }
  return "";
}

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
  args.insert(args.end(), more.begin(), more.end());
  return args;
}

}  // namespace

int run_plan_pipeline(const PlanOptions& options, Context& context) {
  const auto plan_start = Clock::now();
  const fs::path dir(options.dir);
  const auto mm_per_unit = planner::mm_per_unit(options.units);
  if (!mm_per_unit) {
    context.err << "wearknit plan: --units takes mm, cm or m, not '" << options.units << "'\n";
    return kExitUsage;
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    context.err << "wearknit plan: " << options.dir
                << ": cannot create folder: " << (ec ? ec.message() : "not a folder") << '\n';
    return kExitUsage;
  }
  const std::string seed = std::to_string(options.seed);
  const bool live = context.out_is_terminal && !options.quiet;
  StageBoard board(context, live);
  const std::size_t cut_id = board.add("cut", "main");
  const std::size_t wear_id = board.add("wearability", "wear");
  const std::size_t stitch_id = board.add("stitch-mesh", "knit");
  const std::size_t schedule_id = board.add("schedule", "knit");
  board.start_display();

  // Says which stage failed and what it printed, and where the outputs of
  // the stages that finished are.
  auto fail = [&](const std::vector<std::size_t>& failed) {
    board.stop();
    const auto stages = board.snapshot();
    for (std::size_t id : failed) {
      const StageRecord& s = stages[id];
      context.err << "wearknit plan: the " << s.name << " stage failed (exit " << s.exit_code << ")"
                  << (s.err.empty() && s.out.empty() ? "" : ":") << '\n';
      std::istringstream lines(s.err.empty() ? s.out : s.err);
      for (std::string line; std::getline(lines, line);) context.err << "  " << line << '\n';
    }
    std::vector<std::string> finished;
    for (const StageRecord& s : stages) {
      if (s.state == StageState::Done) finished.push_back(s.name);
    }
    if (finished.empty()) {
      context.err << "wearknit plan: no stage finished\n";
    } else {
      context.err << "wearknit plan: the outputs of ";
      for (std::size_t i = 0; i < finished.size(); ++i)
        context.err << (i ? ", " : "") << finished[i];
      context.err << " are in " << options.dir << '\n';
    }
    return kExitInvalid;
  };

  // ---- cut (and the wearer, scaled as the garment) ----
  double scale = options.scale;
  const fs::path wearer_path = dir / "wearer.obj";
  {
    board.begin(cut_id);
    knitout::DiagnosticSink sink;
    std::ostringstream err;
    if (options.size_mm > 0) {
      // Scale so the garment's longest side is size_mm.
      if (auto garment = planner::load_mesh(options.garment, {*mm_per_unit, 1.0}, sink)) {
        const double longest = planner::bounding_box_size(*garment).maxCoeff();
        if (longest > 0) scale = options.size_mm / longest;
      }
    }
    std::optional<planner::PolygonMesh> wearer;
    if (!sink.has_errors())
      wearer = planner::load_mesh(options.wearer, {*mm_per_unit, scale}, sink);
    knitout::print_text(err, sink.diagnostics());
    if (!wearer) {
      board.end(cut_id, kExitInvalid, "", err.str());
      return fail({cut_id});
    }
    std::ostringstream scale_text;
    scale_text << std::setprecision(17) << scale;
    std::vector<std::string> args = {options.garment, "-o",      options.dir,
                                     "--seed",        seed,      "--units",
                                     options.units,   "--scale", scale_text.str()};
    if (!options.pictures) args.push_back("--no-pictures");
    std::ostringstream out;
    Context stage_context{out, err, false};
    int code = kExitUsage;
    try {
      code = run_cut(with(args, options.cut_args), stage_context);
    } catch (const std::exception& e) {
      err << "internal error: " << e.what() << '\n';
    }
    if (code == kExitOk) {
      const std::string failure =
          knitout::write_file_atomically(wearer_path.string(), [&](std::ostream& o) {
            planner::write_obj(o, *wearer,
                               "the wearer " + options.wearer + ", in mm as the garment");
          });
      if (!failure.empty()) {
        err << failure << '\n';
        code = kExitUsage;
      }
    }
    board.end(cut_id, code, out.str(), err.str());
    if (code != kExitOk) return fail({cut_id});
  }

  // ---- wearability ∥ stitch mesh → schedule, each in a staging copy ----
  const fs::path wear_dir = dir / ".plan-wear";
  const fs::path knit_dir = dir / ".plan-knit";
  std::string failure = make_staging(dir, wear_dir);
  if (failure.empty()) failure = make_staging(dir, knit_dir);
  if (!failure.empty()) {
    board.stop();
    context.err << "wearknit plan: " << failure << '\n';
    return kExitUsage;
  }
  const json cut_cuts = read_object(dir / "cuts.json");
  const json cut_report = read_object(dir / "report.json");
  const auto cut_mesh_bytes = slurp(dir / "cut-mesh.obj");

  const std::vector<std::string> wear_args =
      with({wear_dir.string(), "--wearer", wearer_path.string(), "--seed", seed, "--journal",
            (dir / kJournal).string()},
           options.wearability_args);
  std::vector<std::string> stitch_args = {knit_dir.string()};
  if (!options.pictures) stitch_args.push_back("--no-picture");
  stitch_args = with(stitch_args, options.stitch_mesh_args);
  const std::vector<std::string> schedule_args =
      with({knit_dir.string(), "--seed", seed}, options.schedule_args);
  auto knit_branch = [&](std::size_t stitch, std::size_t schedule) {
    if (board.run(stitch, run_stitch_mesh, stitch_args) == kExitOk)
      board.run(schedule, run_schedule, schedule_args);
  };

  // Fig. 2: the wearability test runs beside stitch meshing and scheduling.
  std::thread wear_thread([&] { board.run(wear_id, run_wearability, wear_args); });
  knit_branch(stitch_id, schedule_id);
  wear_thread.join();

  auto stages = board.snapshot();
  const bool wear_ok = stages[wear_id].exit_code == kExitOk;
  // The wearability stage re-cuts the proxy when the fully open garment does
  // not come off (§5); what the knit branch made from the old cut is stale.
  const bool recut = slurp(wear_dir / "cut-mesh.obj") != cut_mesh_bytes ||
                     read_object(wear_dir / "cuts.json")
                         .value("wearability", json::object())
                         .value("recut", false);
  std::size_t final_stitch = stitch_id, final_schedule = schedule_id;
  json knit_start_cuts = cut_cuts, knit_start_report = cut_report;
  if (wear_ok && recut) {
    failure = make_staging(wear_dir, knit_dir);
    if (!failure.empty()) {
      board.stop();
      context.err << "wearknit plan: " << failure << '\n';
      return kExitUsage;
    }
    knit_start_cuts = read_object(knit_dir / "cuts.json");
    knit_start_report = read_object(knit_dir / "report.json");
    final_stitch = board.add("stitch-mesh (re-cut)", "knit");
    final_schedule = board.add("schedule (re-cut)", "knit");
    knit_branch(final_stitch, final_schedule);
    stages = board.snapshot();
  }
  board.rename_paths(wear_dir.string(), options.dir);
  board.rename_paths(knit_dir.string(), options.dir);
  const bool stitch_ok = stages[final_stitch].exit_code == kExitOk;
  const bool schedule_ok = stages[final_schedule].exit_code == kExitOk;

  // ---- merge the branches into DIR ----
  json cuts = cut_cuts, report = cut_report;
  if (wear_ok) {
    failure = take_files(wear_dir, dir);
    cuts = read_object(wear_dir / "cuts.json");
    report = read_object(wear_dir / "report.json");
  }
  if (failure.empty() && stitch_ok) {
    if (!schedule_ok) fs::remove_all(knit_dir / "pieces", ec);
    failure = take_files(knit_dir, dir);
    apply_changes(cuts, knit_start_cuts, read_object(knit_dir / "cuts.json"));
    apply_changes(report, knit_start_report, read_object(knit_dir / "report.json"));
  }

  std::vector<std::size_t> failed;
  for (std::size_t id : {wear_id, final_stitch, final_schedule}) {
    if (board.snapshot()[id].state == StageState::Failed) failed.push_back(id);
  }

  // ---- the assembly guide and the machine, once every piece is there ----
  json sent = json::array();
  if (failure.empty() && failed.empty()) {
    // Written before the guide is drawn: the guide reads the merged folder.
    failure = write_text(dir / "cuts.json", cuts.dump(2) + '\n');
    if (failure.empty()) failure = write_text(dir / "report.json", report.dump(2) + '\n');
  }
  if (failure.empty() && failed.empty()) {
    // Stage 6 of DESIGN.md: the pieces with every seam numbered, sew or lace.
    const std::size_t assembly_id = board.add("assembly", "main");
    board.begin(assembly_id);
    planner::AssemblySummary guide;
    std::string guide_failure;
    try {
      guide_failure = planner::write_assembly_guide(dir, wearer_path.string(), &guide);
    } catch (const std::exception& e) {
      guide_failure = std::string("internal error: ") + e.what();
    }
    std::ostringstream out;
    if (guide_failure.empty()) {
      out << "assembly guide: " << guide.pieces << " piece" << (guide.pieces == 1 ? "" : "s")
          << ", " << guide.seams << " seams (" << guide.sewn << " sew, " << guide.laced
          << " lace), " << guide.pdf_pages << " pages: assembly.svg, assembly.pdf, "
          << "assembly-3d.png\n";
    }
    board.end(assembly_id, guide_failure.empty() ? kExitOk : kExitInvalid, out.str(),
              guide_failure.empty() ? "" : guide_failure + "\n");
    if (!guide_failure.empty()) failed.push_back(assembly_id);
  }
  if (failure.empty() && failed.empty() && !options.send_uri.empty()) {
    const std::size_t send_id = board.add("send", "main");
    board.begin(send_id);
    std::ostringstream out, err;
    int code = kExitOk;
    for (const json& piece : report["schedule"].value("pieces", json::array())) {
      const std::string job = (dir / piece.value("dat", std::string())).string();
      std::ostringstream piece_out, piece_err;
      Context send_context{piece_out, piece_err, false};
      const int piece_code = run_send({job, "--to", options.send_uri, "--quiet"}, send_context);
      out << piece_out.str();
      err << piece_err.str();
      std::string message = piece_code == kExitOk ? piece_out.str() : piece_err.str();
      if (!message.empty() && message.back() == '\n') message.pop_back();
      sent.push_back({{"piece", piece.value("name", std::string())},
                      {"job", piece.value("dat", std::string())},
                      {"to", options.send_uri},
                      {"exit", piece_code},
                      {"message", message}});
      if (piece_code != kExitOk) {
        code = kExitInvalid;
        break;  // one job after another: do not knit the next while one failed
      }
    }
    board.end(send_id, code, out.str(), err.str());
    if (code != kExitOk) failed.push_back(send_id);
  }

  // The plan's own record: every stage's exit and time, the figures that
  // sum up the result.
  const double total = seconds_since(plan_start);
  json stage_list = json::array();
  for (const StageRecord& s : board.snapshot()) {
    if (s.state == StageState::Pending) continue;
    stage_list.push_back({{"name", s.name},
                          {"branch", s.branch},
                          {"exit", s.exit_code},
                          {"time_s", s.seconds},
                          {"message", first_line(s)}});
  }
  int sewn = 0, laced = 0;
  for (const json& arc : cuts.value("arcs", json::array())) {
    const json label = arc.value("label", json());
    sewn += label == "sew";
    laced += label == "lace";
  }
  json summary = {
      {"arcs", cuts.value("arcs", json::array()).size()}, {"sewn", sewn}, {"laced", laced}};
  if (report.contains("stitch_mesh"))
    summary["stitches"] = report["stitch_mesh"].value("faces", json::object()).value("total", 0);
  if (report.contains("schedule")) {
    const json& sched = report["schedule"];
    int passes = 0;
    double knit_time = 0;
    for (const json& piece : sched.value("pieces", json::array())) {
      passes += piece.value("passes", 0);
      knit_time += piece.value("estimated_knit_time_s", 0.0);
    }
    summary["pieces"] = sched.value("pieces", json::array()).size();
    summary["schedule_cuts"] = sched.value("cuts", 0);
    summary["wale_seams"] = sched.value("wale_seams", 0);
    summary["passes"] = passes;
    summary["estimated_knit_time_s"] = knit_time;
  }
  report["plan"] = {{"garment", options.garment},
                    {"wearer", options.wearer},
                    {"seed", options.seed},
                    {"units", options.units},
                    {"scale", scale},
                    {"recut", recut},
                    {"stitch_mesh_redone", wear_ok && recut},
                    {"stages", stage_list},
                    {"summary", summary},
                    {"total_s", total}};
  if (!sent.empty()) report["plan"]["sent"] = sent;
  if (failure.empty()) failure = write_text(dir / "cuts.json", cuts.dump(2) + '\n');
  if (failure.empty()) failure = write_text(dir / "report.json", report.dump(2) + '\n');
  std::ostringstream log;
  for (const StageRecord& s : board.snapshot()) {
    if (s.state == StageState::Pending) continue;
    log << "== " << s.name << " (exit " << s.exit_code << ", " << format_seconds(s.seconds) << ")\n"
        << s.out << s.err;
  }
  if (failure.empty()) failure = write_text(dir / "plan.log", log.str());
  fs::remove_all(wear_dir, ec);
  fs::remove_all(knit_dir, ec);
  if (!failure.empty()) {
    board.stop();
    context.err << "wearknit plan: " << failure << '\n';
    return kExitUsage;
  }
  if (!failed.empty()) return fail(failed);
  board.stop();

  if (!options.quiet) {
    context.out << "plan: " << options.garment << " on " << options.wearer << " -> " << options.dir
                << "/\n";
    for (const StageRecord& s : board.snapshot()) {
      if (s.state == StageState::Pending) continue;
      context.out << "  " << std::left << std::setw(22) << s.name << std::right << std::setw(9)
                  << format_seconds(s.seconds) << "  " << first_line(s) << '\n';
    }
    context.out << "  " << std::left << std::setw(22) << "total" << std::right << std::setw(9)
                << format_seconds(total) << "  " << summary.value("pieces", 0) << " piece"
                << (summary.value("pieces", 0) == 1 ? "" : "s") << ", "
                << summary.value("stitches", 0) << " stitches, " << sewn << " arcs sewn, " << laced
                << " laced, " << summary.value("passes", 0) << " passes, about "
                << static_cast<int>(summary.value("estimated_knit_time_s", 0.0) / 60 + 0.5)
                << " min on the machine\n";
  }
  return kExitOk;
}

}  // namespace wearknit::cli
