// bed::BedTimeline: the bed of a program sweep by sweep, for the HTML bed
// view (bed_page.hpp, web/bed_view.js).
//
// Attach it to a Machine as its Observer. It keeps its own model of the two
// beds from the loop events (loops held per needle, yarn of the top loop)
// and records every change of a needle as one record: the needle, its new
// state, the source line that made the change and whether loops arrived by
// a transfer. Records are grouped by carriage sweep (docs/vm.md); each sweep
// keeps its source lines, its racking, its carriers and its transfer count.
// The state of any needle at any sweep is the last record of that needle at
// or before the sweep, so the whole bed over time is recorded once, with no
// per-sweep copy of the bed.
//
// Memory grows with the changes (one 12-byte record per loop made, moved or
// dropped) and the sweeps (40 bytes each), not with sweeps x needles. After
// max_records records or max_sweeps sweeps the timeline stops recording at
// the end of that sweep and says so (`truncated`); the page then draws the
// program up to there. Loops on sliders are not drawn: a needle whose loops
// moved to a slider shows empty until they come back.
//
// Serialised layout ("wearknit-bed-timeline 1"), little-endian, every
// section starting at a multiple of 4 bytes so that a reader can view it as
// a typed array:
//
//   header, 12 x u32: magic "WKBT" (0x54424b57), version 1, sweep count S,
//     record count R, needle_min (i32), needle count W, last source line,
//     flags (bit 0: truncated, bit 1: cells are u16, bit 2: line deltas
//     are u16), carrier count C, diagnostic count D,
//     two reserved 0
//   carriers: C x (u8 length, UTF-8 name), padded to 4
//   sweeps, S entries each, as arrays:
//     u32 first_line[S]   line of the sweep's first recorded change (the
//                         end of its range when it changed no needle)
//     u32 last_line[S]    line of its last instruction; the sweep covers
//                         lines last_line[s-1]+1 .. last_line[s]
//     u32 record_begin[S+1]  its records are [record_begin[s], record_begin[s+1])
//     u32 transfers[S]    loops moved by xfer or split in it
//     i32 racking_q[S]    racking x 4 (quarter pitches) during the sweep
//     u8  carrier[S]      1 + carrier id of its last loop made, 0 = none
//     u8  flags[S]        bit 0: racking changed since the previous sweep,
//                         bit 1: transfers; padded to 4
//   records, R entries each, as arrays:
//     u32 cell[R]         (needle - needle_min) * 2 + bed (0 front, 1 back);
//                         u16 when flags bit 1 (2 W <= 65536), padded to 4
//     u32 line_delta[R]   source line - first_line of the record's sweep;
//                         u16 when flags bit 2 (every delta < 65536), padded
//     u8  carrier[R]      1 + carrier id of the top loop, 0 = empty needle
//     u8  count[R]        loops held, at most 255
//     u8  flags[R]        bit 0: loops arrived by xfer or split; padded to 4
//   diagnostics, D entries: u32 line, u32 sweep (the sweep whose lines hold
//     it; S-1 past the last), u8 severity (0 error, 1 warning, 2 note),
//     u8 code length, u16 message length, code, message (UTF-8), padded to 4
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "knitout/diagnostic.hpp"
#include "knitout/program.hpp"
#include "simulators/bed/machine.hpp"
#include "simulators/bed/profile.hpp"

namespace bed {

class BedTimeline : public Observer {
 public:
  // About 100 MB of records here, and about as much in the page.
  static constexpr std::size_t kMaxRecords = 8'000'000;
  static constexpr std::size_t kMaxSweeps = 2'000'000;
  // Needles farther than half this from the first needle used are not
  // recorded (only the unlimited generic profile allows such programs).
  static constexpr int kMaxNeedles = 20000;

  explicit BedTimeline(std::size_t max_records = kMaxRecords, std::size_t max_sweeps = kMaxSweeps)
      : max_records_(max_records), max_sweeps_(max_sweeps) {}

  struct Sweep {
    std::uint32_t first_line = 0;
    std::uint32_t last_line = 0;
    std::uint32_t record_begin = 0;  // its records are [record_begin, record_end)
    std::uint32_t record_end = 0;
    std::uint32_t transfers = 0;
    double racking = 0;
    std::uint16_t yarn = 0xffff;  // of its last loop made; 0xffff = none
    bool racked = false;
  };
  struct Record {
    std::int32_t needle = 0;
    std::uint32_t line = 0;
    std::uint16_t yarn = 0;  // of the top loop (Machine::yarn)
    std::uint8_t count = 0;  // loops held, at most 255
    std::uint8_t bed = 0;    // 0 front, 1 back
    bool transfer = false;
  };

  void loop_made(const LoopEvent& event) override;
  void loops_moved(knitout::Needle from, knitout::Needle to, int count,
                   std::uint32_t line) override;
  void loops_dropped(knitout::Needle needle, std::span<const LiveLoop> loops,
                     std::uint32_t line) override;
  void sweep_ended(const Machine& machine, std::uint32_t line) override;

  const std::vector<Sweep>& sweeps() const { return sweeps_; }
  const std::vector<Record>& records() const { return records_; }
  bool truncated() const { return truncated_; }

  // The layout above. Call after Machine::finish; `diagnostics` are the
  // run's (parser and machine), each placed at the sweep holding its line.
  std::string serialize(std::span<const knitout::Diagnostic> diagnostics) const;

 private:
  struct Cell {
    std::uint32_t count = 0;
    std::uint16_t yarn = 0;
  };
  // The model's cell of a needle or slider, or null when it is too far from
  // the first needle used.
  Cell* cell(knitout::Needle needle);
  // Records a needle's new state (sliders are not recorded).
  void record(knitout::Needle needle, const Cell& cell, std::uint32_t line, bool transfer);

  std::size_t max_records_;
  std::size_t max_sweeps_;
  std::int64_t base_ = 0;
  bool based_ = false;
  std::array<std::vector<Cell>, 4> beds_;  // by knitout::Bed; needle base_ + i
  // The split being made: its needle, line and the top of the loops it moves.
  knitout::Needle split_needle_;
  std::uint32_t split_line_ = 0;
  std::uint16_t split_moved_yarn_ = 0;
  bool split_pending_ = false;
  // Since the last sweep ended: the lines of the moves and the (line, yarn)
  // of the loops made. The machine reports a sweep's end after the first
  // instruction of the next one ran, so these are split by line.
  std::vector<std::uint32_t> move_lines_;
  std::vector<std::pair<std::uint32_t, std::uint16_t>> made_;
  double last_racking_ = 0;
  std::uint64_t lines_ = 0;  // the machine's count of source lines
  bool truncated_ = false;
  bool stopped_ = false;                  // truncated, and the sweep where it happened ended
  std::vector<std::uint8_t> yarn_codes_;  // yarn -> 1 + first carrier, 0 = none
  std::vector<std::string> carrier_names_;
  std::vector<Sweep> sweeps_;
  std::vector<Record> records_;
};

// Runs `program` through the machine for `profile` (bed::validate) with a
// BedTimeline and returns its serialised timeline, for a page that shows one
// program (the plan page shows each knitted piece this way). The machine's
// diagnostics go to `sink`; every diagnostic the sink then holds (the
// caller's parse diagnostics too) goes into the timeline.
std::string timeline_bytes(const knitout::Program& program, const MachineProfile& profile,
                           std::string_view source, knitout::DiagnosticSink& sink);

}  // namespace bed
