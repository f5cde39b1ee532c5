// bed::Machine: the needle-bed virtual machine.
//
// A V-bed machine: front and back beds of needles, a slider under every
// needle, a racking between the beds, yarn carriers with the knitout
// specification's logical positions, and the yarn-inserting hook. Every loop
// the program makes gets an integer id and remembers its yarn, the source
// line that made it and whether it was pulled through older loops. Loops
// stack on needles; knit pulls a new loop through the stack, split moves the
// stack to the opposite bed while pulling the new loop through it, xfer
// moves it, drop lets it go. (machine.cpp; the carrier operations are in
// machine_carriers.cpp.)
//
// Contract
//   * Feed instructions in program order with `step`, then call `finish`
//     once. `step` never throws on bad input: every problem becomes a
//     diagnostic (codes V001-V099, docs/diagnostics.md) in the sink given at
//     construction, at the instruction's line, and the machine goes on in the
//     most plausible state so later problems are still found.
//   * Memory is bounded by the bed (needles x loops per needle) and the
//     carriers, never by program length; no heap allocation happens per
//     instruction once the needle arrays have their size. An Observer sees
//     every loop as it is made (the knit graph and bed view use this) and
//     may keep as much as it likes.
//   * The machine judges knitout semantics for one MachineProfile. It does
//     not form carriage passes as a backend does; `Stats::sweeps` is the
//     machine's own estimate (docs/vm.md), `Stats::dat_passes` is left for
//     the DAT backend to fill.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "knitout/diagnostic.hpp"
#include "knitout/program.hpp"
#include "simulators/bed/profile.hpp"
#include "simulators/bed/stats.hpp"

namespace bed {

using LoopId = std::uint32_t;
inline constexpr LoopId kNoLoop = 0xffffffffu;

enum class LoopKind : std::uint8_t { Knit, Tuck, Split };
std::string_view loop_kind_name(LoopKind kind);

// A loop held by a needle or slider.
struct LiveLoop {
  LoopId id = kNoLoop;
  std::uint16_t yarn = 0;    // Machine::yarn(id): the carriers that made it
  bool has_parents = false;  // pulled through older loops (holds stitches below)
  bool held = false;         // a newer loop was pulled through it (split)
};

// What an Observer is told when a loop is made.
struct LoopEvent {
  LoopId id = kNoLoop;
  LoopKind kind = LoopKind::Knit;
  knitout::Needle needle;
  std::uint16_t yarn = 0;
  std::uint32_t line = 0;
  std::span<const LiveLoop> parents;  // the loops it was pulled through (bottom first)
};

// Optional listener; every method has an empty default.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void loop_made(const LoopEvent& /*event*/) {}
  // `count` loops moved from `from` to `to` by xfer (or split's old loops).
  virtual void loops_moved(knitout::Needle /*from*/, knitout::Needle /*to*/, int /*count*/,
                           std::uint32_t /*line*/) {}
  virtual void loops_dropped(knitout::Needle /*needle*/, std::span<const LiveLoop> /*loops*/,
                             std::uint32_t /*line*/) {}
  virtual void racked(double /*racking*/, std::uint32_t /*line*/) {}
  // A carriage sweep (docs/vm.md) ended; the machine shows the bed after it.
  virtual void sweep_ended(const class Machine& /*machine*/, std::uint32_t /*line*/) {}
};

struct MachineOptions {
  // After this many warnings of one code in a file the rest are counted and
  // summed up in one V099 warning at the end; 0 = report every one.
  std::size_t max_repeats = 20;
  Observer* observer = nullptr;
};

enum class CarrierStatus : std::uint8_t {
  Out,            // not on the bed
  PendingIn,      // `in`: enters from the grippers at its first use
  PendingInhook,  // `inhook`: enters on the inserting hook at its first use
  In,             // in action
};

struct CarrierState {
  CarrierStatus status = CarrierStatus::Out;
  bool used = false;            // knitted, tucked, split or missed since it came in
  bool hook_held = false;       // brought in by inhook and not released yet
  bool has_loop = false;        // made a loop since it came in (floats start there)
  bool implicit = false;        // used without being brought in (reported once, V004)
  knitout::CarrierList in_set;  // the carriers brought in with it (first use must match)
  std::uint32_t in_line = 0;
  // Logical position (knitout spec): last needle and side of the needle.
  knitout::Needle needle;
  knitout::Direction side = knitout::Direction::None;
  double last_loop_slot = 0;  // front-bed slot of its last loop
  std::uint32_t last_loop_line = 0;
};

class Machine {
 public:
  // `carrier_names` names the CarrierIds of the instructions (the Reader's or
  // Program's table; it may grow while the machine runs). The first
  // `header_carriers` ids are the ones the `;;Carriers:` header names, or
  // nullopt when the file has no such header (then any name may be used).
  // The profile, sink and carrier table are referenced, not copied: they
  // must outlive the machine.
  Machine(const MachineProfile& profile, knitout::DiagnosticSink& sink, std::string source,
          const knitout::CarrierTable& carrier_names, std::optional<std::size_t> header_carriers,
          MachineOptions options = {});

  // Checks the header lines (Gauge, Position, Machine).
  void check_headers(const std::vector<knitout::Header>& headers);
  // Runs one instruction.
  void step(const knitout::Instruction& instruction);
  // End of program: carriers still in, trailing pause, pending summaries.
  // `last_line` is the file's last line.
  void finish(std::uint32_t last_line);

  const MachineProfile& profile() const { return profile_; }
  // Counts are live; bed span and yarn lengths are filled in by finish().
  const Stats& stats() const { return stats_; }
  double racking() const { return racking_; }
  const CarrierState& carrier(knitout::CarrierId id) const { return carriers_[id]; }
  // Loops on a needle or slider, bottom of the stack first.
  std::span<const LiveLoop> loops_on(knitout::Needle needle) const;
  // Front-bed slots the program has used so far (empty when min > max).
  int min_slot() const { return min_slot_; }
  int max_slot() const { return max_slot_; }
  // The carriers of yarn id `yarn` (see LiveLoop::yarn).
  const knitout::CarrierList& yarn(std::uint16_t yarn) const { return yarns_[yarn]; }
  std::size_t yarn_count() const { return yarns_.size(); }
  const knitout::CarrierTable& carrier_names() const { return names_; }
  std::string carrier_list_text(const knitout::CarrierList& carriers) const;

 private:
  struct NeedleSlot {
    std::vector<LiveLoop> loops;
    std::uint32_t sweep_stamp = 0;  // last sweep that used this needle
  };
  // Dense per-needle storage for one bed, indexed by needle number - base.
  struct BedArray {
    std::int64_t base = 0;
    std::vector<NeedleSlot> slots;
  };
  enum class SweepKind : std::uint8_t { None, Knit, Transfer, Drop };

  void error(const knitout::Instruction& in, std::string_view code, std::string message);
  void warn(std::uint32_t line, std::string_view code, std::string message);

  NeedleSlot* slot(knitout::Needle needle, const knitout::Instruction& in);
  int slot_of(knitout::Needle needle) const;
  double exact_slot_of(knitout::Needle needle) const;
  bool note_slot(int slot, knitout::Needle needle, const knitout::Instruction& in);
  CarrierStats& carrier_stats(knitout::CarrierId id);

  void op_in(const knitout::Instruction& in, bool hook);
  void op_releasehook(const knitout::Instruction& in);
  void op_out(const knitout::Instruction& in, bool hook);
  void op_rack(const knitout::Instruction& in);
  void op_stitch(const knitout::Instruction& in);
  void op_knit_tuck(const knitout::Instruction& in, bool knit);
  void op_drop(const knitout::Instruction& in, bool amiss);
  void op_transfer(const knitout::Instruction& in);  // split and xfer
  void op_miss(const knitout::Instruction& in);
  void op_pause(const knitout::Instruction& in);
  void op_extension(const knitout::Instruction& in);

  bool use_carriers(const knitout::Instruction& in);
  void move_carriers(const knitout::Instruction& in);
  void make_loop(const knitout::Instruction& in, NeedleSlot& target, LoopKind kind,
                 std::span<const LiveLoop> parents, bool has_parents);
  void check_stack(const knitout::Instruction& in, knitout::Needle needle, const NeedleSlot& s);
  std::uint16_t yarn_id(const knitout::CarrierList& carriers);
  // 'text', as messages quote names.
  static std::string quote(std::string_view text) { return "'" + std::string(text) + "'"; }
  void end_drop_run();
  void sweep(SweepKind kind, const knitout::Instruction& in, NeedleSlot* s, int slot);
  void end_sweep(std::uint32_t line);

  const MachineProfile& profile_;
  knitout::DiagnosticSink& sink_;
  std::string source_;
  const knitout::CarrierTable& names_;
  std::optional<std::size_t> header_carriers_;
  MachineOptions options_;

  std::array<BedArray, 4> beds_;  // indexed by knitout::Bed
  bool beds_sized_ = false;
  double racking_ = 0;
  int floor_racking_ = 0;
  int min_slot_ = 1;
  int max_slot_ = 0;

  std::array<CarrierState, 256> carriers_{};
  std::vector<knitout::CarrierId> active_;    // carriers not Out, in order of entry
  std::array<std::int16_t, 256> stat_index_;  // carrier id -> Stats::carriers index, -1 = none
  bool hook_busy_ = false;
  knitout::CarrierList hook_carriers_;

  std::vector<knitout::CarrierList> yarns_;
  std::uint16_t last_yarn_ = 0;
  LoopId next_loop_ = 0;
  std::vector<LiveLoop> scratch_;

  bool last_was_pause_ = false;
  std::uint32_t last_pause_line_ = 0;

  // Consecutive drops of loops that nothing holds, reported once (V053).
  std::uint32_t drop_run_line_ = 0;
  std::uint32_t drop_run_last_line_ = 0;
  std::uint64_t drop_run_loops_ = 0;

  // Current sweep (docs/vm.md).
  SweepKind sweep_kind_ = SweepKind::None;
  knitout::Direction sweep_direction_ = knitout::Direction::None;
  knitout::CarrierList sweep_carriers_;
  std::uint32_t sweep_id_ = 0;
  int sweep_min_ = 0;
  int sweep_max_ = 0;
  int sweep_last_slot_ = 0;
  knitout::Bed sweep_last_bed_ = knitout::Bed::Front;
  std::uint32_t sweep_last_line_ = 0;

  std::vector<std::uint32_t> repeats_;  // warnings per V code number
  std::uint64_t suppressed_ = 0;
  Stats stats_;
};

}  // namespace bed
