#include "planner/schedule/schoolbus.hpp"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace planner {

std::vector<Transfer> schoolbus(const std::vector<LoopMove>& moves,
                                const std::function<bool(int)>& occupied, int max_racking) {
  if (max_racking < 1) throw std::logic_error("schoolbus: racking limit below 1");
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
  struct Rider {
    int at;
    int to;
    int back = 0;  // the back needle it boards this round (`at` unless it boards offset)
  };
  std::vector<Rider> riders;
  for (const auto& [from, to] : to_of) riders.push_back({from, to, from});
  std::vector<Transfer> plan;
  std::set<int> arrived;  // front needles holding riders that reached their destination
  while (true) {
    std::vector<std::size_t> aboard;
    for (std::size_t i = 0; i < riders.size(); ++i) {
      if (riders[i].at != riders[i].to) aboard.push_back(i);
    }
    if (aboard.empty()) break;
    // Riders choose their stops front first in their direction of travel: a
    // rider ahead takes the furthest free stop, and those behind it take
    // shorter steps rather than wait behind it (a rider that waits falls
    // behind riders going less far, whose arrived loops may then fill its
    // way for more than the racking limit).
    std::sort(aboard.begin(), aboard.end(), [&](std::size_t a, std::size_t b) {
      const Rider& ra = riders[a];
      const Rider& rb = riders[b];
      const bool right_a = ra.to > ra.at;
      const bool right_b = rb.to > rb.at;
      if (right_a != right_b) return right_a;
      return right_a ? ra.at > rb.at : ra.at < rb.at;
    });
    // Needles riders get off at this round: their destinations when within
    // reach, else the furthest needle within reach that is empty (no loop
    // that stays, no rider that arrived or waits) and that nobody else gets
    // off at. A rider with no such needle waits on its own needle this
    // round; the needles of waiting riders are then taken, so the choice is
    // made again until nobody else has to wait.
    std::map<std::size_t, int> stop_step;
    std::set<int> waiting_at;
    std::set<int> offset_back;  // back needles of riders that board offset
    while (true) {
      std::set<int> reserved = waiting_at;
      offset_back.clear();
      for (Rider& rider : riders) rider.back = rider.at;
      for (std::size_t i : aboard) {
        if (std::abs(riders[i].to - riders[i].at) <= max_racking) reserved.insert(riders[i].to);
      }
      stop_step.clear();
      std::vector<std::size_t> moving;
      bool more_wait = false;
      for (std::size_t i : aboard) {
        if (waiting_at.count(riders[i].at) != 0) continue;
        const int left = riders[i].to - riders[i].at;
        if (std::abs(left) <= max_racking) {
          // Its destination still holds a rider that waits: it waits too.
          if (waiting_at.count(riders[i].to) != 0) {
            waiting_at.insert(riders[i].at);
            more_wait = true;
          } else {
            moving.push_back(i);
          }
          continue;
        }
        const int sign = left > 0 ? 1 : -1;
        for (int step = max_racking; step >= 1; --step) {
          const int stop = riders[i].at + sign * step;
          if (occupied(stop) || arrived.count(stop) != 0 || reserved.count(stop) != 0) continue;
          stop_step[i] = step;
          reserved.insert(stop);
          break;
        }
        if (stop_step.count(i) == 0 && std::abs(left) <= 2 * max_racking) {
          // No free stop on the way: board at a racking against the travel,
          // onto a back needle ahead that no rider boards, and get off at
          // the destination in the same round (twice the reach of a stop).
          const bool destination_is_a_stop =
              std::any_of(stop_step.begin(), stop_step.end(), [&](const auto& chosen) {
                const Rider& r = riders[chosen.first];
                return chosen.second > 0 &&
                       r.at + (r.to > r.at ? 1 : -1) * chosen.second == riders[i].to;
              });
          for (int k = std::max(1, std::abs(left) - max_racking);
               k <= max_racking && !destination_is_a_stop; ++k) {
            if (k == std::abs(left)) continue;  // that back needle faces the destination
            const int back = riders[i].at + sign * k;
            if (offset_back.count(back) != 0) continue;
            if (std::any_of(riders.begin(), riders.end(),
                            [&](const Rider& r) { return r.at != r.to && r.at == back; }))
              continue;
            riders[i].back = back;
            offset_back.insert(back);
            reserved.insert(riders[i].to);
            stop_step[i] = 0;
            break;
          }
        }
        if (stop_step.count(i) != 0) {
          moving.push_back(i);
        } else {
          waiting_at.insert(riders[i].at);
          more_wait = true;
        }
      }
      if (!more_wait) {
        aboard = std::move(moving);
        std::sort(aboard.begin(), aboard.end());
        break;
      }
    }
    if (aboard.empty())
      throw std::logic_error("schoolbus: no free needle within reach of f" +
                             std::to_string(*waiting_at.begin()));
    for (std::size_t i : aboard) {
      if (riders[i].back == riders[i].at) plan.push_back({0, true, riders[i].at, riders[i].at});
    }
    for (std::size_t i : aboard) {
      if (riders[i].back != riders[i].at)
        plan.push_back({riders[i].at - riders[i].back, true, riders[i].at, riders[i].back});
    }
    std::map<int, int> landing;  // front needle -> destination of who got off there
    // A rider gets off once per round: one that stopped on its way (at a
    // positive racking) must not ride on from its stop later in the round.
    std::set<std::size_t> got_off;
    for (int sign : {+1, -1}) {
      for (int step = 1; step <= max_racking; ++step) {
        const int r = sign * step;
        for (std::size_t i : aboard) {
          if (got_off.count(i) != 0) continue;
          Rider& rider = riders[i];
          const int left = rider.to - rider.back;
          if (left == 0 || (left > 0) != (sign > 0)) continue;
          const auto chosen = stop_step.find(i);
          if (left != r && !(chosen != stop_step.end() && chosen->second == step)) continue;
          const int stop = rider.back + r;
          auto it = landing.find(stop);
          if (it != landing.end() && (it->second != rider.to || stop != rider.to))
            throw std::logic_error("schoolbus: f" + std::to_string(stop) + " is taken");
          landing[stop] = rider.to;
          plan.push_back({r, false, stop, rider.back});
          rider.at = stop;
          rider.back = stop;
          got_off.insert(i);
          if (rider.at == rider.to) arrived.insert(stop);
        }
      }
    }
  }
  return plan;
}

}  // namespace planner
