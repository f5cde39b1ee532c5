// The wearability stage on a cut folder, with the re-cut loop of §5.
//
// §5: "first, our wearability test verifies that the initial set of cuts
// make the garment wearable". When the garment with every cut open does not
// come off the wearer, the cut is rejected and the proxy is cut again with
// another seed (the cut stage is stochastic: the seed picks the seed quad and
// breaks ties, §4.2), up to a limit. A re-cut rewrites the cut folder as
// `wearknit cut` writes it (proxy.obj, cut-mesh.obj, cuts.json, labels.json,
// report.json, and cuts-3d.png / layout-2d.png when they were there), so
// every later stage reads the new cut.
//
// How a caller learns that the cut changed: CutFolderStudy::recut() (and
// cut_seed(), the seed of the cut now in the folder); in the files,
// cuts.json's "wearability" summary has "recut": true and "cut_seed", and
// report.json has the new "params.seed" and a "wearability" object listing
// every attempt. Anything derived from the old cut (a stitch mesh, a
// schedule) must then be made again.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "knitout/diagnostic.hpp"
#include "planner/wearability/wearability.hpp"

namespace planner {

// What the wearability stage reads from a cut folder.
struct CutFolder {
  CoverMesh cover;      // cut-mesh.obj welded, with the arcs of cuts.json
  nlohmann::json cuts;  // cuts.json as read (annotated later)
};

// Reads DIR/cut-mesh.obj and DIR/cuts.json (read_stage_mesh, read_cover_mesh)
// and subdivides a garment of fewer than `min_vertices` vertices for the
// cloth (refined_for_cloth; 0 = as read).
// Diagnostics: W001–W004, W010, W011 (docs/diagnostics.md).
std::optional<CutFolder> read_cut_folder(const std::string& dir, knitout::DiagnosticSink& sink,
                                         int min_vertices = 0);

// One cut tried: the folder's own cut (attempt 0) or a re-cut.
struct CutAttempt {
  int attempt = 0;
  std::optional<std::uint64_t> cut_seed;  // unknown when the folder has no report.json
  int arcs = 0;
  bool wearable = false;             // the garment with every cut open came off
  std::vector<TrialOutcome> trials;  // of that initial test (run 0)
  std::string failure;               // why this attempt could not be made (re-cut failed)
};

struct RecutParams {
  // Re-cuts tried after the folder's own cut fails (§5). 0 = never re-cut.
  int limit = 3;
  // A re-cut folder is read back with this (read_cut_folder).
  int min_vertices = 0;
};

// The cut seed of re-cut `attempt` (1, 2, ...): derived from the
// wearability seed, so a run is repeatable, and different for every attempt.
std::uint64_t recut_seed(std::uint64_t wearability_seed, int attempt);

// Cuts DIR/proxy.obj again with `seed` (c_s and c_o as report.json says)
// and rewrites the folder (see the top of this file); report.json keeps what
// it said about the input and the proxy. Returns an empty string, or why it
// could not (no proxy.obj or report.json, unreadable proxy, a cut that fails
// its own checks, a file that could not be written).
std::string recut_folder(const std::string& dir, std::uint64_t seed);

struct CutFolderStudy {
  CutFolder folder;                  // of the cut finally in the folder
  LacingStudy study;                 // of that cut
  std::vector<CutAttempt> attempts;  // every cut tried, in order; the last is `folder`'s
  bool wearable() const { return chosen_run(study) >= 0; }
  // The folder's files were rewritten by a re-cut (an attempt after the
  // first that did not fail).
  bool recut() const;
  // The seed of the cut now in the folder (unknown without report.json).
  std::optional<std::uint64_t> cut_seed() const;
};

// study_lacing on `folder` (read from `dir`); when no run is wearable, re-cut
// up to recut.limit times (recut_folder with recut_seed(params.seed, i)),
// re-read the folder and study again. Stops at the first wearable cut, when
// the limit is reached, or when a re-cut cannot be made (its CutAttempt then
// has `failure`). Problems reading a re-cut folder are diagnostics.
CutFolderStudy study_cut_folder(const std::string& dir, CutFolder folder,
                                const cloth::SignedDistanceField& wearer,
                                const WearabilityParams& params, int runs, const RecutParams& recut,
                                knitout::DiagnosticSink& sink,
                                const ProgressCallback& progress = {},
                                const std::function<void(const CutAttempt&)>& on_attempt = {});

// annotate_cuts on result.folder.cuts, plus "recut", "cut_seed" and
// "cut_attempts" (attempts_json) in its "wearability" summary.
void annotate_cut_folder(CutFolderStudy& result, const WearabilityParams& params);

// The attempts as JSON: [{"attempt", "cut_seed", "arcs", "wearable",
// "initial_trials", "failure"?}, ...].
nlohmann::json attempts_json(const std::vector<CutAttempt>& attempts);

// Writes the attempts into DIR/report.json under "wearability" (atomically;
// nothing when the folder has no report.json). Returns an empty string or
// the failure.
std::string record_attempts(const std::string& dir, const CutFolderStudy& result);

}  // namespace planner
