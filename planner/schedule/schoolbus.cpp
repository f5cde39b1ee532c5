#include "planner/schedule/schoolbus.hpp"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace planner {
namespace {

struct Rider {
  int at;
  int to;
  int back = 0;  // the back needle it boards this round (`at` unless it boards offset)
};

// One round's choices: who rides, and where each gets off on the way.
struct Round {
  std::vector<std::size_t> riding;  // rider indices, ascending
  // Riders that get off before their destination: the racking step of
  // their stop; 0 for one that boards offset and gets off at its
  // destination.
  std::map<std::size_t, int> stop_step;
  std::set<int> waiting_at;  // needles of riders that wait this round
};

class Bus {
 public:
  Bus(const std::vector<LoopMove>& moves, const std::function<bool(int)>& occupied, int max_racking)
      : occupied_(occupied), max_racking_(max_racking) {
    // One rider per needle that moves.
    std::map<int, int> to_of;  // from -> to
    for (const LoopMove& m : moves) {
      if (m.from == m.to) continue;
      auto [it, added] = to_of.emplace(m.from, m.to);
      if (!added && it->second != m.to)
        throw std::logic_error("schoolbus: two loops on needle " + std::to_string(m.from) +
                               " want different needles");
    }
    for (const LoopMove& m : moves) {
      if (m.from == m.to && to_of.count(m.from) != 0)
        throw std::logic_error("schoolbus: a loop on needle " + std::to_string(m.from) +
                               " both stays and moves");
    }
    for (const auto& [from, to] : to_of) riders_.push_back({from, to, from});
  }

  std::vector<Transfer> run() {
    std::vector<Transfer> plan;
    while (true) {
      const std::vector<std::size_t> aboard = still_to_go();
      if (aboard.empty()) break;
      const Round round = choose(aboard);
      if (round.riding.empty())
        throw NoTransferRoute("the loops on needle f" + std::to_string(*round.waiting_at.begin()) +
                              " find no free needle within the racking limit on their way");
      board(round, plan);
      ride(round, plan);
    }
    return plan;
  }

 private:
  // Riders not at their destination. They choose their stops front first
  // in their direction of travel: a rider ahead takes the furthest free
  // stop, and those behind it take shorter steps rather than wait behind
  // it (a rider that waits falls behind riders going less far, whose
  // arrived loops may then fill its way for more than the racking limit).
  std::vector<std::size_t> still_to_go() const {
    std::vector<std::size_t> aboard;
    for (std::size_t i = 0; i < riders_.size(); ++i) {
      if (riders_[i].at != riders_[i].to) aboard.push_back(i);
    }
    std::sort(aboard.begin(), aboard.end(), [&](std::size_t a, std::size_t b) {
      const Rider& ra = riders_[a];
      const Rider& rb = riders_[b];
      const bool right_a = ra.to > ra.at;
      const bool right_b = rb.to > rb.at;
      if (right_a != right_b) return right_a;
      return right_a ? ra.at > rb.at : ra.at < rb.at;
    });
    return aboard;
  }

  // Needles riders get off at this round: their destinations when within
  // reach, else the furthest needle within reach that is empty (no loop
  // that stays, no rider that arrived or waits) and that nobody else gets
  // off at. A rider with no such needle waits on its own needle this
  // round; the needles of waiting riders are then taken, so the choice is
  // made again until nobody else has to wait.
  Round choose(const std::vector<std::size_t>& aboard) {
    Round round;
    std::set<int> offset_back;  // back needles of riders that board offset
    while (true) {
      std::set<int> reserved = round.waiting_at;
      offset_back.clear();
      for (Rider& rider : riders_) rider.back = rider.at;
      for (std::size_t i : aboard) {
        if (std::abs(riders_[i].to - riders_[i].at) <= max_racking_) reserved.insert(riders_[i].to);
      }
      round.stop_step.clear();
      std::vector<std::size_t> moving;
      bool more_wait = false;
      for (std::size_t i : aboard) {
        if (round.waiting_at.count(riders_[i].at) != 0) continue;
        bool rides = true;
        if (std::abs(riders_[i].to - riders_[i].at) <= max_racking_) {
          // Its destination still holds a rider that waits: it waits too.
          rides = round.waiting_at.count(riders_[i].to) == 0;
        } else {
          rides = find_stop(i, round.stop_step, reserved, offset_back);
        }
        if (rides) {
          moving.push_back(i);
        } else {
          round.waiting_at.insert(riders_[i].at);
          more_wait = true;
        }
      }
      if (!more_wait) {
        round.riding = std::move(moving);
        std::sort(round.riding.begin(), round.riding.end());
        return round;
      }
    }
  }

  // A stop on the way for rider i, further than the racking limit from its
  // destination: the furthest free needle within reach, or else (at most
  // twice the limit to go) an offset boarding. False when it must wait.
  bool find_stop(std::size_t i, std::map<std::size_t, int>& stop_step, std::set<int>& reserved,
                 std::set<int>& offset_back) {
    const int left = riders_[i].to - riders_[i].at;
    const int sign = left > 0 ? 1 : -1;
    for (int step = max_racking_; step >= 1; --step) {
      const int stop = riders_[i].at + sign * step;
      if (occupied_(stop) || arrived_.count(stop) != 0 || reserved.count(stop) != 0) continue;
      stop_step[i] = step;
      reserved.insert(stop);
      return true;
    }
    if (std::abs(left) > 2 * max_racking_) return false;
    // No free stop on the way: board at a racking against the travel,
    // onto a back needle ahead that no rider boards, and get off at the
    // destination in the same round (twice the reach of a stop).
    const bool destination_is_a_stop =
        std::any_of(stop_step.begin(), stop_step.end(), [&](const auto& chosen) {
          const Rider& r = riders_[chosen.first];
          return chosen.second > 0 &&
                 r.at + (r.to > r.at ? 1 : -1) * chosen.second == riders_[i].to;
        });
    for (int k = std::max(1, std::abs(left) - max_racking_);
         k <= max_racking_ && !destination_is_a_stop; ++k) {
      if (k == std::abs(left)) continue;  // that back needle faces the destination
      const int back = riders_[i].at + sign * k;
      if (offset_back.count(back) != 0) continue;
      if (std::any_of(riders_.begin(), riders_.end(),
                      [&](const Rider& r) { return r.at != r.to && r.at == back; }))
        continue;
      riders_[i].back = back;
      offset_back.insert(back);
      reserved.insert(riders_[i].to);
      stop_step[i] = 0;
      return true;
    }
    return false;
  }

  // Everyone riding boards the back bed: at racking 0 first, then those
  // that board offset.
  void board(const Round& round, std::vector<Transfer>& plan) const {
    for (std::size_t i : round.riding) {
      if (riders_[i].back == riders_[i].at) plan.push_back({0, true, riders_[i].at, riders_[i].at});
    }
    for (std::size_t i : round.riding) {
      if (riders_[i].back != riders_[i].at)
        plan.push_back({riders_[i].at - riders_[i].back, true, riders_[i].at, riders_[i].back});
    }
  }

  // The bed racks 1, 2, ... up to the limit, then -1, -2, ...; each rider
  // gets off at its stop or destination when the racking reaches it.
  void ride(const Round& round, std::vector<Transfer>& plan) {
    std::map<int, int> landing;  // front needle -> destination of who got off there
    // A rider gets off once per round: one that stopped on its way (at a
    // positive racking) must not ride on from its stop later in the round.
    std::set<std::size_t> got_off;
    for (int sign : {+1, -1}) {
      for (int step = 1; step <= max_racking_; ++step) {
        const int r = sign * step;
        for (std::size_t i : round.riding) {
          if (got_off.count(i) != 0) continue;
          Rider& rider = riders_[i];
          const int left = rider.to - rider.back;
          if (left == 0 || (left > 0) != (sign > 0)) continue;
          const auto chosen = round.stop_step.find(i);
          if (left != r && !(chosen != round.stop_step.end() && chosen->second == step)) continue;
          const int stop = rider.back + r;
          auto it = landing.find(stop);
          if (it != landing.end() && (it->second != rider.to || stop != rider.to))
            throw std::logic_error("schoolbus: f" + std::to_string(stop) + " is taken");
          landing[stop] = rider.to;
          plan.push_back({r, false, stop, rider.back});
          rider.at = stop;
          rider.back = stop;
          got_off.insert(i);
          if (rider.at == rider.to) arrived_.insert(stop);
        }
      }
    }
  }

  const std::function<bool(int)>& occupied_;
  const int max_racking_;
  std::vector<Rider> riders_;
  std::set<int> arrived_;  // front needles holding riders that reached their destination
};

}  // namespace

std::vector<Transfer> schoolbus(const std::vector<LoopMove>& moves,
                                const std::function<bool(int)>& occupied, int max_racking) {
  if (max_racking < 1) throw std::logic_error("schoolbus: racking limit below 1");
  return Bus(moves, occupied, max_racking).run();
}

}  // namespace planner
