// bed::KnitGraph: every loop a program makes, for yarn-level viewers.
//
// Attach it to a Machine as its Observer (MachineOptions::observer); it
// keeps one record per loop (so memory grows with the program, unlike the
// machine itself). `write_json` writes:
//   {"machine": "...", "carriers": ["3", ...],
//    "carrier_sets": [["3"], ["3", "4"], ...],
//    "yarns": [{"carrier": "3", "loops": [0, 1, ...]}, ...],   // yarn order
//    "loops": [{"id": 0, "kind": "tuck", "needle": "f10", "line": 9,
//               "carriers": 0, "parents": [], "dropped_line": 0}, ...]}
// A loop's "carriers" indexes "carrier_sets" (plated loops have several
// carriers); "parents" are the loops it was pulled through, bottom of the
// stack first; a yarn's "loops" are the loops its carrier made, in the
// order it made them (a plated loop is in every one of its carriers' yarns);
// "dropped_line" is 0 while a loop is still on the bed at the end.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "simulators/bed/machine.hpp"

namespace bed {

class KnitGraph : public Observer {
 public:
  struct Loop {
    LoopId id = kNoLoop;
    LoopKind kind = LoopKind::Knit;
    knitout::Needle needle;
    std::uint16_t yarn = 0;
    std::uint32_t line = 0;
    std::uint32_t dropped_line = 0;
    std::uint32_t parents_begin = 0;  // into parents()
    std::uint32_t parents_count = 0;
  };

  void loop_made(const LoopEvent& event) override;
  void loops_dropped(knitout::Needle needle, std::span<const LiveLoop> loops,
                     std::uint32_t line) override;

  const std::vector<Loop>& loops() const { return loops_; }
  const std::vector<LoopId>& parents() const { return parents_; }

  // `machine` supplies carrier and yarn names; call after Machine::finish.
  void write_json(std::ostream& out, const Machine& machine) const;

 private:
  std::vector<Loop> loops_;  // indexed by LoopId (ids are dense from 0)
  std::vector<LoopId> parents_;
};

}  // namespace bed
