// bed::KnitGraph: every loop a program makes, for yarn-level viewers.
//
// Attach it to a Machine as its Observer (MachineOptions::observer); it
// keeps one record per loop (so memory grows with the program, unlike the
// machine itself). `write_json` writes:
//   {"machine": "...", "carriers": ["3", ...],
//    "yarns": [{"carriers": ["3"], "loops": [0, 1, ...]}, ...],   // yarn order
//    "loops": [{"id": 0, "kind": "tuck", "needle": "f10", "line": 9,
//               "yarn": 0, "parents": [], "dropped_line": 0}, ...]}
// `yarn` indexes "yarns" (a carrier set; plated loops have several
// carriers); `parents` are the loops this loop was pulled through, bottom of
// the stack first; "loops" of a yarn are its loops in the order the yarn
// made them; dropped_line is 0 while a loop is still on the bed at the end.
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
