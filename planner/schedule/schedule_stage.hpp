// The schedule stage's types (§7; the functions are in planner/pipeline.hpp):
// the stitch mesh scheduled into flat-sheet pieces (schedule.hpp, §7.1-7.3),
// each traced into knitout (knitout_emit.hpp, §7.4-7.5), run through the
// needle-bed VM and compiled to a Shima Seiki DAT.
#pragma once

#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "planner/schedule/knitout_emit.hpp"
#include "planner/schedule/piece_layout.hpp"
#include "planner/schedule/schedule.hpp"
#include "simulators/bed/stats.hpp"

namespace planner {

struct ScheduleStageParams {
  ScheduleParams schedule;
  EmitParams emit;
};

// The needle-bed VM's run of one piece (its machine and bed view).
struct PieceCheck;

struct ScheduledPiece {
  std::string name;  // "piece-N", N from 1
  EmittedPiece emitted;
  std::size_t stitches = 0;  // stitch-mesh faces in the piece
  bed::Stats vm_stats;       // the VM's figures, its time estimate among them
  std::size_t vm_warnings = 0;
  std::vector<std::uint8_t> dat;  // the piece as a Shima Seiki DAT
  std::shared_ptr<const PieceCheck> check;
};

struct ScheduleOutcome {
  ScheduleStageParams params;
  Schedule schedule;
  std::vector<ScheduledPiece> pieces;
  std::uint64_t stitch_mesh_id = 0;  // the stitch mesh it was made from (StitchMeshFile::id)
  std::uint64_t cut_id = 0;          // and that mesh's cut, when known
  unsigned threads = 1;              // threads the order search ran on
  double seconds = 0;
};

// What schedule.json and the pieces' layouts hold, as the assembly guide
// reads them.
struct ScheduleRecord {
  std::uint64_t stitch_mesh_id = 0;
  std::vector<PieceLayout> layouts;                        // per piece, in order
  std::vector<std::pair<int, int>> wale_seams;             // Schedule::wale_seams
  nlohmann::json schedule_cuts = nlohmann::json::array();  // the scheduler's cuts (§7.3)
  nlohmann::json file;                                     // schedule.json as a whole
};

// Writes the bed view of a piece (SVG or PNG by the extension of `path`).
std::string write_bed_view(const ScheduledPiece& piece, const std::string& path);

// Why scheduling cut `cut` (an index of Schedule::cut_rows) is made, in
// words: "cut 1: rows 12 and 13 are parted because row 40 is knit before row
// 13 over the needle where the loops from row 12 wait for it".
std::string cut_cause_text(const Schedule& s, std::size_t cut);

// "PATH: N stitches, R rows, P patches; ... pieces in DIR/pieces (...)" as
// the verb prints it, then why each cut is made (the first five).
std::string describe(const ScheduleOutcome& outcome, const std::string& smobj_path,
                     const std::string& pieces_dir);

}  // namespace planner
