#include "backends/dat/passes.hpp"

#include <algorithm>
#include <cmath>
#include <istream>
#include <ostream>

#include "knitout/writer.hpp"

namespace dat {

using knitout::Bed;
using knitout::Direction;
using knitout::format_number;
using knitout::Instruction;
using knitout::Op;
using knitout::opposite;

namespace {

struct SlotOpInfo {
  std::uint8_t colour;
  bool front;  // knits or tucks on the front bed
  bool back;
};

// Colours are the KnitPaint colour indices of docs/dat.md.
constexpr std::array<SlotOpInfo, 20> kSlotOps = {{
    {16, false, false},   // SoftMiss
    {216, false, false},  // MissFront
    {217, false, false},  // MissBack
    {11, true, false},    // TuckFront
    {12, false, true},    // TuckBack
    {51, true, false},    // KnitFront
    {52, false, true},    // KnitBack
    {3, true, true},      // KnitFrontKnitBack
    {41, true, true},     // KnitFrontTuckBack
    {51, true, false},    // KnitFrontMissBack
    {42, true, true},     // TuckFrontKnitBack
    {88, true, true},     // TuckFrontTuckBack
    {11, true, false},    // TuckFrontMissBack
    {52, false, true},    // MissFrontKnitBack
    {12, false, true},    // MissFrontTuckBack
    {16, false, false},   // MissFrontMissBack
    {20, false, false},   // XferToBack
    {30, false, false},   // XferToFront
    {101, false, false},  // SplitToBack
    {102, false, false},  // SplitToFront
}};

const SlotOpInfo& info(SlotOp op) {
  return kSlotOps[static_cast<std::size_t>(op)];
}

// The op doing `a` and then `b` in one slot, moving in the pass direction.
// A soft miss yields to anything; front and back ops share a slot only at
// quarter-pitch racking, where the back needle sits beside the front one.
std::optional<SlotOp> merge_ops(SlotOp a, SlotOp b, bool quarter_pitch) {
  if (a == SlotOp::SoftMiss) return b;
  if (b == SlotOp::SoftMiss) return a;
  if (!quarter_pitch) return std::nullopt;
  int back = -1;
  if (b == SlotOp::MissBack) back = 0;
  if (b == SlotOp::TuckBack) back = 1;
  if (b == SlotOp::KnitBack) back = 2;
  if (back < 0) return std::nullopt;
  static constexpr SlotOp kMiss[3] = {SlotOp::MissFrontMissBack, SlotOp::MissFrontTuckBack,
                                      SlotOp::MissFrontKnitBack};
  static constexpr SlotOp kTuck[3] = {SlotOp::TuckFrontMissBack, SlotOp::TuckFrontTuckBack,
                                      SlotOp::TuckFrontKnitBack};
  static constexpr SlotOp kKnit[3] = {SlotOp::KnitFrontMissBack, SlotOp::KnitFrontTuckBack,
                                      SlotOp::KnitFrontKnitBack};
  if (a == SlotOp::MissFront) return kMiss[back];
  if (a == SlotOp::TuckFront) return kTuck[back];
  if (a == SlotOp::KnitFront) return kKnit[back];
  return std::nullopt;
}

bool is_quarter_pitch(double racking) {
  return racking - std::floor(racking) != 0.0;
}

// Digits, then an optional '.', then digits: the only numbers the reference
// takes for Gauge.
bool is_plain_decimal(std::string_view text) {
  std::size_t i = 0;
  while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
  if (i == 0) return false;
  if (i < text.size() && text[i] == '.') ++i;
  while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
  return i == text.size();
}

bool is_digits(std::string_view text) {
  return !text.empty() &&
         std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// Rejected at the `rack` already: far beyond any machine, and slot numbers
// (needle + racking) must not overflow.
constexpr double kMaxSaneRacking = 1000;

}  // namespace

std::string_view pass_type_name(PassType type) {
  switch (type) {
    case PassType::KnitTuck:
      return "knit-tuck";
    case PassType::AMiss:
      return "a-miss";
    case PassType::Split:
      return "split";
    case PassType::SplitViaSliders:
      return "split-via-sliders";
    case PassType::Xfer:
      return "xfer";
    case PassType::XferToSliders:
      return "xfer-to-sliders";
    case PassType::XferFromSliders:
      return "xfer-from-sliders";
  }
  return "?";
}

std::uint8_t slot_op_colour(SlotOp op) {
  return info(op).colour;
}

bool CarrierSet::contains(std::uint8_t id) const {
  return std::find(begin(), end(), id) != end();
}

bool CarrierSet::operator==(const CarrierSet& other) const {
  return size == other.size && std::equal(begin(), end(), other.begin());
}

std::string to_string(const CarrierSet& carriers) {
  std::string text;
  for (std::uint8_t id : carriers) {
    if (!text.empty()) text += ' ';
    text += std::to_string(id);
  }
  return text;
}

PassBuilder::PassBuilder(std::string source, knitout::DiagnosticSink& sink, const Profile& profile)
    : source_(std::move(source)), sink_(sink), profile_(profile), stitch_(profile.default_stitch) {
  list_.source = source_;
  list_.profile = &profile;
  list_.bed_width = profile.default_bed_width;
}

bool PassBuilder::error(std::uint32_t line, std::string_view code, std::string message) {
  sink_.error(source_, line, 0, code, std::move(message));
  failed_ = true;
  return false;
}

void PassBuilder::warning(std::uint32_t line, std::string_view code, std::string message) {
  sink_.warning(source_, line, 0, code, std::move(message));
}

std::int64_t PassBuilder::slot_number(NeedleRef needle) const {
  // Back needle b faces front needle b + racking; the raster column of a
  // back op is that of the front needle it faces (rounded down at quarter
  // pitch).
  const bool front = needle.bed == Bed::Front || needle.bed == Bed::FrontSlider;
  if (front) return needle.index;
  return needle.index + static_cast<std::int64_t>(std::floor(racking_));
}

std::uint8_t PassBuilder::carrier_number(knitout::CarrierId id,
                                         const knitout::CarrierTable& table) {
  while (id_numbers_.size() < table.size()) {
    const std::string& name = table.name(static_cast<knitout::CarrierId>(id_numbers_.size()));
    std::uint8_t number = 0;
    for (int n = 1; n <= profile_.carrier_count && n < static_cast<int>(carriers_.size()); ++n) {
      if (name == std::to_string(n)) number = static_cast<std::uint8_t>(n);
    }
    id_numbers_.push_back(number);
  }
  return id < id_numbers_.size() ? id_numbers_[id] : 0;
}

std::string PassBuilder::name_list(const CarrierSet& carriers) const {
  std::string text;
  for (std::uint8_t id : carriers) {
    if (!text.empty()) text += ' ';
    text += std::to_string(id);
  }
  return text;
}

std::string PassBuilder::instruction_carriers() const {
  std::string text;
  if (current_ == nullptr || table_ == nullptr) return text;
  for (knitout::CarrierId id : current_->carriers) {
    if (!text.empty()) text += ' ';
    text += table_->name(id);
  }
  return text;
}

bool PassBuilder::begin(bool has_magic, const std::vector<knitout::Header>& headers) {
  if (!has_magic) {
    return error(1, "D001",
                 "missing magic line ';!knitout-N': the DAT backend only reads knitout files "
                 "that start with it");
  }
  const knitout::Header* carriers = nullptr;
  for (const knitout::Header& header : headers) {
    const std::string& value = header.value;
    if (header.key == "Carriers") {
      carriers = &header;
    } else if (header.key == "Machine" || header.key.starts_with("Yarn-")) {
      // Accepted as written; the profile decides the machine.
    } else if (header.key == "Gauge") {
      if (!is_plain_decimal(value) || std::strtod(value.c_str(), nullptr) <= 0) {
        return error(header.line, "D004",
                     "Gauge header '" + value + "' is not a number greater than zero");
      }
    } else if (header.key == "Width") {
      const bool digits = is_digits(value);
      std::int64_t width = 0;
      if (digits && value.size() <= 9) width = std::stoll(value);
      if (!digits || width <= 0) {
        return error(header.line, "D005",
                     "Width header '" + value +
                         "' is not a positive whole number of needles (at most 999999999)");
      }
      list_.bed_width = width;
    } else if (header.key == "Position") {
      if (value == "Center") {
        list_.position = Position::Center;
      } else if (value == "Keep") {
        list_.position = Position::Keep;
      } else if (value == "Left") {
        list_.position = Position::Left;
      } else if (value == "Right") {
        list_.position = Position::Right;
      } else {
        return error(header.line, "D006",
                     "Position header '" + value + "' is not Left, Right, Keep or Center");
      }
    } else {
      warning(header.line, "D007",
              "unknown header '" + header.key + "'; the DAT backend ignores it");
    }
  }
  if (carriers == nullptr) {
    return error(1, "D002",
                 "no ';;Carriers:' header; the " + std::string(profile_.name) +
                     " profile needs "
                     "';;Carriers: " +
                     std::string(profile_.carriers_header) + "'");
  }
  // The reference splits the value on runs of spaces and joins it with one.
  std::string collapsed;
  for (char c : carriers->value) {
    if (c == ' ' && !collapsed.empty() && collapsed.back() == ' ') continue;
    collapsed += c;
  }
  if (collapsed != profile_.carriers_header) {
    return error(carriers->line, "D003",
                 "Carriers header '" + carriers->value + "' is not '" +
                     std::string(profile_.carriers_header) + "', the carriers of the " +
                     std::string(profile_.name) + " profile");
  }
  return true;
}

bool PassBuilder::reject_if_split_via_sliders(std::uint32_t line, std::string_view op) {
  if (!svs_) return true;
  return error(line, "D027",
               "'" + std::string(op) +
                   "' while split-via-sliders loops wait on the sliders; return them all "
                   "with xfer first");
}

PassBuilder::Candidate PassBuilder::make_candidate(PassType type, Direction direction,
                                                   const CarrierSet& cs, std::int64_t slot,
                                                   SlotOp op, std::int64_t stitch) const {
  Candidate candidate;
  candidate.pass.type = type;
  candidate.pass.direction = direction;
  candidate.pass.carriers = cs;
  candidate.pass.racking = racking_;
  candidate.pass.stitch = stitch;
  candidate.pass.speed = speed_;
  candidate.pass.line = line_;
  candidate.entry = {slot, op};
  return candidate;
}

bool PassBuilder::add(const Instruction& in, const knitout::CarrierTable& table,
                      std::string_view text) {
  if (failed_) return false;
  current_ = &in;
  table_ = &table;
  line_ = in.line;
  const std::uint32_t line = in.line;
  CarrierSet cs;
  for (knitout::CarrierId id : in.carriers) cs.ids[cs.size++] = carrier_number(id, table);

  switch (in.op) {
    case Op::Comment:
      return true;
    case Op::Extension:
      return add_extension(in, line, text);
    case Op::In:
    case Op::Inhook:
      return add_in(in, cs, line);
    case Op::Releasehook:
      return add_releasehook(cs, line);
    case Op::Out:
    case Op::Outhook:
      return add_out(in, cs, line);
    case Op::Rack:
      return add_rack(in, line);
    case Op::Stitch:
      return add_stitch_setting(in, line);
    case Op::Knit:
    case Op::Tuck:
    case Op::Miss:
    case Op::Drop:
    case Op::Amiss:
      return add_stitch_op(in, cs, line);
    case Op::Split:
    case Op::Xfer:
      return add_split(in, cs, line);
    case Op::Pause:
      if (!reject_if_split_via_sliders(line, "pause")) return false;
      if (pause_pending_) warning(line, "D032", "pause right after pause; one stop is made");
      pause_pending_ = true;
      return true;
  }
  return true;
}

bool PassBuilder::add_extension(const Instruction& in, std::uint32_t line, std::string_view text) {
  switch (in.extension) {
    case knitout::Extension::StitchNumber:
      if (!reject_if_split_via_sliders(line, "x-stitch-number")) return false;
      stitch_ = static_cast<std::int64_t>(in.value[0]);
      return true;
    case knitout::Extension::SpeedNumber:
      if (!reject_if_split_via_sliders(line, "x-speed-number")) return false;
      speed_ = static_cast<std::int64_t>(in.value[0]);
      return true;
    case knitout::Extension::PresserMode: {
      if (!reject_if_split_via_sliders(line, "x-presser-mode")) return false;
      const auto mode = static_cast<knitout::PresserMode>(static_cast<int>(in.value[0]));
      presser_ = mode == knitout::PresserMode::On     ? Presser::On
                 : mode == knitout::PresserMode::Auto ? Presser::Auto
                                                      : Presser::Off;
      return true;
    }
    default: {
      std::string name(knitout::extension_name(in.extension));
      if (in.extension == knitout::Extension::Unknown) {
        name = std::string(text.substr(0, text.find(' ')));
      }
      if (std::find(warned_extensions_.begin(), warned_extensions_.end(), name) ==
          warned_extensions_.end()) {
        warned_extensions_.push_back(name);
        warning(line, "D031",
                "extension '" + name +
                    "' is not supported by the DAT backend and is ignored (reported once "
                    "per file)");
      }
      return true;
    }
  }
}

bool PassBuilder::add_rack(const Instruction& in, std::uint32_t line) {
  const double racking = in.value[0];
  const double fraction = racking - std::floor(racking);
  if (fraction != 0.0 && fraction != 0.25) {
    return error(
        line, "D020",
        "racking " + format_number(racking) + " is neither whole nor whole + 0.25 (quarter pitch)");
  }
  if (std::abs(racking) > kMaxSaneRacking) {
    return error(line, "D021",
                 "racking " + format_number(racking) + " is beyond the machine's range -" +
                     format_number(profile_.max_racking) + ".." +
                     format_number(profile_.max_racking));
  }
  racking_ = racking;
  return true;
}

bool PassBuilder::add_stitch_setting(const Instruction& in, std::uint32_t line) {
  if (!reject_if_split_via_sliders(line, "stitch")) return false;
  const double leading = in.value[0];
  const double stitch = in.value[1];
  if (leading != std::floor(leading) || stitch != std::floor(stitch)) {
    return error(line, "D023", "stitch takes two whole numbers (leading, stitch value)");
  }
  for (const StitchEntry& entry : profile_.stitch_table) {
    if (entry.stitch == stitch && entry.leading == leading) {
      stitch_ = entry.number;
      return true;
    }
  }
  return error(line, "D023",
               "stitch " + format_number(leading) + " " + format_number(stitch) + ": leading " +
                   format_number(leading) + " with stitch value " + format_number(stitch) +
                   " is not in the " + std::string(profile_.name) +
                   " stitch table (docs/dat.md); use x-stitch-number");
}

bool PassBuilder::add_stitch_op(const Instruction& in, const CarrierSet& cs, std::uint32_t line) {
  const bool miss = in.op == Op::Miss;
  const bool tuck = in.op == Op::Tuck || in.op == Op::Amiss;
  if (!reject_if_split_via_sliders(line, knitout::op_name(in.op))) return false;
  Direction direction = in.direction;
  if (cs.empty()) {
    if (miss) return error(line, "D024", "miss without carriers moves nothing");
    direction = Direction::None;  // drop and a-miss have no direction
  }
  const NeedleRef needle{in.needle.bed, in.needle.index};
  if (!miss) kick_others(needle, cs);
  const bool front = in.needle.is_front();
  SlotOp op = front ? SlotOp::KnitFront : SlotOp::KnitBack;
  if (miss) op = front ? SlotOp::MissFront : SlotOp::MissBack;
  if (tuck) op = front ? SlotOp::TuckFront : SlotOp::TuckBack;
  const PassType type = tuck && cs.empty() ? PassType::AMiss : PassType::KnitTuck;
  Candidate candidate = make_candidate(type, direction, cs, slot_number(needle), op, stitch_);
  candidate.pass.presser = presser_;
  if (!handle_in(cs, candidate, line)) return false;
  if (!check_pass_carriers(cs, line)) return false;
  merge(candidate);
  set_last(cs, direction, needle);
  return true;
}

bool PassBuilder::add_split(const Instruction& in, const CarrierSet& cs, std::uint32_t line) {
  const knitout::Needle& n = in.needle;
  const knitout::Needle& t = in.needle2;
  const std::string_view op_name = knitout::op_name(in.op);
  auto misaligned = [&]() {
    return error(line, "D022",
                 "needles " + knitout::to_string(n) + " and " + knitout::to_string(t) +
                     " do not face each other at racking " + format_number(racking_));
  };
  if (n.is_back() && t.is_front()) {
    if (static_cast<double>(n.index) + racking_ != static_cast<double>(t.index)) {
      return misaligned();
    }
  } else if (n.is_front() && t.is_back()) {
    if (static_cast<double>(n.index) != static_cast<double>(t.index) + racking_) {
      return misaligned();
    }
  }
  std::optional<SlotOp> op;
  PassType type = PassType::Xfer;
  if (!n.is_slider() && !t.is_slider()) {
    if (!reject_if_split_via_sliders(line, op_name)) return false;
    if (cs.empty()) {
      type = PassType::Xfer;
      op = n.is_front() ? SlotOp::XferToBack : SlotOp::XferToFront;
    } else {
      type = PassType::Split;
      op = n.is_front() ? SlotOp::SplitToBack : SlotOp::SplitToFront;
    }
  } else if (n.is_slider() && !t.is_slider()) {
    if (!cs.empty()) return error(line, "D026", "cannot split from a slider");
    if (svs_) {
      if (!return_from_slider(n, line)) return false;
    } else {
      type = PassType::XferFromSliders;
      op = n.is_front() ? SlotOp::XferToBack : SlotOp::XferToFront;
    }
  } else if (!n.is_slider() && t.is_slider()) {
    if (cs.empty()) {
      if (!reject_if_split_via_sliders(line, op_name)) return false;
      type = PassType::XferToSliders;
      op = n.is_front() ? SlotOp::XferToBack : SlotOp::XferToFront;
    } else {
      if (!split_to_slider(n, t, line)) return false;
      type = PassType::SplitViaSliders;
      op = n.is_front() ? SlotOp::SplitToBack : SlotOp::SplitToFront;
    }
  } else {
    return error(line, "D026",
                 "cannot move loops from slider " + knitout::to_string(n) + " to slider " +
                     knitout::to_string(t));
  }
  if (!op) return true;

  const Direction direction = cs.empty() ? Direction::None : in.direction;
  const NeedleRef source{n.bed, n.index};
  kick_others(source, cs);
  Candidate candidate =
      make_candidate(type, direction, cs, slot_number(source), *op, cs.empty() ? 0 : stitch_);
  if (!handle_in(cs, candidate, line)) return false;
  if (!check_pass_carriers(cs, line)) return false;
  merge(candidate);
  // Carriers attached to the loops that just moved now hang from the target.
  for (CarrierState& state : carriers_) {
    if (state.active && state.has_last && state.last_needle == source) {
      state.last_needle = NeedleRef{t.bed, t.index};
    }
  }
  set_last(cs, direction, source);
  return true;
}

// Returning a split-via-sliders loop from slider needle n: no pass of its
// own, the split pass's colour includes the return (docs/dat.md).
bool PassBuilder::return_from_slider(const knitout::Needle& n, std::uint32_t line) {
  if (!svs_->has_return) {
    svs_->has_return = true;
    svs_->return_racking = racking_;
    if (!list_.passes.empty()) {
      list_.passes.back().has_return_racking = true;
      list_.passes.back().return_racking = racking_;
    }
  }
  if (svs_->return_racking != racking_) {
    return error(line, "D027",
                 "split-via-sliders loops return at racking " +
                     format_number(svs_->return_racking) + ", not also at " +
                     format_number(racking_));
  }
  if (svs_->needles.erase({static_cast<int>(n.bed), n.index}) == 0) {
    return error(line, "D027",
                 "no split-via-sliders loop waits on " + knitout::to_string(n) +
                     " (already returned, or never split to)");
  }
  if (svs_->needles.empty()) svs_.reset();
  return true;
}

// A split with yarn from needle n to slider t: its loop waits there to be
// returned.
bool PassBuilder::split_to_slider(const knitout::Needle& n, const knitout::Needle& t,
                                  std::uint32_t line) {
  if (!svs_) {
    svs_ = SplitViaSliders{};
    svs_->racking = racking_;
  }
  if (svs_->has_return) {
    return error(line, "D027",
                 "split to a slider while split-via-sliders loops are being returned");
  }
  if (svs_->racking != racking_) {
    return error(line, "D027",
                 "split-via-sliders at racking " + format_number(racking_) +
                     " while others were split at racking " + format_number(svs_->racking));
  }
  if (!svs_->needles.insert({static_cast<int>(t.bed), t.index}).second) {
    return error(line, "D027",
                 "split-via-sliders " + knitout::to_string(n) + " -> " + knitout::to_string(t) +
                     ": that slider already holds a split loop");
  }
  return true;
}

// Merges a one-slot pass into the last pass, or starts a new pass with it,
// first kicking its own carriers to the side they must start from. The
// carriers' stopping distance is taken as unbounded: a carrier parked on
// the wrong side of the slot is always kicked.
void PassBuilder::merge(Candidate candidate) {
  bool do_pause = pause_pending_;
  pause_pending_ = false;
  if (!list_.passes.empty() && !do_pause && append(list_.passes.back(), candidate)) return;

  const std::int64_t pass_slot = candidate.entry.slot;
  const Direction direction = candidate.pass.direction;
  std::vector<std::pair<std::int64_t, CarrierSet>> kicks;  // in first-seen order
  auto add_kick = [&](std::uint8_t c, std::int64_t slot) {
    for (auto& [s, set] : kicks) {
      if (s == slot) {
        set.ids[set.size++] = c;
        return;
      }
    }
    CarrierSet set;
    set.ids[set.size++] = c;
    kicks.emplace_back(slot, set);
  };
  for (std::uint8_t c : candidate.pass.carriers) {
    const CarrierState& state = carriers_[c];
    if (!state.has_last) continue;  // being brought in: nothing to kick
    const std::int64_t kick_slot = slot_number(state.kick_needle);
    if (state.kick_direction == Direction::Minus) {
      if (direction == Direction::Minus) {
        add_kick(c, kick_slot);
      } else if (kick_slot > pass_slot) {
        add_kick(c, pass_slot);
      }
    } else {
      if (direction == Direction::Plus) {
        add_kick(c, kick_slot);
      } else if (kick_slot < pass_slot) {
        add_kick(c, pass_slot);
      }
    }
  }
  if (kicks.empty()) {
    if (do_pause) candidate.pass.pause = true;
    push(candidate);
    return;
  }
  // Kick passes run in the order the reference's slot-keyed map iterates:
  // non-negative slots ascending, then negative slots as first seen.
  std::stable_sort(kicks.begin(), kicks.end(), [](const auto& a, const auto& b) {
    const bool a_negative = a.first < 0;
    const bool b_negative = b.first < 0;
    if (a_negative != b_negative) return !a_negative;
    if (a_negative) return false;
    return a.first < b.first;
  });
  const Direction kick_direction = opposite(direction);
  for (const auto& [slot, set] : kicks) {
    Candidate kick =
        make_candidate(PassType::KnitTuck, kick_direction, set, slot, SlotOp::SoftMiss, stitch_);
    if (do_pause) {
      kick.pass.pause = true;
      do_pause = false;
    }
    merge(kick);
    for (std::uint8_t c : set) {
      carriers_[c].kick_needle = NeedleRef{Bed::Front, slot};
      carriers_[c].kick_direction = kick_direction;
    }
  }
  if (do_pause) candidate.pass.pause = true;
  merge(candidate);
}

bool PassBuilder::append(Pass& last, const Candidate& next) {
  const Pass& pass = next.pass;
  if (pass.pause) return false;
  if (last.type != pass.type || last.racking != pass.racking || last.stitch != pass.stitch ||
      last.speed != pass.speed || last.direction != pass.direction ||
      !(last.carriers == pass.carriers)) {
    return false;
  }
  if (last.presser != Presser::Unset && pass.presser != Presser::Unset &&
      last.presser != pass.presser) {
    return false;
  }
  const SlotOpInfo& next_info = info(next.entry.op);
  if (last.presser == Presser::On) {
    // The presser cannot work a pass that mixes front and back stitches.
    if (last.has_front && next_info.back) return false;
    if (last.has_back && next_info.front) return false;
    if (pass.hook != Hook::None) return false;
  }
  // Hook in / release only at the start of a pass, hook out only at its end;
  // the same for the grippers.
  const bool hook_ok =
      (last.hook == Hook::None && pass.hook == Hook::None) ||
      ((last.hook == Hook::In || last.hook == Hook::Release) && pass.hook == Hook::None) ||
      (last.hook == Hook::None && pass.hook == Hook::Out);
  if (!hook_ok) return false;
  const bool gripper_ok = (last.gripper == Gripper::None && pass.gripper == Gripper::None) ||
                          (last.gripper == Gripper::In && pass.gripper == Gripper::None) ||
                          (last.gripper == Gripper::None && pass.gripper == Gripper::Out);
  if (!gripper_ok) return false;

  // The slot must be free, or its op must combine with the new one. In a
  // directed pass slots only grow in the pass direction, so the one slot that
  // can collide is the newest entry.
  const bool quarter = is_quarter_pitch(last.racking);
  const std::int64_t slot = next.entry.slot;
  SlotEntry* existing = nullptr;
  std::optional<SlotOp> merged;
  if (last.direction == Direction::Plus || last.direction == Direction::Minus) {
    const bool plus = last.direction == Direction::Plus;
    const std::int64_t edge = plus ? last.max_slot : last.min_slot;
    if (plus ? slot < edge : slot > edge) return false;
    if (slot == edge) {
      existing = &list_.entries[last.first_entry + last.entry_count - 1];
      merged = plus ? merge_ops(existing->op, next.entry.op, quarter)
                    : merge_ops(next.entry.op, existing->op, quarter);
      if (!merged) return false;
    }
  } else {
    auto found = open_slots_.find(slot);
    if (found != open_slots_.end()) {
      existing = &list_.entries[found->second];
      merged = merge_ops(existing->op, next.entry.op, quarter);
      if (!merged) merged = merge_ops(next.entry.op, existing->op, quarter);
      if (!merged) return false;
    }
  }

  if (pass.presser != Presser::Unset) last.presser = pass.presser;
  if (last.hook == Hook::None) last.hook = pass.hook;
  if (last.gripper == Gripper::None) last.gripper = pass.gripper;
  if (existing != nullptr) {
    existing->op = *merged;
  } else {
    const auto index = static_cast<std::uint32_t>(list_.entries.size());
    list_.entries.push_back(next.entry);
    ++last.entry_count;
    if (last.direction == Direction::None) open_slots_.emplace(slot, index);
    last.min_slot = std::min(last.min_slot, slot);
    last.max_slot = std::max(last.max_slot, slot);
  }
  last.has_front = last.has_front || next_info.front;
  last.has_back = last.has_back || next_info.back;
  return true;
}

void PassBuilder::push(const Candidate& candidate) {
  Pass pass = candidate.pass;
  pass.first_entry = static_cast<std::uint32_t>(list_.entries.size());
  pass.entry_count = 1;
  pass.min_slot = pass.max_slot = candidate.entry.slot;
  pass.has_front = info(candidate.entry.op).front;
  pass.has_back = info(candidate.entry.op).back;
  list_.entries.push_back(candidate.entry);
  list_.passes.push_back(pass);
  open_slots_.clear();
  if (pass.direction == Direction::None)
    open_slots_.emplace(candidate.entry.slot, pass.first_entry);
}

bool PassBuilder::finish(std::uint32_t last_line) {
  if (failed_) return false;
  std::string left_in;
  std::uint32_t first_line = 0;
  for (std::uint8_t c = 1; c <= 10; ++c) {
    if (!carriers_[c].active) continue;
    if (!left_in.empty()) left_in += ", ";
    left_in += std::to_string(c);
    if (first_line == 0) first_line = carriers_[c].in_line;
  }
  if (!left_in.empty()) {
    return error(first_line, "D018",
                 "carriers still in at the end of the file: " + left_in +
                     " (each needs 'out' or 'outhook')");
  }
  if (list_.passes.empty()) {
    return error(last_line, "D029", "nothing to knit: the program forms no carriage pass");
  }
  return true;
}

std::optional<PassList> form_passes(std::istream& in, std::string source,
                                    knitout::DiagnosticSink& sink, const Profile& profile) {
  knitout::Reader reader(in, source, sink);
  PassBuilder builder(source, sink, profile);
  if (!sink.has_errors()) builder.begin(reader.has_magic(), reader.headers());
  Instruction instruction;
  while (reader.next(instruction)) {
    // After the first error the rest is only read for its syntax errors.
    if (sink.has_errors()) continue;
    builder.add(instruction, reader.carriers(), reader.text());
  }
  if (sink.has_errors()) return std::nullopt;
  if (!builder.finish(static_cast<std::uint32_t>(reader.lines_read()))) return std::nullopt;
  return builder.take_passes();
}

std::optional<PassList> form_passes(const knitout::Program& program, std::string source,
                                    knitout::DiagnosticSink& sink, const Profile& profile) {
  PassBuilder builder(source, sink, profile);
  if (!builder.begin(program.has_magic, program.headers)) return std::nullopt;
  std::uint32_t last_line = 0;
  for (const Instruction& instruction : program.instructions) {
    if (!builder.add(instruction, program.carriers, program.text(instruction))) {
      return std::nullopt;
    }
    last_line = instruction.line;
  }
  if (!builder.finish(last_line)) return std::nullopt;
  return builder.take_passes();
}

}  // namespace dat
