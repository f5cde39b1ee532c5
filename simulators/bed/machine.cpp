#include "simulators/bed/machine.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "knitout/writer.hpp"

namespace bed {

using knitout::Bed;
using knitout::CarrierId;
using knitout::CarrierList;
using knitout::Direction;
using knitout::format_number;
using knitout::Instruction;
using knitout::Needle;
using knitout::Op;

namespace {

// Dense needle arrays never grow past this many needles per bed, even on
// the unlimited `generic` profile: a program that spreads further than this
// is reported (V030) instead of allocating gigabytes.
constexpr std::int64_t kMaxDenseNeedles = std::int64_t{1} << 19;

int code_number(std::string_view code) {
  int value = 0;
  if (code.size() < 2) return 0;
  std::from_chars(code.data() + 1, code.data() + code.size(), value);
  return value;
}

}  // namespace

std::string_view loop_kind_name(LoopKind kind) {
  switch (kind) {
    case LoopKind::Knit:
      return "knit";
    case LoopKind::Tuck:
      return "tuck";
    case LoopKind::Split:
      return "split";
  }
  return "?";
}

Machine::Machine(const MachineProfile& profile, knitout::DiagnosticSink& sink, std::string source,
                 const knitout::CarrierTable& carrier_names,
                 std::optional<std::size_t> header_carriers, MachineOptions options)
    : profile_(profile),
      sink_(sink),
      source_(std::move(source)),
      names_(carrier_names),
      header_carriers_(header_carriers),
      options_(options),
      repeats_(100, 0) {
  stat_index_.fill(-1);
  yarns_.reserve(16);
  scratch_.reserve(16);
  active_.reserve(16);
}

void Machine::error(const Instruction& in, std::string_view code, std::string message) {
  sink_.error(source_, in.line, 0, code, std::move(message));
}

void Machine::warn(std::uint32_t line, std::string_view code, std::string message) {
  const int number = code_number(code);
  if (number >= 0 && number < static_cast<int>(repeats_.size())) {
    ++repeats_[number];
    if (options_.max_repeats != 0 && repeats_[number] > options_.max_repeats) {
      ++suppressed_;
      return;
    }
  }
  sink_.warning(source_, line, 0, code, std::move(message));
}

std::string Machine::carrier_list_text(const CarrierList& carriers) const {
  std::string out;
  for (CarrierId id : carriers) {
    if (!out.empty()) out += ' ';
    out += names_.name(id);
  }
  return out;
}

CarrierStats& Machine::carrier_stats(CarrierId id) {
  if (stat_index_[id] < 0) {
    stat_index_[id] = static_cast<std::int16_t>(stats_.carriers.size());
    stats_.carriers.push_back(CarrierStats{names_.name(id)});
  }
  return stats_.carriers[static_cast<std::size_t>(stat_index_[id])];
}

// ---------------------------------------------------------------- headers

void Machine::check_headers(const std::vector<knitout::Header>& headers) {
  for (const knitout::Header& header : headers) {
    if (header.key == "Gauge") {
      double gauge = 0;
      const char* first = header.value.data();
      const char* last = first + header.value.size();
      auto result = std::from_chars(first, last, gauge);
      if (result.ec != std::errc() || result.ptr != last || !(gauge > 0)) {
        sink_.error(source_, header.line, 0, "V070",
                    "Gauge header " + quote(header.value) +
                        " is not a number greater than zero (needles per inch)");
      } else if (profile_.gauge > 0 && gauge != profile_.gauge) {
        warn(header.line, "V071",
             "Gauge " + header.value + " differs from the " + format_number(profile_.gauge) +
                 " gauge of machine " + profile_.name);
      }
    } else if (header.key == "Position") {
      const std::string& v = header.value;
      if (v != "Left" && v != "Center" && v != "Right" && v != "Keep") {
        sink_.error(source_, header.line, 0, "V072",
                    "Position header " + quote(v) + " is not Left, Center, Right or Keep");
      }
    } else if (header.key == "Machine") {
      const auto& names = profile_.machine_headers;
      if (!names.empty() && std::find(names.begin(), names.end(), header.value) == names.end()) {
        std::string hint = "--machine picks another profile";
        for (const MachineProfile& other : machine_profiles()) {
          const auto& theirs = other.machine_headers;
          if (std::find(theirs.begin(), theirs.end(), header.value) != theirs.end()) {
            hint = "--machine " + other.name + " validates on it";
          }
        }
        warn(header.line, "V073",
             "file is for machine " + quote(header.value) + " but is validated on " +
                 profile_.name + " (" + hint + ")");
      }
    }
  }
}

// ---------------------------------------------------------------- needles

int Machine::slot_of(Needle needle) const {
  if (needle.is_front()) return needle.index;
  // Wide arithmetic: needle numbers and rackings near the int range must not
  // overflow; such a slot is far outside any bed and reported as such.
  const std::int64_t slot = std::int64_t{needle.index} + floor_racking_;
  return static_cast<int>(std::clamp<std::int64_t>(slot, std::numeric_limits<int>::min(),
                                                   std::numeric_limits<int>::max()));
}

double Machine::exact_slot_of(Needle needle) const {
  return needle.is_front() ? needle.index : needle.index + racking_;
}

bool Machine::note_slot(int slot, Needle needle, const Instruction& in) {
  const int new_min = min_slot_ > max_slot_ ? slot : std::min(min_slot_, slot);
  const int new_max = min_slot_ > max_slot_ ? slot : std::max(max_slot_, slot);
  if (profile_.needle_count > 0 &&
      static_cast<std::int64_t>(new_max) - new_min + 1 > profile_.needle_count) {
    error(in, "V030",
          "needle " + knitout::to_string(needle) + " is outside the bed: the program would span " +
              std::to_string(static_cast<std::int64_t>(new_max) - new_min + 1) +
              " needles (slots " + std::to_string(new_min) + " to " + std::to_string(new_max) +
              "), machine " + profile_.name + " has " + std::to_string(profile_.needle_count));
    return false;
  }
  min_slot_ = new_min;
  max_slot_ = new_max;
  return true;
}

Machine::NeedleSlot* Machine::slot(Needle needle, const Instruction& in) {
  if (needle.is_slider() && !profile_.has_sliders) {
    error(in, "V031",
          "machine " + profile_.name + " has no sliders (" + knitout::to_string(needle) + ")");
    return nullptr;
  }
  if (!note_slot(slot_of(needle), needle, in)) return nullptr;
  BedArray& bed = beds_[static_cast<std::size_t>(needle.bed)];
  std::int64_t index = static_cast<std::int64_t>(needle.index) - bed.base;
  const auto size = static_cast<std::int64_t>(bed.slots.size());
  if (index < 0 || index >= size) {
    // Grow to cover the needle with room on both sides; a bounded bed gets
    // its whole possible range at once, so this happens once or twice.
    const std::int64_t margin =
        profile_.needle_count > 0
            ? profile_.needle_count + 16 +
                  static_cast<std::int64_t>(std::max(0.0, profile_.max_racking))
            : std::max<std::int64_t>(256, size);
    std::int64_t low =
        size == 0 ? needle.index - margin : std::min<std::int64_t>(bed.base, needle.index - margin);
    std::int64_t high = size == 0 ? needle.index + margin
                                  : std::max<std::int64_t>(bed.base + size, needle.index + margin);
    if (high - low > kMaxDenseNeedles) {
      error(in, "V030",
            "needle " + knitout::to_string(needle) +
                " is too far from the other needles the program uses (more than " +
                std::to_string(kMaxDenseNeedles) + " needles apart)");
      return nullptr;
    }
    std::vector<NeedleSlot> grown(static_cast<std::size_t>(high - low));
    for (std::int64_t i = 0; i < size; ++i) {
      grown[static_cast<std::size_t>(bed.base - low + i)] =
          std::move(bed.slots[static_cast<std::size_t>(i)]);
    }
    bed.slots = std::move(grown);
    bed.base = low;
    index = static_cast<std::int64_t>(needle.index) - bed.base;
  }
  return &bed.slots[static_cast<std::size_t>(index)];
}

std::span<const LiveLoop> Machine::loops_on(Needle needle) const {
  const BedArray& bed = beds_[static_cast<std::size_t>(needle.bed)];
  const std::int64_t index = static_cast<std::int64_t>(needle.index) - bed.base;
  if (index < 0 || index >= static_cast<std::int64_t>(bed.slots.size())) return {};
  return bed.slots[static_cast<std::size_t>(index)].loops;
}

void Machine::check_stack(const Instruction& in, Needle needle, const NeedleSlot& s) {
  const int count = static_cast<int>(s.loops.size());
  if (count > stats_.largest_stack) {
    stats_.largest_stack = count;
    stats_.largest_stack_needle = knitout::to_string(needle);
    stats_.largest_stack_line = in.line;
  }
  if (count > profile_.max_loops_per_needle) {
    error(in, "V037",
          knitout::to_string(needle) + " would hold " + std::to_string(count) +
              " loops; needles of machine " + profile_.name + " hold at most " +
              std::to_string(profile_.max_loops_per_needle));
  }
}

// ---------------------------------------------------------------- settings

void Machine::op_rack(const Instruction& in) {
  const double r = in.racking();
  if (profile_.max_racking >= 0 && std::fabs(r) > profile_.max_racking) {
    error(in, "V020",
          "racking " + format_number(r) + " is outside the range -" +
              format_number(profile_.max_racking) + " to " + format_number(profile_.max_racking) +
              " of machine " + profile_.name);
  }
  if (!profile_.racking_fractions.empty()) {
    const double fraction = r - std::floor(r);
    const auto& allowed = profile_.racking_fractions;
    if (std::find(allowed.begin(), allowed.end(), fraction) == allowed.end()) {
      std::string what = "whole numbers";
      for (double f : allowed) {
        if (f != 0) what += " or whole + " + format_number(f);
      }
      error(in, "V021",
            "racking " + format_number(r) + " is not possible on machine " + profile_.name +
                ": it racks by " + what);
    }
  }
  if (r != racking_) {
    end_sweep(in.line);
    racking_ = r;
    // Clamped so that absurd rackings (already reported) stay representable.
    floor_racking_ = static_cast<int>(std::clamp(std::floor(r), -1e9, 1e9));
    ++stats_.racks;
    stats_.estimated_time_s += profile_.rack_s;
    if (options_.observer != nullptr) options_.observer->racked(r, in.line);
  }
}

void Machine::op_stitch(const Instruction& in) {
  for (int i = 0; i < 2; ++i) {
    const double v = in.value[static_cast<std::size_t>(i)];
    const char* what = i == 0 ? "leading value" : "stitch value";
    if (v < 0) {
      error(in, "V041", std::string("stitch ") + what + " " + format_number(v) + " is negative");
    } else if (profile_.integer_stitch_values && v != std::floor(v)) {
      error(in, "V041",
            std::string("stitch ") + what + " " + format_number(v) + " is not a whole number (" +
                profile_.name + " stitch settings are whole numbers)");
    }
  }
}

void Machine::op_extension(const Instruction& in) {
  const double v = in.value[0];
  if (in.extension == knitout::Extension::SpeedNumber && v > profile_.max_speed_number) {
    error(in, "V042",
          "x-speed-number " + format_number(v) + " is above " +
              std::to_string(profile_.max_speed_number) + ", the highest speed number of " +
              profile_.name);
  } else if (in.extension == knitout::Extension::SubRollerNumber &&
             v > profile_.max_sub_roller_number) {
    error(in, "V042",
          "x-sub-roller-number " + format_number(v) + " is above " +
              std::to_string(profile_.max_sub_roller_number) + ", the highest of " + profile_.name);
  }
}

void Machine::op_pause(const Instruction& in) {
  end_sweep(in.line);
  if (last_was_pause_) {
    warn(in.line, "V060",
         "pause right after the pause at line " + std::to_string(last_pause_line_) +
             " stops the machine only once");
  }
  last_pause_line_ = in.line;
}

// ---------------------------------------------------------------- loops

void Machine::make_loop(const Instruction& in, NeedleSlot& target, LoopKind kind,
                        std::span<const LiveLoop> parents, bool has_parents) {
  const LoopId id = next_loop_++;
  const std::uint16_t yarn = yarn_id(in.carriers);
  ++stats_.loops_made;
  const double x = exact_slot_of(in.needle);
  for (CarrierId c : in.carriers) {
    CarrierState& st = carriers_[c];
    CarrierStats& cs = carrier_stats(c);
    ++cs.loops;
    if (st.has_loop) {
      const double d = std::fabs(x - st.last_loop_slot);
      cs.float_pitches += d;
      cs.longest_float_pitches = std::max(cs.longest_float_pitches, d);
      if (d > profile_.long_float_needles) {
        warn(in.line, "V054",
             "float of carrier " + quote(names_.name(c)) + " spans " + format_number(d) +
                 " needles (from its loop at line " + std::to_string(st.last_loop_line) +
                 "); machine " + profile_.name + " warns above " +
                 std::to_string(profile_.long_float_needles));
      }
    }
    st.has_loop = true;
    st.last_loop_slot = x;
    st.last_loop_line = in.line;
  }
  if (options_.observer != nullptr) {
    options_.observer->loop_made(LoopEvent{id, kind, in.needle, yarn, in.line, parents});
  }
  target.loops.push_back(LiveLoop{id, yarn, has_parents, false});
}

void Machine::op_knit_tuck(const Instruction& in, bool knit) {
  if (in.carriers.empty()) {
    op_drop(in, !knit);
    return;
  }
  if (in.needle.is_slider()) {
    use_carriers(in);
    error(in, "V032",
          std::string(knit ? "knit" : "tuck") + " on slider " + knitout::to_string(in.needle) +
              ": sliders only hold loops moved there by xfer");
    return;
  }
  use_carriers(in);
  NeedleSlot* s = slot(in.needle, in);
  move_carriers(in);
  if (s == nullptr) return;
  if (knit) {
    if (s->loops.empty()) {
      warn(in.line, "V050",
           "knit on empty needle " + knitout::to_string(in.needle) +
               ": the new loop holds nothing (tuck casts on)");
    }
    scratch_.assign(s->loops.begin(), s->loops.end());
    s->loops.clear();
    make_loop(in, *s, LoopKind::Knit, scratch_, !scratch_.empty());
  } else {
    make_loop(in, *s, LoopKind::Tuck, {}, false);
  }
  check_stack(in, in.needle, *s);
  sweep(SweepKind::Knit, in, s, slot_of(in.needle));
}

void Machine::op_drop(const Instruction& in, bool amiss) {
  if (in.needle.is_slider()) {
    error(in, "V032",
          std::string(amiss ? "amiss" : "drop") + " on slider " + knitout::to_string(in.needle) +
              ": loops on sliders go back to a needle with xfer");
    return;
  }
  NeedleSlot* s = slot(in.needle, in);
  if (s == nullptr) return;
  if (s->loops.empty()) {
    warn(in.line, "V052",
         std::string(amiss ? "amiss" : "drop") + " on empty needle " +
             knitout::to_string(in.needle) + " does nothing");
  } else if (!amiss) {
    std::uint64_t loose = 0;
    for (const LiveLoop& loop : s->loops) loose += loop.has_parents && !loop.held ? 1 : 0;
    if (loose > 0) {
      if (drop_run_loops_ == 0) drop_run_line_ = in.line;
      drop_run_loops_ += loose;
      drop_run_last_line_ = in.line;
    }
    if (options_.observer != nullptr)
      options_.observer->loops_dropped(in.needle, s->loops, in.line);
    s->loops.clear();
  }
  sweep(SweepKind::Drop, in, s, slot_of(in.needle));
}

void Machine::end_drop_run() {
  if (drop_run_loops_ == 0) return;
  std::string lines = drop_run_last_line_ == drop_run_line_
                          ? "this drop"
                          : "the drops of lines " + std::to_string(drop_run_line_) + "-" +
                                std::to_string(drop_run_last_line_);
  warn(drop_run_line_, "V053",
       lines + " let go of " + std::to_string(drop_run_loops_) +
           (drop_run_loops_ == 1 ? " loop" : " loops") +
           " that hold stitches but that nothing holds: the fabric can unravel from here"
           " (bind off first if it must not)");
  drop_run_loops_ = 0;
}

void Machine::op_transfer(const Instruction& in) {
  const Needle from = in.needle;
  const Needle to = in.needle2;
  const bool split = in.op == Op::Split && !in.carriers.empty();
  const char* name = split ? "split" : "xfer";
  if (from.is_slider() && to.is_slider()) {
    error(in, "V033",
          std::string(name) + " " + knitout::to_string(from) + " " + knitout::to_string(to) +
              ": loops cannot move from slider to slider");
    return;
  }
  if (from.is_front() == to.is_front()) {
    error(in, "V035",
          std::string(name) + " " + knitout::to_string(from) + " " + knitout::to_string(to) +
              " stays on one bed; loops move between the front and the back bed");
    return;
  }
  if (split && from.is_slider()) {
    error(in, "V034",
          "split from slider " + knitout::to_string(from) + ": sliders cannot form loops");
    return;
  }
  const Needle front = from.is_front() ? from : to;
  const Needle back = from.is_front() ? to : from;
  if (static_cast<double>(front.index) != back.index + racking_) {
    std::string why;
    if (racking_ != std::floor(racking_)) {
      why = "; at a fractional racking no needles face each other";
    } else {
      why = "; " + knitout::to_string(front) + " faces b" + format_number(front.index - racking_) +
            " here";
    }
    error(in, "V036",
          std::string(name) + " " + knitout::to_string(from) + " " + knitout::to_string(to) +
              ": the needles are not aligned at racking " + format_number(racking_) + why);
    return;
  }
  if (split) use_carriers(in);
  NeedleSlot* source = slot(from, in);
  NeedleSlot* target = slot(to, in);
  if (split) move_carriers(in);
  if (source == nullptr || target == nullptr) return;
  if (source->loops.empty()) {
    warn(in.line, "V051",
         split ? "split on empty needle " + knitout::to_string(from) +
                     ": the new loop holds nothing and nothing moves"
               : "xfer from empty needle " + knitout::to_string(from) + ": nothing moves");
  }
  scratch_.assign(source->loops.begin(), source->loops.end());
  source->loops.clear();
  if (split) {
    make_loop(in, *source, LoopKind::Split, scratch_, !scratch_.empty());
    for (LiveLoop& loop : scratch_) loop.held = true;
  } else if (!scratch_.empty()) {
    ++stats_.transfers;
    stats_.loops_transferred += scratch_.size();
  }
  if (!scratch_.empty()) {
    target->loops.insert(target->loops.end(), scratch_.begin(), scratch_.end());
    if (options_.observer != nullptr) {
      options_.observer->loops_moved(from, to, static_cast<int>(scratch_.size()), in.line);
    }
    check_stack(in, to, *target);
  }
  // Carriers whose logical position is at the source needle follow its
  // loops (knitout spec, "split" and "xfer").
  for (CarrierId id : active_) {
    CarrierState& st = carriers_[id];
    if (split && in.carriers.contains(id)) continue;
    if (st.side != Direction::None && st.needle == from) {
      st.needle = to;
      st.last_loop_slot = exact_slot_of(to);
    }
  }
  if (split) check_stack(in, from, *source);
  sweep(split ? SweepKind::Knit : SweepKind::Transfer, in, source, slot_of(from));
}

void Machine::op_miss(const Instruction& in) {
  if (in.carriers.empty()) {
    error(in, "V040", "miss without carriers does nothing: miss moves the carriers it names");
    return;
  }
  if (in.needle.is_slider()) {
    use_carriers(in);
    error(in, "V032",
          "miss at slider " + knitout::to_string(in.needle) +
              ": carriers move along needles, not sliders");
    return;
  }
  use_carriers(in);
  NeedleSlot* s = slot(in.needle, in);
  move_carriers(in);
  if (s == nullptr) return;
  sweep(SweepKind::Knit, in, s, slot_of(in.needle));
}

// ---------------------------------------------------------------- sweeps

// A sweep is one carriage crossing as the machine model estimates it
// (docs/vm.md): consecutive operations of one kind, in one direction with one
// carrier set for knitting, in needle order, with no needle used twice.
void Machine::sweep(SweepKind kind, const Instruction& in, NeedleSlot* s, int slot_number) {
  bool fresh = kind != sweep_kind_;
  if (!fresh) {
    if (kind == SweepKind::Knit) {
      const bool same_place = slot_number == sweep_last_slot_ && in.needle.bed == sweep_last_bed_;
      if (in.direction != sweep_direction_ || !(in.carriers == sweep_carriers_) || same_place) {
        fresh = true;
      } else if (in.direction == Direction::Plus) {
        fresh = slot_number < sweep_last_slot_;
      } else {
        fresh = slot_number > sweep_last_slot_;
      }
    }
    if (!fresh && s != nullptr) fresh = s->sweep_stamp == sweep_id_;
  }
  if (fresh) {
    end_sweep(in.line);
    sweep_kind_ = kind;
    ++sweep_id_;
    sweep_direction_ = in.direction;
    sweep_carriers_ = in.carriers;
    sweep_min_ = slot_number;
    sweep_max_ = slot_number;
  } else {
    sweep_min_ = std::min(sweep_min_, slot_number);
    sweep_max_ = std::max(sweep_max_, slot_number);
  }
  sweep_last_slot_ = slot_number;
  sweep_last_bed_ = in.needle.bed;
  sweep_last_line_ = in.line;
  if (s != nullptr) s->sweep_stamp = sweep_id_;
}

void Machine::end_sweep(std::uint32_t /*line*/) {
  if (sweep_kind_ == SweepKind::None) return;
  const double needles =
      (static_cast<double>(sweep_max_) - sweep_min_ + 1) + 2.0 * profile_.overrun_needles;
  const double metres = needles * profile_.pitch_mm() / 1000.0;
  const double speed = sweep_kind_ == SweepKind::Knit ? profile_.knit_speed_m_per_s
                                                      : profile_.transfer_speed_m_per_s;
  stats_.sweep_needles += needles;
  stats_.estimated_time_s += metres / speed + profile_.turnaround_s;
  ++stats_.sweeps;
  switch (sweep_kind_) {
    case SweepKind::Knit:
      ++stats_.knit_sweeps;
      break;
    case SweepKind::Transfer:
      ++stats_.transfer_sweeps;
      break;
    case SweepKind::Drop:
      ++stats_.drop_sweeps;
      break;
    case SweepKind::None:
      break;
  }
  sweep_kind_ = SweepKind::None;
  if (options_.observer != nullptr) options_.observer->sweep_ended(*this, sweep_last_line_);
}

// ---------------------------------------------------------------- driver

void Machine::step(const Instruction& in) {
  if (in.line > stats_.lines) stats_.lines = in.line;
  if (in.op == Op::Comment) return;
  ++stats_.instructions;
  ++stats_.by_op[static_cast<std::size_t>(in.op)];
  const bool dropping = in.op == Op::Drop || (in.op == Op::Knit && in.carriers.empty());
  if (!dropping && drop_run_loops_ != 0) end_drop_run();
  switch (in.op) {
    case Op::In:
      op_in(in, false);
      break;
    case Op::Inhook:
      op_in(in, true);
      break;
    case Op::Releasehook:
      op_releasehook(in);
      break;
    case Op::Out:
      op_out(in, false);
      break;
    case Op::Outhook:
      op_out(in, true);
      break;
    case Op::Stitch:
      op_stitch(in);
      break;
    case Op::Rack:
      op_rack(in);
      break;
    case Op::Knit:
      op_knit_tuck(in, true);
      break;
    case Op::Tuck:
      op_knit_tuck(in, false);
      break;
    case Op::Split:
    case Op::Xfer:
      op_transfer(in);
      break;
    case Op::Drop:
      op_drop(in, false);
      break;
    case Op::Amiss:
      op_drop(in, true);
      break;
    case Op::Miss:
      op_miss(in);
      break;
    case Op::Pause:
      op_pause(in);
      break;
    case Op::Extension:
      op_extension(in);
      break;
    case Op::Comment:
      break;
  }
  last_was_pause_ = in.op == Op::Pause;
}

void Machine::finish(std::uint32_t last_line) {
  if (last_line > stats_.lines) stats_.lines = last_line;
  end_drop_run();
  end_sweep(last_line);
  for (CarrierId id : active_) {
    const CarrierState& st = carriers_[id];
    if (st.implicit) continue;
    sink_.error(source_, st.in_line, 0, "V013",
                "carrier " + quote(names_.name(id)) +
                    " brought in here is still in at the end of the program (line " +
                    std::to_string(stats_.lines) + "); take it out with out or outhook");
  }
  if (last_was_pause_) {
    warn(last_pause_line_, "V061",
         "pause at the end of the program: nothing follows it for the machine to stop before");
  }
  for (Bed slider : {Bed::FrontSlider, Bed::BackSlider}) {
    const BedArray& b = beds_[static_cast<std::size_t>(slider)];
    for (std::size_t i = 0; i < b.slots.size(); ++i) {
      if (b.slots[i].loops.empty()) continue;
      const Needle n{slider, static_cast<std::int32_t>(b.base + static_cast<std::int64_t>(i))};
      warn(stats_.lines, "V055",
           "slider " + knitout::to_string(n) + " still holds " +
               std::to_string(b.slots[i].loops.size()) +
               " loop(s) at the end of the program; xfer them back to a needle");
    }
  }
  if (options_.max_repeats != 0) {
    for (std::size_t code = 0; code < repeats_.size(); ++code) {
      if (repeats_[code] <= options_.max_repeats) continue;
      char name[32];
      std::snprintf(name, sizeof name, "V%03zu", code);
      sink_.warning(source_, 0, 0, "V099",
                    std::to_string(repeats_[code] - options_.max_repeats) + " more " + name +
                        " warnings not shown (the first " + std::to_string(options_.max_repeats) +
                        " are)");
    }
  }
  stats_.has_span = min_slot_ <= max_slot_;
  stats_.min_slot = min_slot_;
  stats_.max_slot = max_slot_;
  for (CarrierStats& cs : stats_.carriers) {
    cs.yarn_m = (static_cast<double>(cs.loops) * profile_.loop_yarn_pitches + cs.float_pitches) *
                profile_.pitch_mm() / 1000.0;
  }
}

}  // namespace bed
