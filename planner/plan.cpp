#include "planner/plan.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <mutex>
#include <ostream>
#include <sstream>
#include <thread>

#include "knitout/output_file.hpp"
#include "planner/common/json_file.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/wearability/journal.hpp"
#include "planner/wearability/wearability_io.hpp"

namespace planner {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr const char* kJournal = "wearability.journal";

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string diagnostics_text(const knitout::DiagnosticSink& sink) {
  std::ostringstream text;
  knitout::print_text(text, sink.diagnostics());
  return text.str();
}

// The first non-empty line of a stage's output, else of its error text.
std::string first_line(const StageRun& s) {
  for (const std::string* text : {&s.out, &s.err}) {
    std::istringstream lines(*text);
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty()) return line;
    }
  }
  return "";
}

// The plan's state shared by its two threads: the stages run so far, the
// observer, and the folder's summary files, all behind one lock.
class PlanRun {
 public:
  PlanRun(std::string dir, PlanObserver& observer) : dir_(std::move(dir)), observer_(observer) {}

  // Runs `body` as stage `name`: it fills the run's out and err and returns
  // its exit code. A broken invariant (std::logic_error) or any other
  // exception ends the stage as an internal error, exit 2. The folder's
  // summary is made again when the stage ends.
  int stage(const std::string& name, const std::string& branch,
            const std::function<int(StageRun&)>& body) {
    return run(reserve(name, branch), body);
  }

  // A place in the list of stages, so the list keeps the stages' order
  // whichever of two concurrent stages ends first.
  std::size_t reserve(const std::string& name, const std::string& branch) {
    std::lock_guard lock(mutex_);
    StageRun run;
    run.name = name;
    run.branch = branch;
    stages_.push_back(run);
    return stages_.size() - 1;
  }

  int run(std::size_t slot, const std::function<int(StageRun&)>& body) {
    StageRun run;
    {
      std::lock_guard lock(mutex_);
      run = stages_[slot];
      observer_.stage_started(run.name, run.branch);
    }
    const auto start = Clock::now();
    try {
      run.exit_code = body(run);
    } catch (const std::exception& e) {
      run.err += std::string("internal error: ") + e.what() + '\n';
      run.exit_code = 2;
    }
    run.seconds = seconds_since(start);
    std::lock_guard lock(mutex_);
    if (const std::string failure = write_folder_summary(dir_); !failure.empty()) {
      run.err += failure + '\n';
      if (run.exit_code == 0) run.exit_code = 2;
    }
    stages_[slot] = run;
    observer_.stage_finished(run);
    return run.exit_code;
  }

  void progress(const Progress& p) {
    std::lock_guard lock(mutex_);
    observer_.wearability_progress(p);
  }

  std::vector<StageRun> stages() const {
    std::lock_guard lock(mutex_);
    return stages_;
  }

 private:
  std::string dir_;
  PlanObserver& observer_;
  mutable std::mutex mutex_;
  std::vector<StageRun> stages_;
};

// What the cut stage hands on: the cut and the wearer as their files hold
// them.
struct CutOutput {
  Cut cut;
  PolygonMesh wearer;
  std::string wearer_path;
  double scale = 1.0;
};

int cut_stage(const PlanInputs& inputs, const PlanParams& params, const fs::path& dir,
              StageRun& run, CutOutput& output) {
  const auto start = Clock::now();
  knitout::DiagnosticSink sink;
  const auto mm = mm_per_unit(inputs.units);
  if (!mm) {
    run.err = "--units takes mm, cm or m, not '" + inputs.units + "'\n";
    return 2;
  }
  double scale = inputs.scale;
  if (inputs.size_mm > 0) {
    // Scale so the garment's longest side is size_mm.
    if (auto garment = load_mesh(inputs.garment, {*mm, 1.0}, sink)) {
      const double longest = bounding_box_size(*garment).maxCoeff();
      if (longest > 0) scale = inputs.size_mm / longest;
    }
  }
  std::optional<PolygonMesh> garment, wearer;
  if (!sink.has_errors()) garment = load_mesh(inputs.garment, {*mm, scale}, sink);
  const double load_seconds = seconds_since(start);
  if (!sink.has_errors()) wearer = load_mesh(inputs.wearer, {*mm, scale}, sink);
  run.err = diagnostics_text(sink);
  if (!garment || !wearer) {
    const bool missing =
        !fs::is_regular_file(inputs.garment) || !fs::is_regular_file(inputs.wearer);
    return missing ? 2 : 1;
  }
  Cut cut = cut_garment(*garment, params.cut);
  cut.report.input = inputs.garment;
  cut.report.units = inputs.units;
  cut.report.scale = scale;
  cut.report.load_seconds = load_seconds;
  output.wearer_path = (dir / "wearer.obj").string();
  std::string failure = write_cut(dir.string(), cut, {params.pictures, CutPictures{}.panel_px});
  if (failure.empty()) {
    failure = knitout::write_file_atomically(output.wearer_path, [&](std::ostream& out) {
      write_obj(out, *wearer, "the wearer " + inputs.wearer + ", in mm as the garment");
    });
  }
  if (!failure.empty()) {
    run.err += failure + '\n';
    return 2;
  }
  auto cut_back = read_cut(dir.string(), sink);
  auto wearer_back = read_stage_mesh(output.wearer_path, sink);
  if (!cut_back || !wearer_back) {
    run.err = diagnostics_text(sink);
    return 2;
  }
  output.cut = std::move(*cut_back);
  output.wearer = std::move(*wearer_back);
  output.scale = scale;
  run.out = describe(cut);
  return 0;
}

// The wearability stage, with its journal; a re-cut is written before the
// labels. `labelled` receives the cut the labels belong to, as written.
int wearability_stage(const CutOutput& input, const PlanParams& params, const fs::path& dir,
                      PlanRun& plan, StageRun& run, std::optional<Cut>& labelled) {
  TestJournal journal((dir / kJournal).string(), journal_context(input.wearer, params.wearability),
                      params.restart);
  if (!journal.error().empty()) {
    run.err +=
        "warning: " + journal.error() + " (the tests run, but a run cut short starts again)\n";
  } else if (journal.loaded() > 0) {
    run.out += "resuming: " + std::to_string(journal.loaded()) +
               " tests of a run cut short read from " + journal.path() + '\n';
  }
  const cloth::SignedDistanceField field = wearer_field(input.wearer, params.wearability);
  WearabilityCallbacks callbacks;
  callbacks.progress = [&](const Progress& p) { plan.progress(p); };
  callbacks.record = journal.error().empty() ? &journal : nullptr;
  const Wearability result = label_arcs(input.cut, field, params.wearability, callbacks);
  std::uint64_t labelled_id = input.cut.id;
  std::string failure;
  if (result.recut) {
    failure = write_cut(dir.string(), *result.recut, {params.pictures, CutPictures{}.panel_px},
                        &labelled_id);
    if (failure.empty()) {
      knitout::DiagnosticSink sink;
      labelled = read_cut(dir.string(), sink);
      if (!labelled) failure = diagnostics_text(sink);
    }
  }
  if (failure.empty())
    failure = write_wearability(dir.string(), result, labelled_id, params.pictures);
  if (!failure.empty()) {
    run.err += failure + '\n';
    return 2;
  }
  if (const std::string removed = journal.remove(); !removed.empty())
    run.err += "warning: " + removed + '\n';
  if (!result.wearable()) {
    run.err += (dir / "wearability.json").string() + ": error: [W020] " +
               not_wearable_message(result) + '\n';
    return 1;
  }
  if (const std::string warning = check_warning(result); !warning.empty())
    run.err += (dir / "wearability.json").string() + ": warning: [W021] " + warning + '\n';
  run.out += describe(result);
  return 0;
}

int stitch_mesh_stage(const Cut& cut, const PlanParams& params, const fs::path& dir,
                      StageRun& run) {
  knitout::DiagnosticSink sink;
  const auto outcome =
      mesh_stitches(cut, params.stitch_mesh, (dir / "cut-mesh.obj").string(), sink);
  run.err = diagnostics_text(sink);
  if (!outcome) return 1;
  if (const std::string failure = write_stitch_mesh(dir.string(), *outcome, params.pictures);
      !failure.empty()) {
    run.err += failure + '\n';
    return 2;
  }
  run.out = describe(*outcome);
  return 0;
}

int schedule_stage(const PlanParams& params, const fs::path& dir, StageRun& run) {
  knitout::DiagnosticSink sink;
  const auto stitches = read_stitch_mesh(dir.string(), sink);
  std::optional<ScheduleOutcome> outcome;
  const std::string smobj = (dir / "stitch-mesh.smobj").string();
  if (stitches) outcome = schedule_stitches(*stitches, params.schedule, smobj, sink);
  run.err = diagnostics_text(sink);
  if (!outcome) return 1;
  if (const std::string failure = write_schedule(dir.string(), *outcome); !failure.empty()) {
    run.err += failure + '\n';
    return 2;
  }
  run.out = describe(*outcome, smobj, (dir / "pieces").string());
  return 0;
}

// Stitch mesh, then schedule, on `cut`; names carry `suffix`.
void knit_branch(const Cut& cut, const PlanParams& params, const fs::path& dir, PlanRun& plan,
                 const std::string& suffix) {
  const int stitched = plan.stage("stitch-mesh" + suffix, "knit", [&](StageRun& run) {
    return stitch_mesh_stage(cut, params, dir, run);
  });
  if (stitched != 0) return;
  plan.stage("schedule" + suffix, "knit",
             [&](StageRun& run) { return schedule_stage(params, dir, run); });
}

int assembly_stage(const fs::path& dir, const std::string& wearer_path, StageRun& run) {
  AssemblySummary guide;
  const std::string failure = write_assembly_guide(dir, wearer_path, &guide);
  if (!failure.empty()) {
    run.err = failure + '\n';
    return 1;
  }
  if (const std::string record = write_assembly_record(dir.string(), guide); !record.empty()) {
    run.err = record + '\n';
    return 2;
  }
  std::ostringstream out;
  out << "assembly guide: " << guide.pieces << " piece" << (guide.pieces == 1 ? "" : "s") << ", "
      << guide.seams << " seams (" << guide.sewn << " sew, " << std::lround(guide.sewn_mm)
      << " mm; " << guide.laced << " lace, " << std::lround(guide.laced_mm) << " mm), "
      << guide.pdf_pages << " page" << (guide.pdf_pages == 1 ? "" : "s")
      << ": assembly.svg, assembly.pdf, assembly-3d.png\n";
  run.out = out.str();
  return 0;
}

// The figures that sum up a plan, from its stage files.
json plan_summary(const fs::path& dir) {
  json summary = json::object();
  int sewn = 0, laced = 0, arcs = 0;
  if (const auto cut = read_json_object_if_any((dir / "cut.json").string()))
    arcs = static_cast<int>(cut->value("arcs", json::array()).size());
  if (const auto wear = read_json_object_if_any((dir / "wearability.json").string())) {
    for (const json& arc : wear->value("arcs", json::array())) {
      sewn += arc.value("label", std::string()) == "sew";
      laced += arc.value("label", std::string()) == "lace";
    }
  }
  summary = {{"arcs", arcs}, {"sewn", sewn}, {"laced", laced}};
  if (const auto stitch = read_json_object_if_any((dir / "stitch-mesh.json").string())) {
    summary["stitches"] =
        stitch->value("report", json::object()).value("faces", json::object()).value("total", 0);
  }
  if (const auto schedule = read_json_object_if_any((dir / "schedule.json").string())) {
    const json report = schedule->value("report", json::object());
    int passes = 0;
    double knit_time = 0;
    for (const json& piece : report.value("pieces", json::array())) {
      passes += piece.value("passes", 0);
      knit_time += piece.value("estimated_knit_time_s", 0.0);
    }
    summary["pieces"] = report.value("pieces", json::array()).size();
    summary["schedule_cuts"] = report.value("cuts", 0);
    summary["wale_seams"] = report.value("wale_seams", 0);
    summary["passes"] = passes;
    summary["estimated_knit_time_s"] = knit_time;
  }
  // The seams a person closes, from the assembly guide (docs/assembly.md).
  if (const auto guide = read_json_object_if_any((dir / "assembly.json").string())) {
    const json seams = guide->value("summary", json::object());
    summary["seams_sewn"] = seams.value("sewn", 0);
    summary["seams_laced"] = seams.value("laced", 0);
    summary["seams_sewn_mm"] = seams.value("sewn_mm", 0.0);
    summary["seams_laced_mm"] = seams.value("laced_mm", 0.0);
  }
  return summary;
}

std::string format_seconds(double seconds) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(seconds < 10 ? 2 : 1) << seconds << " s";
  return text.str();
}

// Each piece's DAT as schedule.json lists it, relative to the folder.
std::vector<std::string> dat_files(const fs::path& dir) {
  std::vector<std::string> files;
  if (const auto schedule = read_json_object_if_any((dir / "schedule.json").string())) {
    for (const json& piece :
         schedule->value("report", json::object()).value("pieces", json::array()))
      files.push_back(piece.value("dat", std::string()));
  }
  return files;
}

// plan.json and plan.log, then the folder's summary.
std::string write_plan_files(const fs::path& dir, const PlanResult& result) {
  std::string failure = write_json_file((dir / "plan.json").string(),
                                        {{"format", "wearknit-plan 1"}, {"plan", result.record}});
  std::ostringstream log;
  for (const StageRun& s : result.stages) {
    log << "== " << s.name << " (exit " << s.exit_code << ", " << format_seconds(s.seconds) << ")\n"
        << s.out << s.err;
  }
  if (failure.empty()) {
    failure = knitout::write_file_atomically((dir / "plan.log").string(),
                                             [&](std::ostream& out) { out << log.str(); });
  }
  if (failure.empty()) failure = write_folder_summary(dir.string());
  return failure;
}

}  // namespace

bool PlanResult::ok() const {
  for (const StageRun& s : stages) {
    if (s.exit_code != 0) return false;
  }
  return !stages.empty();
}

PlanResult run_plan(const PlanInputs& inputs, const PlanParams& params, const std::string& dir,
                    PlanObserver& observer) {
  const auto plan_start = Clock::now();
  const fs::path base(dir);
  PlanResult result;
  PlanRun plan(dir, observer);
  CutOutput cut;
  std::optional<Cut> labelled;
  json sent = json::array();
  const int cut_code = plan.stage("cut", "main", [&](StageRun& run) {
    std::error_code ec;
    fs::create_directories(base, ec);
    if (ec || !fs::is_directory(base)) {
      run.err = dir + ": cannot create folder: " + (ec ? ec.message() : "not a folder") + '\n';
      return 2;
    }
    const int code = cut_stage(inputs, params, base, run, cut);
    // Fine features refused stop the plan before the wearability stage
    // spends its minutes (the stitch-mesh stage would refuse them too).
    if (code == 0 && params.stitch_mesh.refuse_fine_features) {
      const FineFeatures fine = fine_features(cut.cut, params.stitch_mesh);
      if (!fine.parts.empty()) {
        knitout::DiagnosticSink sink;
        report_fine_features(fine, true, (base / "cut.json").string(), sink);
        run.err += diagnostics_text(sink);
        return 1;
      }
    }
    return code;
  });
  if (cut_code == 0) {
    // Fig. 2: the wearability test runs beside stitch meshing and scheduling.
    int wear_code = -1;
    const std::size_t wear_slot = plan.reserve("wearability", "wear");
    std::thread wear_thread([&] {
      wear_code = plan.run(wear_slot, [&](StageRun& run) {
        return wearability_stage(cut, params, base, plan, run, labelled);
      });
    });
    knit_branch(cut.cut, params, base, plan, "");
    wear_thread.join();
    // §5: the proxy was cut again; what the knit branch made from the old
    // cut is stale.
    result.recut = wear_code == 0 && labelled.has_value();
    if (result.recut) knit_branch(*labelled, params, base, plan, " (re-cut)");
    bool all_ok = true;
    for (const StageRun& s : plan.stages()) all_ok = all_ok && s.exit_code == 0;
    // Stage 6 of DESIGN.md: the pieces with every seam numbered, sew or lace.
    if (all_ok) {
      all_ok = plan.stage("assembly", "main", [&](StageRun& run) {
        return assembly_stage(base, cut.wearer_path, run);
      }) == 0;
    }
    if (all_ok) {
      result.dat_files = dat_files(base);
      if (params.deliver) {
        plan.stage("send", "main", [&](StageRun& run) {
          std::vector<std::string> paths;
          for (const std::string& file : result.dat_files) paths.push_back((base / file).string());
          return params.deliver(paths, run, sent);
        });
      }
    }
  }
  result.stages = plan.stages();
  result.scale = cut.scale;
  result.total_seconds = seconds_since(plan_start);
  json stages = json::array();
  for (const StageRun& s : result.stages) {
    stages.push_back({{"name", s.name},
                      {"branch", s.branch},
                      {"exit", s.exit_code},
                      {"time_s", s.seconds},
                      {"message", first_line(s)}});
  }
  result.record = {{"garment", inputs.garment},
                   {"wearer", inputs.wearer},
                   {"seed", params.cut.cut.seed},
                   {"units", inputs.units},
                   {"scale", cut.scale},
                   {"recut", result.recut},
                   {"stitch_mesh_redone", result.recut},
                   {"stages", stages},
                   {"summary", plan_summary(base)},
                   {"total_s", result.total_seconds}};
  if (!sent.empty()) result.record["sent"] = sent;
  if (fs::is_directory(base)) {
    if (const std::string failure = write_plan_files(base, result); !failure.empty()) {
      StageRun io;
      io.name = "plan files";
      io.branch = "main";
      io.exit_code = 2;
      io.err = failure + '\n';
      result.stages.push_back(io);
    }
  }
  return result;
}

std::string describe(const PlanResult& result) {
  const json summary = result.record.value("summary", json::object());
  const int pieces = summary.value("pieces", 0);
  std::ostringstream text;
  text << pieces << " piece" << (pieces == 1 ? "" : "s") << ", " << summary.value("stitches", 0)
       << " stitches, ";
  if (summary.contains("seams_sewn")) {
    text << summary.value("seams_sewn", 0) << " seams sewn ("
         << std::lround(summary.value("seams_sewn_mm", 0.0)) << " mm), "
         << summary.value("seams_laced", 0) << " laced ("
         << std::lround(summary.value("seams_laced_mm", 0.0)) << " mm), ";
  } else {
    text << summary.value("sewn", 0) << " arcs sewn, " << summary.value("laced", 0) << " laced, ";
  }
  text << summary.value("passes", 0) << " passes, about "
       << static_cast<int>(summary.value("estimated_knit_time_s", 0.0) / 60 + 0.5)
       << " min on the machine";
  return text.str();
}

}  // namespace planner
