// planner::emit_piece: subdivision, tracing and knitting instructions for one
// piece of a planner::Schedule (paper §7.4-7.5), as knitout for the default
// swg091n2 machine (Shima Seiki SWG091N2: carriers 1-10, racking within ±8,
// yarn-inserting hook).
//
// Subdivision (§7.4, Fig. 11): every row is knit as two passes, away from the
// side the yarn starts on and back, so the yarn always returns to where the
// row began. Each quad becomes two faces (one loop per pass); an increase a
// quad below and an increase above (knit, then a tuck on the new needle); a
// decrease a decrease below (knit through the stacked loops) and a quad
// above; a short-row triangle one face knit in the first pass only. The
// triangle at the far end of a row gets a tuck as the yarn turns
// ("tuck and turn", Fig. 12); the one at the near end is missed.
//
// Instructions (§7.5): loops move between rows with transfers planned by
// planner::schoolbus (and, before the rows the schedule names, loops held
// for later rows move aside: Schedule::aside_moves); course edges with no loop below are cast on
// with an alternating tuck cast-on; course edges with nothing above (or cut, §7.3) are bound off
// with a chain bind-off whose last loop joins the next live loop of the row or, at the top of a
// branch, stays on the bed: on a needle no later row needs, or moved aside (within the racking
// limit) to the one needed latest and moved on when that row comes. It is dropped (and can unravel)
// only when no needle within reach is free. The seed pattern knits purls on the back bed,
// checkerboard in (pass, needle).
//
// Carriers: one carrier (default "3") comes in with `inhook`, is released
// with `releasehook` after the first pass of stitches, and leaves with
// `outhook`; when the yarn would float further than max_float_needles to
// the next row it goes out and comes in again there.
//
// Broken invariants (a row that finds foreign loops on its needles, a
// transfer that cannot be planned) throw std::logic_error.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "planner/schedule/schedule.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"

namespace planner {

enum class StitchPattern : std::uint8_t { Plain, Seed };

struct EmitParams {
  StitchPattern pattern = StitchPattern::Plain;
  std::string carrier = "3";
  int max_float_needles = 20;  // longer floats cut the yarn (outhook, inhook)
  int first_needle = 1;        // the piece's leftmost needle
  int machine_needles = 540;   // a wider piece is a ScheduleError
};

// One loop of a subdivided face, in the order the yarn makes them (§7.4).
struct TraceStep {
  int face = 0;
  int part = 0;  // 0: lower half (first pass), 1: upper half (second pass)
  char bed = 'f';
  int needle = 0;
  int line = 0;  // 1-based line of the knit instruction in the piece's knitout
};

// Estimated machine time: each carriage pass travels its needle span plus
// 100 mm of run-out each side at 0.5 m/s and turns in 0.3 s; needle pitch
// 25.4 mm / 15. A documented model, not a measurement (docs/scheduling.md).
struct PieceStats {
  int rows = 0;
  int passes = 0;
  int knit_passes = 0;
  int transfer_passes = 0;
  int transfers = 0;
  int racks = 0;
  int knits = 0;
  int tucks = 0;
  int yarn_ins = 0;
  int bind_off_tails = 0;
  int width_needles = 0;
  int lines = 0;
  double knit_time_s = 0;
};

struct EmittedPiece {
  std::string knitout;
  std::vector<TraceStep> trace;
  PieceStats stats;
};

std::string_view stitch_pattern_name(StitchPattern pattern);  // "plain", "seed"

// Knitout for schedule.pieces[piece].
EmittedPiece emit_piece(const StitchMesh& mesh, const Schedule& schedule, std::size_t piece,
                        const EmitParams& params);

}  // namespace planner
