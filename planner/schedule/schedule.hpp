// planner::Schedule: the flat-sheet knit schedule of paper §7, from a
// planner::StitchMesh.
//
// Stages (each a free function, run in this order by `schedule`):
//   build_rows          §7.1, Fig. 8b: faces into rows (wale-connected, left to right)
//   build_patches       §7.1, Fig. 8c-f: row graph, redundant paths removed,
//                       serial chains collapsed into patches
//   assign_needles      §7.2: needles per course edge, per patch from its bottom
//                       row, then patches shifted to agree along their boundaries
//   choose_order        §7.3: random patch orders simulated on the needle bed
//                       (patches moved sideways, held loops set aside where
//                       that clears an overlap); each overlap left adds a
//                       cut; the order with fewest cuts wins
//   make_pieces         the connected parts left once the cuts are made
// Tracing, subdivision and knitout are in knitout_emit.hpp (§7.4-7.5).
//
// Needles are in global front-bed indices (may be negative until a piece is
// written; the emitter shifts each piece to start at needle 1).
// Bad input (faces whose sides do not make a stitch mesh the scheduler can
// read) throws ScheduleError naming the face; broken invariants throw
// std::logic_error.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "planner/stitch_mesh/stitch_mesh.hpp"

namespace planner {

class ScheduleError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr int kNone = -1;

// §7.3: the furthest (in needles) the order simulation moves a patch
// sideways, by default, to keep it clear of loops held for other rows: the
// racking limit, so the move is one round of the schoolbus (docs/scheduling.md
// compares 4 and 8 over the shared meshes).
inline constexpr int kMaxPatchShift = 8;

// §7.3 (docs/scheduling.md, "Setting held loops aside"): the furthest (in
// needles, in all) the order simulation moves loops held for a later row
// out of the way of a patch that would cover them; again one round of the
// schoolbus.
inline constexpr int kMaxAside = 8;

// One loop-carrying course edge of the stitch mesh: made by `lower` (its
// CourseOut side), knit through by `upper` (its CourseIn side). kNone on a
// side means the edge is on the mesh boundary there: cast on below, bound off
// above.
struct CourseEdge {
  int lower = kNone;
  int upper = kNone;
  int needle = 0;    // §7.2: where the loop sits once `lower` is knit (global)
  bool cut = false;  // §7.3: cut to avoid an overlap (a seam labelled sew)
};

struct FaceLinks {
  std::vector<int> in;   // course edges entering the face, left to right
  std::vector<int> out;  // course edges leaving the face, left to right
  int left = kNone;      // neighbouring face in the row across a wale side
  int right = kNone;
};

struct Row {
  std::vector<int> faces;  // left to right
  int patch = kNone;
  bool cycle_broken = false;  // the row closed on itself and was opened (a cut)
};

// Before `row` (the first row of a patch) is knit, the loop of course edge
// `edge`, held for a later row, moves to front needle `to` (global, patch
// shifts included): the patch would otherwise cover it (§7.3).
struct AsideMove {
  int row = 0;
  int edge = 0;
  int to = 0;
};

struct Patch {
  std::vector<int> rows;  // bottom to top: the order they are knit in
};

// Each order is simulated with held loops kept where they were made and
// with them set aside (§7.3, docs/scheduling.md); `cuts` is the fewer.
struct TrialResult {
  std::uint64_t trial = 0;
  int cuts = 0;
  int cuts_in_place = 0;
  int cuts_aside = 0;  // = cuts_in_place when loops may not be set aside
};

struct ScheduleParams {
  int trials = 100;                      // random knitting orders tried (§7.3)
  double time_budget_s = 0;              // > 0: try orders until this much time has passed instead
  std::uint64_t seed = 1;                // every random choice derives from it and the trial number
  int threads = 0;                       // 0: OMP_NUM_THREADS, else all cores
  int max_patch_shift = kMaxPatchShift;  // 0: patches stay where §7.2 put them
  int max_aside = kMaxAside;             // 0: held loops stay where they were made
  // The best random orders refined by improve_order (0: §7.3's random
  // orders only), and the orders simulated per refinement, at most.
  int improve = 8;
  int improve_moves = 1000;
};

struct Piece {
  std::vector<int> rows;  // in knitting order
};

// §7.3: why a row pair is cut: row `covering` is knit (in the order kept)
// over `needle`, where loops from the lower row wait for the upper one.
struct CutCause {
  int covering = kNone;
  int needle = 0;  // global front-bed index, as CourseEdge::needle
};

struct Schedule {
  std::vector<FaceLinks> faces;
  std::vector<CourseEdge> edges;
  std::vector<int> face_row;
  std::vector<Row> rows;
  // Wale sides shared by two faces whose rows run opposite ways (both see
  // the side as their right, or both as their left): left open as seams to
  // sew, as (face, face).
  std::vector<std::pair<int, int>> wale_seams;
  // Row graph (§7.1, Fig. 8c): successors of each row, and the edges left once
  // redundant paths are removed (Fig. 8d).
  std::vector<std::vector<int>> row_successors;
  std::vector<std::vector<int>> reduced_successors;
  // Each row's place in a topological order of the row graph (Kahn's,
  // lowest row number first).
  std::vector<int> row_topo_index;
  std::vector<Patch> patches;
  std::vector<int> patch_order;        // §7.3: the order kept
  std::vector<int> patch_shift;        // §7.3: needles each patch was moved (already in the edges)
  std::vector<AsideMove> aside_moves;  // §7.3: held loops moved out of the way, in knitting order
  std::vector<TrialResult> trials;     // every order tried, in trial order
  std::uint64_t best_trial = 0;        // the random order kept, or refined into the kept one
  int random_cuts = 0;                 // cuts of the best random order, before improve_order
  int cuts = 0;                        // cuts of the kept order (row pairs separated)
  std::vector<std::pair<int, int>> cut_rows;  // (lower row, upper row) per cut
  std::vector<CutCause> cut_causes;           // why, per cut (as cut_rows)
  std::vector<Piece> pieces;
};

// §7.1, Fig. 8b: course edges, wale neighbours and rows. Throws ScheduleError
// for faces the scheduler cannot read (no course edge in or out, sides shared
// with mismatched roles, vertex indices out of range).
void build_rows(const StitchMesh& mesh, Schedule& schedule);

// §7.1, Fig. 8c-f. Throws ScheduleError when the row graph has a cycle (the
// mesh's course directions are inconsistent).
void build_patches(Schedule& schedule);

// §7.2. Deterministic.
void assign_needles(const StitchMesh& mesh, Schedule& schedule);

// §7.3: simulate one order; returns the row pairs that must be cut. `order`
// is a topological order of the patches. A patch about to be knit over
// loops held for other rows is first moved sideways by the fewest needles
// (within ±max_shift) that leaves the fewest row pairs to cut, and the held
// loops it would still cover are moved out of its way where that clears
// them (each row pair's loops together, at most max_aside needles from
// where they were made); the shift per patch is stored in `patch_shift` and
// the moves of held loops in `asides` when given (edges' needles are not
// changed); why each pair is cut in `causes` when given.
std::vector<std::pair<int, int>> simulate_order(
    const Schedule& schedule, const std::vector<int>& order, int max_shift = kMaxPatchShift,
    std::vector<int>* patch_shift = nullptr, int max_aside = kMaxAside,
    std::vector<AsideMove>* asides = nullptr, std::vector<CutCause>* causes = nullptr);

// §7.3: a random topological order of the patches for `trial`.
std::vector<int> random_patch_order(const Schedule& schedule, std::uint64_t seed,
                                    std::uint64_t trial);

// After §7.3's random orders: a local search from `order`. For each cut
// (lower row, upper row), the upper row's patch is moved as early as its
// predecessors allow, or the lower row's as late as its successors allow; a
// move that leaves fewer cuts is kept, and the search starts again, until no
// move helps or `max_moves` orders have been simulated. Deterministic.
// Returns the cuts of the order left in `order`.
int improve_order(const Schedule& schedule, std::vector<int>& order, int max_shift, int max_moves,
                  int max_aside = kMaxAside);

// §7.3: tries orders (in parallel on OpenMP threads, each trial into its own
// slot; the result depends only on params.seed and the number of trials, not
// on the threads; a time budget runs rounds of one trial per thread until it
// is spent), refines the params.improve best of them (improve_order) and
// keeps the one with fewest cuts (ties: the better random order, then the
// lowest trial number), marks the cut edges.
void choose_order(Schedule& schedule, const ScheduleParams& params);

// Connected parts once cuts are made; rows in knitting order.
void make_pieces(Schedule& schedule);

// All of the above.
Schedule schedule(const StitchMesh& mesh, const ScheduleParams& params);

}  // namespace planner
