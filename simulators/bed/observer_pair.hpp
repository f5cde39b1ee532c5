// Two observers of one machine run (bed::Observer, machine.hpp): each event
// goes to both, in order; a null observer is skipped.
#pragma once

#include <cstdint>
#include <span>

#include "simulators/bed/machine.hpp"

namespace bed {

class ObserverPair : public Observer {
 public:
  ObserverPair(Observer* first, Observer* second) : first_(first), second_(second) {}
  void loop_made(const LoopEvent& e) override {
    for (Observer* o : {first_, second_})
      if (o) o->loop_made(e);
  }
  void loops_moved(knitout::Needle from, knitout::Needle to, int count,
                   std::uint32_t line) override {
    for (Observer* o : {first_, second_})
      if (o) o->loops_moved(from, to, count, line);
  }
  void loops_dropped(knitout::Needle needle, std::span<const LiveLoop> loops,
                     std::uint32_t line) override {
    for (Observer* o : {first_, second_})
      if (o) o->loops_dropped(needle, loops, line);
  }
  void racked(double racking, std::uint32_t line) override {
    for (Observer* o : {first_, second_})
      if (o) o->racked(racking, line);
  }
  void sweep_ended(const Machine& machine, std::uint32_t line) override {
    for (Observer* o : {first_, second_})
      if (o) o->sweep_ended(machine, line);
  }

 private:
  Observer* first_;
  Observer* second_;
};

}  // namespace bed
