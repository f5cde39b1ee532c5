// The wearability stage's picture (wearability.png): the garment from a 3/4
// view with its arcs coloured green sewn, red laced, or — over several runs —
// from green to red by the probability of being laced (Fig. 18).
#pragma once

#include <iosfwd>
#include <vector>

#include "planner/wearability/wearability.hpp"

namespace planner {

// Writes the picture as PNG to `out`. `lace_share` holds, per arc, the share
// of runs that laced it (1: laced, 0: sewn). With `caught` (a failed trial
// of the garment with every cut open, W020), the faces within its caught
// radius of where it stays caught are drawn orange: the region that locks
// the garment on its wearer.
void draw_wearability(std::ostream& out, const CoverMesh& mesh,
                      const std::vector<double>& lace_share, const TrialOutcome* caught = nullptr);

}  // namespace planner
