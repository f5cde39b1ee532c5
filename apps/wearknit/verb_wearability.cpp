// wearknit wearability: which cut-arcs of a cut folder are sewn and which are
// laced (§5), by stripping the garment off the wearer in simulation.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "apps/wearknit/cli.hpp"
#include "knitout/output_file.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/wearability/journal.hpp"
#include "planner/wearability/recut.hpp"
#include "planner/wearability/wearability.hpp"
#include "planner/wearability/wearability_io.hpp"
#include "planner/wearability/wearability_picture.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

// The seed of a successful trial of the final configuration: the last sewn
// arc's test (the configuration did not change after it), else the test
// with every cut open.
std::uint64_t final_seed(const planner::EliminationResult& result) {
  const planner::TestResult* last = &result.initial;
  int position = -1;
  for (const auto& arc : result.arcs) {
    if (arc.label == planner::Label::Sew && arc.position > position) {
      position = arc.position;
      last = &arc.test;
    }
  }
  return last->trials.empty() ? 0 : last->trials.back().seed;
}

// What decides a test besides the garment, the configuration and the seed
// (which the journal's keys hold): the program itself (a changed simulation
// must not reuse old results), the wearer, and the options the simulation
// reads.
std::uint64_t journal_context(const std::string& wearer_path, const planner::WearabilityParams& p,
                              int resolution) {
  std::ostringstream text;
  const auto program = slurp("/proc/self/exe");
  const auto wearer = slurp(wearer_path);
  text << "program " << (program ? planner::fingerprint(*program) : 0) << " wearer "
       << (wearer ? planner::fingerprint(*wearer) : 0) << " trials " << p.trials << " max-steps "
       << p.cloth.max_steps << " resolution " << resolution;
  return planner::fingerprint(text.str());
}

}  // namespace

int run_wearability(const std::vector<std::string>& args, Context& context) {
  std::string dir, wearer_path, frames_dir, journal_path;
  planner::WearabilityParams params;
  int runs = 1, frame_every = 10, resolution = cloth::SdfParams{}.resolution;
  planner::RecutParams recut;
  std::uint64_t seed = 1;
  po::options_description options("options");
  options.add_options()("dir", po::value<std::string>(&dir)->required(),
                        "cut folder (cut-mesh.obj + cuts.json, as `wearknit cut` writes)")(
      "wearer", po::value<std::string>(&wearer_path)->required(), "the rigid object (OBJ)")(
      "trials", po::value<int>(&params.trials)->default_value(params.trials),
      "K: trials per test, each with its own global-force directions")(
      "runs", po::value<int>(&runs)->default_value(1),
      "R: eliminations with different arc orders (probability of lacing, Fig. 18)")(
      "seed", po::value<std::uint64_t>(&seed)->default_value(1), "random seed")(
      "recut-limit", po::value<int>(&recut.limit)->default_value(recut.limit),
      "re-cuts with other seeds when the garment with every cut open is not wearable (§5)")(
      "threads", po::value<int>(&params.threads)->default_value(0),
      "threads running trials (0 = all cores)")(
      "max-steps", po::value<int>(&params.cloth.max_steps)->default_value(params.cloth.max_steps),
      "steps before a trial counts as failed")(
      "resolution", po::value<int>(&resolution)->default_value(resolution),
      "distance-field cells along the wearer's longest side")(
      "cloth-vertices", po::value<int>(&recut.min_vertices)->default_value(500),
      "subdivide a garment with fewer vertices until it has this many, so it can bend around "
      "the wearer (0 = never)")(
      "frames", po::value<std::string>(&frames_dir),
      "write the strip-off of the final configuration as OBJ files into this folder")(
      "frame-every", po::value<int>(&frame_every)->default_value(10), "steps between frames")(
      "journal", po::value<std::string>(&journal_path),
      "keep every test here as it ends, so a run cut short resumes (default "
      "DIR/wearability.journal; deleted when the stage finishes)")(
      "restart", "ignore the tests of a run cut short and start again")(
      "one-at-a-time",
      "test each arc on its own, as §5 does, instead of closing runs of arcs together while "
      "the garment keeps coming off")("quiet,q", "no progress display");
  po::positional_options_description positional;
  positional.add("dir", 1);
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("wearability"), options, positional, values, context)) {
    return *code;
  }
  params.seed = seed;
  params.group_testing = values.count("one-at-a-time") == 0;
  if (params.trials < 1 || runs < 1 || params.cloth.max_steps < 1 || resolution < 8 ||
      frame_every < 1 || recut.limit < 0 || recut.min_vertices < 0) {
    context.err << "wearknit wearability: --trials, --runs, --max-steps and --frame-every must be "
                   "positive, --recut-limit and --cloth-vertices not negative, --resolution at "
                   "least 8\n";
    return kExitUsage;
  }
  const bool show_progress = context.out_is_terminal && values.count("quiet") == 0;

  knitout::DiagnosticSink sink;
  const std::string cuts_path = (fs::path(dir) / "cuts.json").string();
  auto folder = planner::read_cut_folder(dir, sink, recut.min_vertices);
  const auto wearer = planner::read_stage_mesh(wearer_path, sink);
  print_diagnostics(context, sink.diagnostics(), DiagnosticFormat::Text);
  if (sink.has_errors()) {
    const bool missing = std::any_of(sink.diagnostics().begin(), sink.diagnostics().end(),
                                     [](const auto& d) { return d.code == "W004"; });
    return missing ? kExitUsage : kExitInvalid;
  }

  if (journal_path.empty()) journal_path = (fs::path(dir) / "wearability.journal").string();
  planner::TestJournal journal(journal_path, journal_context(wearer_path, params, resolution),
                               values.count("restart") != 0);
  if (!journal.error().empty()) {
    context.err << "wearknit wearability: warning: " << journal.error()
                << " (the tests run, but a run cut short starts again)\n";
  } else if (journal.loaded() > 0 && show_progress) {
    context.out << "resuming: " << journal.loaded() << " tests of a run cut short read from "
                << journal.path() << '\n';
  }
  params.record = &journal;
  const bool journal_ok = journal.error().empty();

  if (show_progress) context.out << "building the wearer's distance field..." << std::flush;
  cloth::SdfParams sdf_params;
  sdf_params.resolution = resolution;
  sdf_params.threads = params.threads;
  const cloth::SignedDistanceField field(wearer->positions, wearer->faces, sdf_params);
  if (show_progress) context.out << "\r\033[K";

  const auto progress = [&](const planner::Progress& p) {
    if (!show_progress) return;
    context.out << "\rrun " << p.run + 1 << '/' << p.runs << "  arcs tested " << p.tested << '/'
                << p.arcs << "  sewn " << p.sewn << "\033[K" << std::flush;
  };
  // §5: a cut whose garment does not come off with every cut open is cut
  // again with another seed, up to --recut-limit times.
  auto seed_text = [](const std::optional<std::uint64_t>& s) {
    return s ? "seed " + std::to_string(*s) : std::string("an unrecorded seed");
  };
  const auto on_attempt = [&](const planner::CutAttempt& a) {
    if (show_progress) context.out << "\r\033[K";
    if (values.count("quiet") != 0 || a.wearable) return;
    if (!a.failure.empty()) {
      context.out << "cannot cut again: " << a.failure << '\n';
    } else if (a.attempt < recut.limit) {
      context.out << "the cut with " << seed_text(a.cut_seed)
                  << " does not come off the wearer with every cut open; cutting again with seed "
                  << planner::recut_seed(params.seed, a.attempt + 1) << '\n';
    }
  };
  knitout::DiagnosticSink recut_sink;
  planner::CutFolderStudy folder_study = planner::study_cut_folder(
      dir, std::move(*folder), field, params, runs, recut, recut_sink, progress, on_attempt);
  if (show_progress) context.out << "\r\033[K";
  if (journal_ok && !journal.error().empty()) {
    context.err << "wearknit wearability: warning: " << journal.error()
                << " (tests after it were not kept)\n";
  }
  print_diagnostics(context, recut_sink.diagnostics(), DiagnosticFormat::Text);
  const planner::LacingStudy& study = folder_study.study;
  const planner::CoverMesh* cover = &folder_study.folder.cover;
  nlohmann::json& cuts = folder_study.folder.cuts;

  planner::annotate_cut_folder(folder_study, params);
  const int chosen = planner::chosen_run(study);
  std::vector<double> lace_share(cover->arcs.size(), 1.0);
  if (chosen >= 0) {
    if (runs > 1) {
      lace_share = study.lace_probability;
    } else {
      const auto open = study.runs[chosen].open();
      for (std::size_t a = 0; a < open.size(); ++a) lace_share[a] = open[a] ? 1.0 : 0.0;
    }
  }
  std::string failure = knitout::write_file_atomically(
      cuts_path, [&](std::ostream& out) { out << cuts.dump(2) << '\n'; });
  const std::string picture_path = (fs::path(dir) / "wearability.png").string();
  if (failure.empty()) {
    failure = knitout::write_file_atomically(picture_path, [&](std::ostream& out) {
      planner::draw_wearability(out, *cover, lace_share);
    });
  }
  if (failure.empty()) failure = planner::record_attempts(dir, folder_study);
  if (!failure.empty()) {
    context.err << "wearknit wearability: " << failure << '\n';
    return kExitUsage;
  }
  // The results are written: the journal has done its work.
  params.record = nullptr;
  if (const std::string removed = journal.remove(); !removed.empty()) {
    context.err << "wearknit wearability: warning: " << removed << '\n';
  }

  if (chosen < 0) {
    context.err << cuts_path << ": error: [W020] the garment with every cut open did not come off "
                << "the wearer in " << params.trials << " trials of " << params.cloth.max_steps
                << " steps, ";
    std::vector<std::string> made;
    std::string not_made;
    for (const auto& a : folder_study.attempts) {
      if (!a.failure.empty()) {
        not_made = a.failure;
      } else {
        made.push_back(seed_text(a.cut_seed) +
                       (a.attempt == 0 ? std::string(" (the folder's)")
                                       : " (re-cut " + std::to_string(a.attempt) + ")"));
      }
    }
    context.err << (made.size() == 1 ? "with the cut of " : "with each of the cuts of ");
    for (std::size_t i = 0; i < made.size(); ++i) context.err << (i ? ", " : "") << made[i];
    if (!not_made.empty()) {
      context.err << "; cannot cut again: " << not_made;
    } else if (made.size() == 1) {
      context.err << " (--recut-limit " << recut.limit << ")";
    }
    context.err << "; every arc is labelled lace\n";
    return kExitInvalid;
  }
  const auto& result = study.runs[chosen];
  int sewn = 0;
  for (const auto& arc : result.arcs) sewn += arc.label == planner::Label::Sew;
  double seconds = 0;
  std::uint64_t steps = 0;
  int replayed = 0;
  for (const auto& run : study.runs) {
    seconds += run.seconds;
    steps += run.steps;
    replayed += run.replayed;
  }
  context.out << "wearability: " << cover->arcs.size() << " arcs, " << sewn << " sew, "
              << cover->arcs.size() - sewn << " lace";
  if (runs > 1) context.out << " (run " << chosen + 1 << " of " << runs << ", most sewn)";
  if (folder_study.recut()) {
    context.out << "; re-cut with " << seed_text(folder_study.cut_seed()) << " (attempt "
                << folder_study.attempts.size() - 1 << " of " << recut.limit << ")";
  }
  context.out << "; " << steps << " steps in " << std::fixed << std::setprecision(1) << seconds
              << " s";
  if (replayed > 0) context.out << " (" << replayed << " tests read from the journal)";
  context.out << "\n"
              << "wrote " << cuts_path << " and " << picture_path << '\n';

  if (!frames_dir.empty()) {
    std::error_code error;
    fs::create_directories(frames_dir, error);
    if (error) {
      context.err << frames_dir << ": error: cannot create folder: " << error.message() << '\n';
      return kExitUsage;
    }
    const planner::CoverMesh dressed = planner::dressed(*cover, field, params.cloth);
    const cloth::PolygonMesh garment = planner::open_cuts(dressed, result.open());
    // One thread: a garment of a few thousand vertices gains little from
    // splitting a step, and loses much when the cores are busy.
    cloth::ClothSimulation sim(garment, field, params.cloth);
    int written = 0;
    auto write_frame = [&](int step, const cloth::ClothSimulation& state) {
      std::ostringstream name;
      name << "frame-" << std::setw(5) << std::setfill('0') << step << ".obj";
      failure = knitout::write_file_atomically(
          (fs::path(frames_dir) / name.str()).string(), [&](std::ostream& out) {
            planner::write_obj(out, planner::PolygonMesh{state.positions(), state.mesh().faces});
          });
      ++written;
      return failure.empty();
    };
    write_frame(0, sim);
    const auto outcome =
        sim.run(final_seed(result), [&](int step, const cloth::ClothSimulation& s) {
          return step % frame_every != 0 || write_frame(step, s);
        });
    if (!failure.empty()) {
      context.err << "wearknit wearability: " << failure << '\n';
      return kExitUsage;
    }
    context.out << "wrote " << written << " frames to " << frames_dir << " ("
                << (outcome.success ? "garment off" : "garment still on") << " after "
                << outcome.steps << " steps)\n";
  }
  return kExitOk;
}

}  // namespace wearknit::cli
