// PassBuilder (passes.hpp): carriers in and out, the hook, the carriers of
// a pass and the kicks that move other carriers out of its way.
#include <algorithm>
#include <cmath>

#include "backends/dat/passes.hpp"

namespace dat {

using knitout::Bed;
using knitout::Direction;
using knitout::Instruction;
using knitout::Op;
using knitout::opposite;

bool PassBuilder::add_in(const Instruction& in, const CarrierSet& cs, std::uint32_t line) {
  const std::string_view op = in.op == Op::In ? "in" : "inhook";
  if (!reject_if_split_via_sliders(line, op)) return false;
  for (std::size_t i = 0; i < cs.size; ++i) {
    if (cs.ids[i] == 0) {
      return error(line, "D010",
                   "carrier '" + table_->name(in.carriers[i]) +
                       "' is not named in the Carriers header (1 to 10)");
    }
  }
  for (std::uint8_t c : cs) {
    if (carriers_[c].active) {
      return error(line, "D011",
                   "carrier " + std::to_string(c) + " is already in (brought in at line " +
                       std::to_string(carriers_[c].in_line) + ")");
    }
  }
  in_infos_.push_back({in.op == Op::Inhook, cs});
  for (std::uint8_t c : cs) {
    CarrierState& state = carriers_[c];
    state = CarrierState{};
    state.active = true;
    state.in_info = static_cast<int>(in_infos_.size() - 1);
    state.used_hook = in.op == Op::Inhook;
    state.in_line = line;
  }
  return true;
}

bool PassBuilder::add_releasehook(const CarrierSet& cs, std::uint32_t line) {
  if (!reject_if_split_via_sliders(line, "releasehook")) return false;
  if (!hook_) {
    return error(line, "D015",
                 "releasehook " + instruction_carriers() +
                     ": the hook holds nothing (it takes hold at the first stitch after "
                     "inhook)");
  }
  if (!(hook_->second == cs)) {
    return error(line, "D015",
                 "releasehook " + instruction_carriers() + ": the hook holds carriers " +
                     name_list(hook_->second));
  }
  for (std::uint8_t c : cs) carriers_[c].used_hook = false;
  // The machine releases before the pass starts, so the release gets a
  // pass of its own, without carriers; KnitPaint refuses a release on a
  // carriage-move row, hence the empty opposite pass before it when the
  // previous pass went the same way.
  const Direction direction = hook_->first;
  const std::int64_t slot = slot_number(carriers_[cs.ids[0]].last_needle);
  if (!list_.passes.empty() && list_.passes.back().direction == direction) {
    push(make_candidate(PassType::KnitTuck, opposite(direction), CarrierSet{}, slot,
                        SlotOp::SoftMiss, stitch_));
  }
  Candidate release =
      make_candidate(PassType::KnitTuck, direction, CarrierSet{}, slot, SlotOp::SoftMiss, stitch_);
  release.pass.hook = Hook::Release;
  push(release);
  hook_.reset();
  return true;
}

bool PassBuilder::add_out(const Instruction& in, const CarrierSet& cs, std::uint32_t line) {
  const bool outhook = in.op == Op::Outhook;
  if (!reject_if_split_via_sliders(line, outhook ? "outhook" : "out")) return false;
  for (std::size_t i = 0; i < cs.size; ++i) {
    const std::uint8_t c = cs.ids[i];
    const std::string name = table_->name(in.carriers[i]);
    if (c == 0 || !carriers_[c].active) {
      return error(line, "D016", "carrier '" + name + "' is not in, so it cannot go out");
    }
    if (!carriers_[c].has_last) {
      return error(line, "D016",
                   "carrier " + name + " has not made a stitch since 'in' (line " +
                       std::to_string(carriers_[c].in_line) + "), so it cannot go out");
    }
    if (!outhook && carriers_[c].used_hook) {
      return error(line, "D017",
                   "out " + name +
                       ": the carrier came in with inhook and the hook still holds it; "
                       "releasehook first, or use outhook");
    }
  }
  if (outhook && hook_) {
    return error(line, "D017",
                 "outhook " + instruction_carriers() + ": the hook still holds carriers " +
                     name_list(hook_->second) + "; releasehook first");
  }
  // A rightward carrier move at the rightmost last stitch of the set,
  // out to the grippers at its end.
  std::int64_t best = 0;
  NeedleRef needle;
  bool found = false;
  for (std::uint8_t c : cs) {
    const std::int64_t slot = slot_number(carriers_[c].last_needle);
    if (!found || slot > best) {
      best = slot;
      needle = carriers_[c].last_needle;
      found = true;
    }
  }
  if (!check_pass_carriers(cs, line)) return false;
  Candidate candidate = make_candidate(PassType::KnitTuck, Direction::Plus, cs, slot_number(needle),
                                       SlotOp::SoftMiss, stitch_);
  candidate.pass.gripper = Gripper::Out;
  if (outhook) candidate.pass.hook = Hook::Out;
  merge(candidate);
  for (std::uint8_t c : cs) carriers_[c] = CarrierState{};
  return true;
}

bool PassBuilder::check_pass_carriers(const CarrierSet& cs, std::uint32_t line) {
  if (cs.size < 3) return true;
  return error(line, "D025",
               "a pass with " + std::to_string(cs.size) + " carriers (" + name_list(cs) +
                   "): the DAT yarn-carrier option notates at most two carriers per pass");
}

bool PassBuilder::handle_in(const CarrierSet& cs, Candidate& candidate, std::uint32_t line) {
  if (cs.empty()) return true;
  int pending = -1;
  for (std::size_t i = 0; i < cs.size; ++i) {
    const std::uint8_t c = cs.ids[i];
    if (c == 0 || !carriers_[c].active) {
      return error(line, "D014",
                   "carrier '" + table_->name(current_->carriers[i]) +
                       "' is used but not in (bring it in with 'in' or 'inhook')");
    }
    if (carriers_[c].in_info >= 0) {
      pending = carriers_[c].in_info;
      carriers_[c].in_info = -1;
    }
  }
  if (pending < 0) return true;
  const InInfo& in_info = in_infos_[static_cast<std::size_t>(pending)];
  if (!(in_info.carriers == cs)) {
    return error(line, "D012",
                 "first use of carriers " + name_list(cs) +
                     " does not match the set brought in together: " + name_list(in_info.carriers));
  }
  candidate.pass.gripper = Gripper::In;
  if (in_info.hook) {
    candidate.pass.hook = Hook::In;
    if (hook_) {
      return error(line, "D013",
                   "cannot bring in carriers " + name_list(cs) +
                       " with the hook: it still holds carriers " + name_list(hook_->second) +
                       " (releasehook first)");
    }
    hook_.emplace(candidate.pass.direction, cs);
  }
  return true;
}

void PassBuilder::set_last(const CarrierSet& cs, Direction direction, NeedleRef needle) {
  for (std::uint8_t c : cs) {
    CarrierState& state = carriers_[c];
    state.has_last = true;
    state.last_needle = needle;
    state.last_direction = direction;
    state.kick_needle = needle;
    state.kick_direction = direction;
  }
}

// Moves every other active carrier off the needle about to be worked: a
// carrier attached left of it must be parked left of it, one attached right
// parked right. Carriers are visited in carrier-number order.
void PassBuilder::kick_others(NeedleRef needle, const CarrierSet& cs) {
  const std::int64_t needle_slot = slot_number(needle);
  for (std::uint8_t c = 1; c <= 10; ++c) {
    CarrierState& state = carriers_[c];
    if (!state.active || cs.contains(c) || !state.has_last) continue;
    const std::int64_t last_slot = slot_number(state.last_needle);
    // The yarn hangs just left (direction -) or right (+) of its last needle.
    const bool left = last_slot < needle_slot ||
                      (last_slot == needle_slot && state.last_direction == Direction::Minus);
    const std::int64_t kick_slot = slot_number(state.kick_needle);
    const Direction want = left ? Direction::Minus : Direction::Plus;
    const bool parked = left
                            ? (state.kick_direction == Direction::Minus && kick_slot <= needle_slot)
                            : (state.kick_direction == Direction::Plus && kick_slot >= needle_slot);
    if (parked) continue;
    CarrierSet one;
    one.ids[one.size++] = c;
    merge(make_candidate(PassType::KnitTuck, want, one, last_slot, SlotOp::SoftMiss, stitch_));
    state.kick_direction = want;
    state.kick_needle = NeedleRef{Bed::Front, last_slot};
  }
}

}  // namespace dat
