// The wearability stage's types (§5, §8.2; the functions are in
// planner/pipeline.hpp): which cut-arcs are sewn and which laced, decided by
// stripping the garment off its wearer in simulation (wearability.hpp), with
// the re-cut of §5 when the garment with every cut open does not come off.
//
// §5: "first, our wearability test verifies that the initial set of cuts
// make the garment wearable". When it does not, the proxy is cut again with
// another seed (recut_seed), up to a limit; the stage's result then carries
// the new cut, and everything made from the old one (a stitch mesh, a
// schedule) must be made again.
#pragma once

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "planner/cut/cut_stage.hpp"
#include "planner/wearability/wearability.hpp"
#include "simulators/cloth/sdf.hpp"

namespace planner {

struct WearabilityStageParams {
  WearabilityParams test;  // K trials per test, the cloth, group testing, seed, threads
  int runs = 1;            // R eliminations with different arc orders (Fig. 18)
  int recut_limit = 3;     // re-cuts tried after the cut given fails (§5); 0 = never
  // A garment with fewer vertices is subdivided until it has this many, so
  // it can bend around the wearer (refined_for_cloth; 0 = never).
  int cloth_vertices = 500;
  // A garment with more vertices is simplified to about this many for the
  // elimination (coarsened, coarse_cloth.hpp; 0 = never): a step costs time
  // in proportion to the cloth's vertices, and the strip-off needs far
  // fewer than the proxy has.
  int cloth_max_vertices = 1000;
  int sdf_resolution = cloth::SdfParams{}.resolution;  // cells along the wearer's longest side
  // M: trials of the final check (FinalCheck below); 0 = no check.
  int check_trials = 4;
  // The final check's trials stop after this many direction switches
  // without progress: more patient than the elimination's, since every one
  // of them must come off.
  int check_stall_switches = cloth::ClothParams{}.stall_switches;
};

// The final check: the garment with the chosen run's laced arcs open must
// come off in every one of M fresh trials, with seeds the elimination never
// used and a cloth finer than the elimination's (the garment as it is when
// the elimination's was coarsened, else one subdivision step finer,
// planner::subdivided), further subdivided until it has at least
// cloth_vertices vertices, so that neither a lucky trial nor a resolution
// too coarse to hold the garment decides the labels. When a trial fails,
// the sewn arcs nearest where it stays caught are opened (laced), one in
// the first round and twice as many in each round after, and the check
// runs again with new seeds, until it passes or no sewn arc is left. When
// it passed after lacing a batch of several, rounds more sew back the
// longest run of that batch, in the elimination's order, with which the
// garment still comes off in every trial (a binary search); the labels are
// those of the last round that passed.
struct CheckRound {
  std::uint64_t seed = 0;
  TestResult test;            // test_every_trial: its trials up to the first failure
  std::vector<int> reopened;  // arcs laced after this round (empty when it passed)
  // A round after the check passed: arcs of the last batch laced that were
  // sewn again for it (laced once more, and in `reopened`, when it failed).
  std::vector<int> sewn_again;
};

struct FinalCheck {
  bool ran = false;
  bool passed = false;  // the last round's garment came off in every trial
  int trials = 0;       // M
  int cloth_vertices = 0;
  std::vector<CheckRound> rounds;
  double seconds = 0;
  int reopened() const;  // arcs laced by the check, over every round
  // The last round that passed, whose configuration the labels are; null
  // when none did.
  const CheckRound* last_passed() const;
};

// The sewn arcs of `run` to open after a failed round of the final check:
// the `count` nearest to where its failed trials stay caught (the distance
// of an arc is that of its nearest vertex to the edge of a caught region:
// the caught vertices' centroid and radius). Among arcs as near, the one
// the elimination sewed last first: it was sewn with the most others
// closed, in the test that came off with the least to spare. A garment
// caught over most of its cloth leaves most arcs at distance 0, so this
// undoes the elimination from its end. Sorted by arc index.
std::vector<int> arcs_to_open(const CoverMesh& cover, const EliminationResult& run,
                              const TestResult& test, int count);

// One cut tried: the one given (attempt 0) or a re-cut.
struct CutAttempt {
  int attempt = 0;
  std::optional<std::uint64_t> cut_seed;  // unknown for a garment made by hand
  int arcs = 0;
  bool wearable = false;  // the garment with every cut open came off
  // It could not: a curve of it is linked with the wearer (no trials ran).
  bool linked = false;
  std::vector<TrialOutcome> trials;  // of that initial test (run 0)
  std::string failure;               // why this attempt could not be made (the re-cut failed)
  int cloth_vertices = 0;            // of the cloth the elimination ran on
  // The last coarser cloth that did not come off with every cut open, so
  // the elimination ran on a finer one: its vertices (0 when the first
  // cloth came off or the garment was not coarsened).
  int coarse_cloth_vertices = 0;
};

struct Wearability {
  WearabilityStageParams params;
  std::optional<Cut> recut;  // the cut the labels belong to, when not the one given
  std::uint64_t cut_id = 0;  // the id of the cut given (Cut::id)
  CoverMesh cover;           // the garment of the labelled cut, refined for the cloth
  // The elimination's: `cover` coarsened to cloth_max_vertices, or finer
  // when that cloth did not come off with every cut open (CutAttempt).
  CoverMesh cloth;
  LacingStudy study;                 // of that cut
  std::vector<CutAttempt> attempts;  // every cut tried, in order
  FinalCheck check;                  // of the chosen run's labels (its arcs say which it laced)
  double seconds = 0;

  bool wearable() const { return chosen_run(study) >= 0; }
  // The elimination simulated a cloth coarser than the garment.
  bool coarse_cloth() const { return cloth.positions.size() < cover.positions.size(); }
  // The seed of the cut the labels belong to (unknown for a garment made by hand).
  std::optional<std::uint64_t> cut_seed() const;
};

struct WearabilityCallbacks {
  ProgressCallback progress;                         // arcs tested, per run
  std::function<void(const CutAttempt&)> attempted;  // after each cut tried
  TestRecord* record = nullptr;                      // tests kept, so a run cut short resumes
};

// What wearability.json holds, as later stages read it.
struct WearabilityRecord {
  std::uint64_t cut_id = 0;  // the cut its labels belong to
  bool wearable = false;
  std::vector<Label> labels;  // per arc of the cut, in cut.json's order
  nlohmann::json file;        // the whole file, for the folder's summary
};

// The cut seed of re-cut `attempt` (1, 2, ...): derived from the
// wearability seed, so a run is repeatable, and different for every attempt.
std::uint64_t recut_seed(std::uint64_t wearability_seed, int attempt);

// The garment of a cut as the wearability test takes it: the disc with the
// vertices along its cuts welded, its cut-arcs, subdivided until it has at
// least `min_vertices` vertices (refined_for_cloth).
CoverMesh cover_of(const Cut& cut, int min_vertices);

// A garment made by hand has no proxy to cut again: the wearability test of
// its arcs as given (§5), every attempt after the first reported as not
// possible.
Wearability label_garment(const CoverMesh& garment, const cloth::SignedDistanceField& wearer,
                          const WearabilityStageParams& params,
                          const WearabilityCallbacks& callbacks = {});

// The wearer's signed distance field at the stage's resolution.
cloth::SignedDistanceField wearer_field(const PolygonMesh& wearer,
                                        const WearabilityStageParams& params);

// What decides a test besides the garment, the configuration and the seed
// (the keys of a TestJournal): the program itself (a changed simulation must
// not reuse old results), the wearer and the options the simulation reads.
std::uint64_t journal_context(const PolygonMesh& wearer, const WearabilityStageParams& params);

// "wearability: N arcs, S sew, L lace; ..." as the verb prints it.
std::string describe(const Wearability& result);
// Of the failed trials of every cut tried, the one that left the fewest
// cloth vertices on the wearer (where the garment stays caught), or null.
const TrialOutcome* farthest_failed_trial(const Wearability& result);
// The W021 warning when the final check did not pass even with every arc
// laced, else "".
std::string check_warning(const Wearability& result);
// The W020 message when no cut came off the wearer with every cut open.
std::string not_wearable_message(const Wearability& result);

// The strip-off of the final configuration as OBJ frames (frame-NNNNN.obj,
// every `every` steps) in `dir`. Returns "" or the failure; `written` and
// `off` tell how many frames and whether the garment came off.
std::string write_strip_off_frames(const Wearability& result,
                                   const cloth::SignedDistanceField& wearer, const std::string& dir,
                                   int every, int* written, bool* off);

}  // namespace planner
