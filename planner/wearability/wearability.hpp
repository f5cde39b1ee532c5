// The wearability test and the elimination of cut-arcs (§5, §8.2, Fig. 18).
//
// Input: a CoverMesh — the garment surface with every cut closed (vertices
// welded), and its cut-arcs, each a list of mesh edges. An arc is *open* when
// the mesh is split along its edges (a seam left unsewn, to be laced) and
// *closed* when its edges stay welded (sewn). Building one from a mesh and
// lists of arcs takes a few lines; from a split cut-mesh, weld_vertices()
// first (the vertex map also translates arcs given in split indices).
//
// The test (§5): the garment, dressed just outside the wearer, is stripped
// off by the cloth simulation (simulators/cloth); it is wearable when one of
// K trials, each with its own sequence of global-force directions, gets it
// sufficiently far from the wearer. It is conservative: a failed trial only
// means no way off was found, so arcs may stay laced that could be sewn
// (under-sewing), never the reverse.
//
// The elimination (§5): with every arc open the garment must be wearable
// (else the cut is rejected and the caller re-cuts with another seed). Then
// the arcs are taken one at a time in a random order, each tested once:
// closed tentatively, kept closed (label sew) when the garment stays
// wearable, reopened (label lace) otherwise. Repeating it over R random
// orders gives each arc's probability of being laced (Fig. 18). By default
// the first run takes the arcs in the order of how far their sides parted
// in that first test instead (ArcOrder::Opening).
//
// Group testing (on by default, WearabilityParams::group_testing) decides
// the same order with fewer tests: the next run of arcs in the order is
// closed together; when the garment still comes off they are all sewn, else
// the run is halved and each half settled the same way, down to single arcs.
// When sewing more never makes a garment easier to strip (closing a seam
// only removes ways off), this gives exactly the labels of the one-at-a-time
// elimination of the same order; docs/wearability.md says why it is used.
//
// Deterministic for a given seed, whatever the thread count: trials run in
// parallel, but the outcome of an arc is decided by the lowest-numbered
// successful trial, and only trials up to it are recorded.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "planner/common/hash.hpp"
#include "planner/mesh/mesh.hpp"
#include "simulators/cloth/cloth.hpp"
#include "simulators/cloth/sdf.hpp"

namespace planner {

using cloth::Vec3;

struct CoverArc {
  std::string name;                       // for reports; may be empty
  std::vector<std::array<int, 2>> edges;  // vertex pairs of the CoverMesh's positions
};

// The garment: its surface, welded (one vertex per point of the garment,
// faces counter-clockwise seen from outside), and its cut-arcs.
struct CoverMesh : PolygonMesh {
  std::vector<CoverArc> arcs;
};

// Problems that make the mesh unusable, each a sentence naming the element
// (face or arc and edge index): index out of range, face with fewer than 3
// vertices, an edge with more than two faces, an arc edge that is not an
// edge of the mesh, an edge in two arcs. Empty when the mesh is fine.
std::vector<std::string> validate(const CoverMesh& mesh);

// The arc through the vertex path p0, p1, ... (consecutive pairs).
CoverArc arc_from_path(const std::vector<int>& path, std::string name = {});
// Shortest path along mesh edges (Euclidean edge lengths) from `from` to `to`
// (inclusive); empty when they are not connected.
std::vector<int> shortest_edge_path(const CoverMesh& mesh, int from, int to);
// Index of the vertex nearest to `point`.
int nearest_vertex(const CoverMesh& mesh, const Vec3& point);

// Merges vertices closer than `tolerance` (keeping the first), rewriting
// `faces`; returns old index → new index. Turns a split cut-mesh into the
// welded CoverMesh form.
std::vector<int> weld_vertices(std::vector<Vec3>& vertices, std::vector<std::vector<int>>& faces,
                               double tolerance);

// One step of polygon subdivision: every n-gon becomes n quads through its
// centroid and its edges' midpoints (new points on the old faces: the shape
// does not change), and every arc edge becomes the two edges of its halves.
// Arc indices and names are kept.
CoverMesh subdivided(const CoverMesh& mesh);

// The mesh subdivided until it has at least `min_vertices` vertices (at most
// 4 steps, i.e. up to 256 times the faces). A garment of a few dozen large
// faces cannot bend around its wearer in the simulation; its sew/lace
// answers are per arc and do not depend on the resolution.
CoverMesh refined_for_cloth(CoverMesh mesh, int min_vertices);

// The garment with the arcs where open[arc] is true split open: every vertex
// gets one copy per group of its faces that stays connected across closed
// edges. `source` (optional) receives the CoverMesh vertex of each copy.
cloth::PolygonMesh open_cuts(const CoverMesh& mesh, const std::vector<bool>& open,
                             std::vector<int>* source = nullptr);

struct TestResult;

// Tests already run, looked up before a test is simulated and added after.
// An elimination cut short (the process killed, the machine restarted)
// resumes from them: the simulation is deterministic, so a test of the same
// dressed garment, configuration and seed, under the same parameters and
// wearer, has the same result. Keys come from the elimination (test_key);
// the record's owner makes sure the parameters and the wearer match
// (TestJournal, planner/wearability/journal.hpp, keeps them in a file).
class TestRecord {
 public:
  virtual ~TestRecord() = default;
  virtual std::optional<TestResult> find(std::uint64_t key) = 0;
  virtual void add(std::uint64_t key, const TestResult& result) = 0;
};

// The cloth of the elimination's trials: the simulation's defaults, with the
// stall stop after two direction switches without progress instead of
// three. Most of the elimination's steps are spent in failing tests, every
// trial of them run until it stalls; on them this saves 15-23 % of the
// steps, and one trial in twelve of a configuration that comes off stops
// early (docs/wearability.md, "The stall stop"). The final check keeps three
// (WearabilityStageParams::check_stall_switches).
inline cloth::ClothParams elimination_cloth() {
  cloth::ClothParams params;
  params.stall_switches = 2;
  return params;
}

// The order in which the elimination takes the arcs.
enum class ArcOrder : std::uint8_t {
  // §5: a random order, drawn from the seed.
  Random,
  // The arcs whose two sides parted least while the garment came off with
  // every cut open first (TestResult::openings), ties in the random order:
  // runs of arcs the garment does not need open come first and are sewn
  // together, the arcs it opens to come off are tested last
  // (docs/wearability.md, "The order of the arcs"). A heuristic: the labels
  // are those of one particular order of §5's elimination. Runs after the
  // first of a study (study_lacing) take random orders.
  Opening,
};
const char* to_string(ArcOrder order);

struct WearabilityParams {
  // Every trial's simulation (its `threads` is ignored).
  cloth::ClothParams cloth = elimination_cloth();
  // K: trials per test, each with its own global-force directions. An arc is
  // sewn when one of them strips the garment off.
  int trials = 4;
  // Threads running trials concurrently (0 = all hardware threads).
  int threads = 0;
  // Settle runs of arcs with one test while the garment keeps coming off
  // (see the top of this file); false = the paper's one test per arc.
  bool group_testing = true;
  // The longest run closed in one test.
  int max_group = 32;
  std::uint64_t seed = 1;
  // Not owned; when set, every test is looked up here first and added after.
  TestRecord* record = nullptr;
  // With several runs (study_lacing): a configuration whose open arcs
  // include all the open arcs of one that came off in an earlier run comes
  // off without a test (opening more never makes a garment harder to
  // take off).
  bool reuse_passes = true;
  // Fail without a simulation a configuration in which a closed curve of
  // the garment winds around a handle of the wearer (planner/wearability/
  // linking.hpp): it cannot come off, whatever the trials would find.
  bool linking = true;
  ArcOrder order = ArcOrder::Opening;
};

// The open-arc sets of configurations that came off, shared by the runs of
// a study (WearabilityParams::reuse_passes).
class PassedConfigurations {
 public:
  // Whether `open` opens every arc that some recorded configuration opens.
  bool covers(const std::vector<bool>& open) const;
  void add(const std::vector<bool>& open);

 private:
  std::vector<std::vector<bool>> open_sets_;
};

struct TrialOutcome {
  std::uint64_t seed = 0;  // of its global-force directions
  bool success = false;
  int steps = 0;
  bool stalled = false;     // stopped before the budget for lack of progress
  double min_distance = 0;  // at the end, as a fraction of the wearer's scale
  // A failed trial: garment vertices still within the success distance of
  // the wearer at the end, and their centroid in mm (where it is caught).
  int caught = 0;
  Vec3 caught_at = Vec3::Zero();
  double caught_radius = 0;  // mm: the farthest of them from caught_at
  int cloth_vertices = 0;    // of the garment simulated
};

struct TestResult {
  bool wearable = false;
  int group = 1;                     // arcs closed tentatively for this test (the elimination's)
  std::vector<TrialOutcome> trials;  // up to and including the first success
  std::uint64_t steps = 0;           // simulated, over every trial started
  std::uint64_t projections = 0;
  // Not simulated: an earlier run of the study passed with a subset of
  // this test's open arcs (LacingStudy, WearabilityParams::reuse_passes).
  bool inferred = false;
  // Not simulated: a curve of the garment is linked with the wearer
  // (WearabilityParams::linking), so it cannot come off.
  bool linked = false;
  // Per arc, when measured (the elimination's initial test with
  // ArcOrder::Opening): how far its two sides parted in the decisive trial
  // while the garment was on the wearer. Per edge, the largest distance
  // between the midpoints of its two sides at a moment when one of them was
  // within the success distance of the wearer; the mean over the arc's
  // edges, in mesh units. Empty otherwise.
  std::vector<double> openings;
};

enum class Label : std::uint8_t { Lace, Sew };
const char* to_string(Label label);

struct ArcResult {
  Label label = Label::Lace;
  int position = -1;  // when it was tested (0 = first); -1 when never tested
  // The test that decided it, of the garment with this arc closed. With
  // test.group > 1 a sewn arc was closed with test.group - 1 others, all
  // sewn with it; a laced arc was closed with others that were then all
  // sewn (settled before it), so the test is of exactly the garment with
  // this arc closed.
  TestResult test;
  // Sewn by the elimination, laced by the final check of the stage
  // (Wearability::check): the check's garment did not come off with it
  // closed.
  bool reopened = false;
};

struct EliminationResult {
  TestResult initial;           // every arc open
  std::vector<int> order;       // arcs in the order they were tested
  std::vector<ArcResult> arcs;  // by arc index
  int tests = 0;                // tests run after the initial one
  int replayed = 0;             // tests (the initial one included) read from params.record
  int inferred = 0;             // tests passed from an earlier run's (TestResult::inferred)
  int linked = 0;               // tests failed by the linking test (TestResult::linked)
  double seconds = 0;
  std::uint64_t steps = 0;
  std::uint64_t projections = 0;
  bool wearable() const { return initial.wearable; }
  std::vector<bool> open() const;  // the final configuration: true = laced
};

struct Progress {
  int run = 0, runs = 1;
  int tested = 0, arcs = 0;  // arcs tested so far in this run
  int sewn = 0;
};
using ProgressCallback = std::function<void(const Progress&)>;

// Dresses the garment on the wearer (every vertex pushed `clearance` out),
// the starting configuration of every trial.
CoverMesh dressed(const CoverMesh& mesh, const cloth::SignedDistanceField& wearer,
                  const cloth::ClothParams& params);

// The key under which a test of `open` with `seed` on the dressed garment
// whose fingerprint is `garment` is recorded (TestRecord).
std::uint64_t test_key(std::uint64_t garment, const std::vector<bool>& open, std::uint64_t seed);
// The fingerprint of a (dressed) garment: its vertices, faces and arcs.
std::uint64_t fingerprint(const CoverMesh& mesh);

// One wearability test of the configuration `open` (mesh already dressed).
// `seed` picks the trials' direction seeds.
// With `openings`, the result's openings are measured (TestResult::openings).
TestResult test_wearability(const CoverMesh& dressed_mesh, const std::vector<bool>& open,
                            const cloth::SignedDistanceField& wearer,
                            const WearabilityParams& params, std::uint64_t seed,
                            bool openings = false);

// The final check's test (planner/wearability/wearability_stage.hpp): the
// configuration passes only when every one of `trials` trials strips the
// garment off. Trials after the first failure are stopped and not recorded.
TestResult test_every_trial(const CoverMesh& dressed_mesh, const std::vector<bool>& open,
                            const cloth::SignedDistanceField& wearer,
                            const WearabilityParams& params, std::uint64_t seed, int trials);

// The elimination (§5) for run `run` (orders and trial seeds follow from
// params.seed and run). Throws std::invalid_argument when validate() fails.
// `passed` (optional, not owned): configurations that came off in earlier
// runs, looked up before each test and added to after each pass.
EliminationResult eliminate(const CoverMesh& mesh, const cloth::SignedDistanceField& wearer,
                            const WearabilityParams& params, int run = 0,
                            const ProgressCallback& progress = {},
                            PassedConfigurations* passed = nullptr);

struct LacingStudy {
  std::vector<EliminationResult> runs;
  std::vector<double> lace_probability;  // per arc, over the runs whose initial test passed
  int wearable_runs = 0;
};

// The run whose labels are used: the wearable run with the most arcs sewn
// (every run's final configuration passed a test, so each is safe; this one
// laces least), the first on ties; -1 when no run was wearable.
int chosen_run(const LacingStudy& study);

// R eliminations with different orders (Fig. 18).
LacingStudy study_lacing(const CoverMesh& mesh, const cloth::SignedDistanceField& wearer,
                         const WearabilityParams& params, int runs,
                         const ProgressCallback& progress = {});

}  // namespace planner
