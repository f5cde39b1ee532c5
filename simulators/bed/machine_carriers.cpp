// bed::Machine (machine.hpp): carriers in and out, the yarn-inserting hook,
// and the carriers each stitch uses.
#include <algorithm>
#include <string>

#include "simulators/bed/machine.hpp"

namespace bed {

using knitout::CarrierId;
using knitout::CarrierList;
using knitout::Instruction;
using knitout::Op;

// ---------------------------------------------------------------- carriers

std::uint16_t Machine::yarn_id(const CarrierList& carriers) {
  if (last_yarn_ < yarns_.size() && yarns_[last_yarn_] == carriers) return last_yarn_;
  for (std::size_t i = 0; i < yarns_.size(); ++i) {
    if (yarns_[i] == carriers) {
      last_yarn_ = static_cast<std::uint16_t>(i);
      return last_yarn_;
    }
  }
  if (yarns_.size() >= 0xffff) return 0;  // 65535 distinct carrier sets: share the first
  yarns_.push_back(carriers);
  last_yarn_ = static_cast<std::uint16_t>(yarns_.size() - 1);
  return last_yarn_;
}

void Machine::op_in(const Instruction& in, bool hook) {
  if (hook && !profile_.has_inserting_hook) {
    error(in, "V015", "machine " + profile_.name + " has no yarn-inserting hook; use in");
  }
  for (CarrierId id : in.carriers) {
    const std::string& name = names_.name(id);
    if (!profile_.carrier_exists(name)) {
      error(in, "V001", "carrier " + quote(name) + " does not exist on machine " + profile_.name);
      continue;
    }
    if (header_carriers_ && id >= *header_carriers_) {
      error(in, "V002", "carrier " + quote(name) + " is not named in the ';;Carriers:' header");
      continue;
    }
    CarrierState& st = carriers_[id];
    if (st.status != CarrierStatus::Out) {
      error(in, "V003",
            "cannot bring in carrier " + quote(name) + ": it is already in (since line " +
                std::to_string(st.in_line) + ")");
      continue;
    }
    st = CarrierState{};
    st.status = hook ? CarrierStatus::PendingInhook : CarrierStatus::PendingIn;
    st.hook_held = hook;
    st.in_set = in.carriers;
    st.in_line = in.line;
    active_.push_back(id);
    carrier_stats(id);
  }
}

// The first use of carriers that are pending `in`/`inhook` brings them in;
// returns false when a carrier cannot be used (reported).
bool Machine::use_carriers(const Instruction& in) {
  bool ok = true;
  const CarrierState* pending = nullptr;
  for (CarrierId id : in.carriers) {
    CarrierState& st = carriers_[id];
    if (st.status == CarrierStatus::Out) {
      const std::string& name = names_.name(id);
      if (!profile_.carrier_exists(name)) {
        error(in, "V001", "carrier " + quote(name) + " does not exist on machine " + profile_.name);
      } else {
        error(
            in, "V004",
            "carrier " + quote(name) + " is not in; bring it in with in or inhook before using it");
      }
      // Carry on as if it had been brought in, so one mistake is reported once.
      st = CarrierState{};
      st.status = CarrierStatus::In;
      st.implicit = true;
      st.in_line = in.line;
      active_.push_back(id);
      ok = false;
    } else if (st.status != CarrierStatus::In) {
      pending = &st;
    }
  }
  if (pending != nullptr) {
    const bool hook = pending->status == CarrierStatus::PendingInhook;
    if (!(pending->in_set == in.carriers)) {
      error(in, "V005",
            "first use of carriers " + quote(carrier_list_text(in.carriers)) +
                " does not match the " + (hook ? "inhook" : "in") + " of " +
                quote(carrier_list_text(pending->in_set)) + " at line " +
                std::to_string(pending->in_line) +
                "; carriers brought in together are first used together");
      ok = false;
    }
    if (hook) {
      if (hook_busy_) {
        error(in, "V006",
              "cannot bring in " + quote(carrier_list_text(in.carriers)) +
                  " on the yarn-inserting hook: it still holds " +
                  quote(carrier_list_text(hook_carriers_)) + "; releasehook them first");
        ok = false;
      } else {
        hook_busy_ = true;
        hook_carriers_ = in.carriers;
      }
    }
    for (CarrierId id : in.carriers) {
      CarrierState& st = carriers_[id];
      if (st.status == CarrierStatus::PendingIn || st.status == CarrierStatus::PendingInhook) {
        st.status = CarrierStatus::In;
      }
    }
  }
  for (CarrierId id : in.carriers) carriers_[id].used = true;
  return ok;
}

void Machine::move_carriers(const Instruction& in) {
  for (CarrierId id : in.carriers) {
    CarrierState& st = carriers_[id];
    st.needle = in.needle;
    st.side = in.direction;
  }
}

void Machine::op_releasehook(const Instruction& in) {
  end_sweep(in.line);
  if (!hook_busy_) {
    std::string message =
        "releasehook " + carrier_list_text(in.carriers) + ": the hook holds nothing";
    for (CarrierId id : in.carriers) {
      const CarrierState& st = carriers_[id];
      if (st.status == CarrierStatus::PendingInhook) {
        message += "; carrier " + quote(names_.name(id)) + " (inhook at line " +
                   std::to_string(st.in_line) +
                   ") has not stitched yet: the hook takes its yarn at the first stitch";
        break;
      }
    }
    error(in, "V007", std::move(message));
    return;
  }
  if (!(hook_carriers_ == in.carriers)) {
    error(in, "V008",
          "releasehook " + quote(carrier_list_text(in.carriers)) + ": the hook holds " +
              quote(carrier_list_text(hook_carriers_)));
    return;
  }
  for (CarrierId id : hook_carriers_) carriers_[id].hook_held = false;
  hook_busy_ = false;
  hook_carriers_.clear();
}

void Machine::op_out(const Instruction& in, bool hook) {
  end_sweep(in.line);
  for (CarrierId id : in.carriers) {
    const CarrierState& st = carriers_[id];
    const std::string& name = names_.name(id);
    if (st.status == CarrierStatus::Out) {
      error(in, "V009", "cannot take out carrier " + quote(name) + ": it is not in");
    } else if (!st.used) {
      error(in, "V010",
            "cannot take out carrier " + quote(name) + ": it has not been used since it came in" +
                " at line " + std::to_string(st.in_line));
    } else if (!hook && st.hook_held) {
      error(in, "V011",
            "cannot take out carrier " + quote(name) +
                " with out: the yarn-inserting hook still holds it (inhook at line " +
                std::to_string(st.in_line) + "); releasehook it first, or use outhook");
    }
  }
  if (hook && hook_busy_) {
    error(in, "V012",
          "outhook " + quote(carrier_list_text(in.carriers)) +
              ": the yarn-inserting hook still holds " + quote(carrier_list_text(hook_carriers_)) +
              "; releasehook first");
  }
  for (CarrierId id : in.carriers) {
    CarrierState& st = carriers_[id];
    if (st.status == CarrierStatus::Out) continue;
    st.status = CarrierStatus::Out;
    active_.erase(std::find(active_.begin(), active_.end(), id));
  }
  if (hook_busy_) {
    bool any_in = false;
    for (CarrierId id : hook_carriers_) any_in |= carriers_[id].status != CarrierStatus::Out;
    if (!any_in) {
      hook_busy_ = false;
      hook_carriers_.clear();
    }
  }
}

}  // namespace bed
