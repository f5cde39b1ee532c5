// The knitted loops a piece's trace promises, as the needle-bed VM's knit
// graph saw them: for the scheduler's tests that check the yarn visits every
// subdivided face in the traced order (§7.4).
#pragma once

#include <cstdint>
#include <set>
#include <vector>

#include "planner/schedule/knitout_emit.hpp"
#include "simulators/bed/knit_graph.hpp"

namespace planner::testing {

// The source lines of the knit loops the graph made at the trace's lines,
// in the order the machine made them. A correct piece gives exactly the
// trace's lines, in the trace's order.
inline std::vector<std::uint32_t> knitted_trace_lines(const bed::KnitGraph& graph,
                                                      const std::vector<TraceStep>& trace) {
  std::set<std::uint32_t> lines;
  for (const TraceStep& t : trace) lines.insert(static_cast<std::uint32_t>(t.line));
  std::vector<std::uint32_t> made;
  for (const auto& loop : graph.loops()) {
    if (loop.kind == bed::LoopKind::Knit && lines.count(loop.line) != 0) made.push_back(loop.line);
  }
  return made;
}

}  // namespace planner::testing
