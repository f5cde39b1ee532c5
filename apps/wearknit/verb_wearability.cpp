// wearknit wearability: which cut-arcs of a cut folder are sewn and which are
// laced (§5), by stripping the garment off the wearer in simulation; the
// stage itself is planner::label_arcs (planner/pipeline.hpp).
#include <algorithm>
#include <filesystem>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/stage_options.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/pipeline.hpp"
#include "planner/wearability/journal.hpp"
#include "planner/wearability/wearability_io.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;
namespace fs = std::filesystem;

int run_wearability(const std::vector<std::string>& args, Context& context) {
  std::string dir, wearer_path, frames_dir, journal_path;
  WearerUnitOptions wearer_units;
  WearabilityOptions wear;
  int frame_every = 10;
  po::options_description options("options");
  options.add_options()("dir", po::value<std::string>(&dir)->required(),
                        "cut folder (as `wearknit cut` writes it, or cut-mesh.obj and cut.json "
                        "made by hand)")("wearer", po::value<std::string>(&wearer_path)->required(),
                                         "the rigid object (OBJ, OFF, PLY or STL)")(
      "seed", po::value<std::uint64_t>(&wear.params.test.seed)->default_value(1), "random seed");
  add_wearer_unit_options(options, wearer_units);
  add_wearability_options(options, wear, "trials");
  add_threads_option(options, wear.params.test.threads);
  options.add_options()("frames", po::value<std::string>(&frames_dir),
                        "write the strip-off of the final configuration as OBJ files into this "
                        "folder")("frame-every", po::value<int>(&frame_every)->default_value(10),
                                  "steps between frames")(
      "journal", po::value<std::string>(&journal_path),
      "keep every test here as it ends, so a run cut short resumes (default "
      "DIR/wearability.journal; deleted when the stage finishes)")(
      "restart", "ignore the tests of a run cut short and start again")("quiet,q",
                                                                        "no progress display");
  po::positional_options_description positional;
  positional.add("dir", 1);
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("wearability"), options, positional, values, context)) {
    return *code;
  }
  std::string problem = check_wearability_options(values, wear);
  if (frame_every < 1) problem = "--frame-every must be positive";
  const double wearer_factor = wearer_mm_per_unit(values, wearer_units, dir, problem);
  if (!problem.empty()) {
    context.err << "wearknit wearability: " << problem << '\n';
    return kExitUsage;
  }
  const bool quiet = values.count("quiet") != 0;
  const bool show_progress = context.out_is_terminal && !quiet;

  knitout::DiagnosticSink sink;
  std::optional<planner::Cut> cut;
  std::optional<planner::CoverMesh> garment;
  if (fs::exists(fs::path(dir) / "proxy.obj")) {
    cut = planner::read_cut(dir, sink);
  } else {
    garment = planner::read_garment(dir, wear.params.cloth_vertices, sink);
  }
  auto wearer = planner::read_stage_mesh(wearer_path, sink);
  if (wearer) {
    for (planner::Vec3& p : wearer->positions) p *= wearer_factor;
    const planner::PolygonMesh* worn = cut       ? &cut->mesh.proxy.polygons()
                                       : garment ? &*garment
                                                 : nullptr;
    if (worn != nullptr) {
      const std::string disagreement = planner::size_disagreement(*worn, *wearer);
      if (!disagreement.empty()) sink.warning(wearer_path, 0, 0, "W005", disagreement);
    }
  }
  print_diagnostics(context, sink.diagnostics(), DiagnosticFormat::Text);
  if (sink.has_errors()) {
    const bool missing = std::any_of(sink.diagnostics().begin(), sink.diagnostics().end(),
                                     [](const auto& d) { return d.code == "W004"; });
    return missing ? kExitUsage : kExitInvalid;
  }

  if (journal_path.empty()) journal_path = (fs::path(dir) / "wearability.journal").string();
  planner::TestJournal journal(journal_path, planner::journal_context(*wearer, wear.params),
                               values.count("restart") != 0);
  if (!journal.error().empty()) {
    context.err << "wearknit wearability: warning: " << journal.error()
                << " (the tests run, but a run cut short starts again)\n";
  } else if (journal.loaded() > 0 && show_progress) {
    context.out << "resuming: " << journal.loaded() << " tests of a run cut short read from "
                << journal.path() << '\n';
  }
  const cloth::SignedDistanceField field = planner::wearer_field(*wearer, wear.params);
  planner::WearabilityCallbacks callbacks;
  callbacks.record = journal.error().empty() ? &journal : nullptr;
  callbacks.progress = [&](const planner::Progress& p) {
    if (!show_progress) return;
    context.out << "\rrun " << p.run + 1 << '/' << p.runs << "  arcs tested " << p.tested << '/'
                << p.arcs << "  sewn " << p.sewn << "\033[K" << std::flush;
  };
  callbacks.attempted = [&](const planner::CutAttempt& a) {
    if (show_progress) context.out << "\r\033[K";
    if (quiet || a.wearable) return;
    if (!a.failure.empty()) {
      context.out << "cannot cut again: " << a.failure << '\n';
    } else if (a.attempt < wear.params.recut_limit) {
      context.out << "the cut with "
                  << (a.cut_seed ? "seed " + std::to_string(*a.cut_seed) : "an unrecorded seed")
                  << " does not come off the wearer with every cut open; cutting again with seed "
                  << planner::recut_seed(wear.params.test.seed, a.attempt + 1) << '\n';
    }
  };
  // A folder written by `wearknit cut` is re-cut when its garment does not
  // come off (§5); a garment made by hand is tested as it is.
  const planner::Wearability result =
      cut ? planner::label_arcs(*cut, field, wear.params, callbacks)
          : planner::label_garment(*garment, field, wear.params, callbacks);

  // A re-cut is written (as the cut stage writes a cut) before the labels.
  std::uint64_t labelled_id = cut ? cut->id : 0;
  std::string failure;
  if (result.recut) {
    // Pictures drawn again as the cut had them.
    const int px = result.recut->report.picture_px;
    failure = planner::write_cut(dir, *result.recut, {px > 0, px > 0 ? px : 600}, &labelled_id);
  }
  if (failure.empty()) failure = planner::write_wearability(dir, result, labelled_id);
  if (failure.empty()) failure = planner::write_folder_summary(dir);
  if (!failure.empty()) {
    context.err << "wearknit wearability: " << failure << '\n';
    return kExitUsage;
  }
  // The results are written: the journal has done its work.
  if (const std::string removed = journal.remove(); !removed.empty())
    context.err << "wearknit wearability: warning: " << removed << '\n';
  const std::string labels_path = (fs::path(dir) / "wearability.json").string();
  if (!result.wearable()) {
    context.err << labels_path << ": error: [W020] " << planner::not_wearable_message(result)
                << '\n';
    return kExitInvalid;
  }
  if (const std::string warning = planner::check_warning(result); !warning.empty())
    context.err << labels_path << ": warning: [W021] " << warning << '\n';
  context.out << planner::describe(result) << "wrote " << labels_path << ", "
              << (fs::path(dir) / "wearability.png").string()
              << (result.recut ? " and the re-cut's files" : "") << '\n';
  if (frames_dir.empty()) return kExitOk;
  int written = 0;
  bool off = false;
  failure = planner::write_strip_off_frames(result, field, frames_dir, frame_every, &written, &off);
  if (!failure.empty()) {
    context.err << "wearknit wearability: " << failure << '\n';
    return kExitUsage;
  }
  context.out << "wrote " << written << " frames to " << frames_dir << " ("
              << (off ? "garment off" : "garment still on") << ")\n";
  return kExitOk;
}

}  // namespace wearknit::cli
