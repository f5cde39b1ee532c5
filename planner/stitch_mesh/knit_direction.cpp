// Which of the cut's two field directions is knitted as the course
// (stitch_mesher.hpp, KnitDirection).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <future>
#include <limits>

#include "planner/stitch_mesh/stitch_mesher.hpp"

namespace planner {

const char* to_string(KnitDirection direction) {
  switch (direction) {
    case KnitDirection::AsCut:
      return "as-cut";
    case KnitDirection::Turned:
      return "turned";
    case KnitDirection::Best:
      break;
  }
  return "best";
}

std::optional<KnitDirection> parse_knit_direction(const std::string& text) {
  for (const KnitDirection d : {KnitDirection::Best, KnitDirection::AsCut, KnitDirection::Turned}) {
    if (text == to_string(d)) return d;
  }
  return std::nullopt;
}

LabelledDisc turned(const LabelledDisc& disc) {
  LabelledDisc result = disc;
  // 0 = +u (course), 1 = +v (wale), 2 = -u, 3 = -v: a quarter turn of every
  // face's frame. Sides of an uncut edge keep opposite directions, and the
  // two sides at a vanishing corner keep equal ones.
  for (std::vector<int>& face : result.directions) {
    for (int& d : face) d = (d + 1) % 4;
  }
  return result;
}

double stitch_mesh_score(const StitchMeshResult& result, const LabelledDisc& disc,
                         const StitchMeshParams& params) {
  if (!result.problems.empty() || result.mesh.faces.empty())
    return -std::numeric_limits<double>::infinity();
  const StitchMeshFigures f = measure(result.mesh);
  if (f.course.count + f.wale.count <= 0 || f.faces <= 0)
    return -std::numeric_limits<double>::infinity();
  // The kind of side that keeps its size worse decides. A few sides far off
  // (a row as tall as a levelled region) are few in the share within 15% but
  // make the whole piece longer: a mean off by more than its target's 5%
  // costs what it is off beyond that.
  auto kept = [](const EdgeLengthStats& sides, double target_mm) {
    const double mean_off = std::abs(sides.mean_mm / target_mm - 1.0);
    return sides.within_15_percent - std::max(0.0, mean_off - kMeanSizeTolerance);
  };
  const double within = std::min(kept(f.course, params.course_mm), kept(f.wale, params.wale_mm));
  const double off =
      static_cast<double>(off_surface_faces(result.mesh, disc, params.wale_mm).faces.size());
  return within - off / static_cast<double>(f.faces);
}

DirectedStitchMesh make_directed_stitch_mesh(const LabelledDisc& disc,
                                             const StitchMeshParams& params,
                                             KnitDirection direction) {
  DirectedStitchMesh chosen;
  if (direction == KnitDirection::AsCut) {
    chosen.result = make_stitch_mesh(disc, params);
    return chosen;
  }
  const LabelledDisc other = turned(disc);
  if (direction == KnitDirection::Turned) {
    chosen.result = make_stitch_mesh(other, params);
    chosen.turned = true;
    return chosen;
  }
  // Both ways, one on each core where there are two; the result does not
  // depend on which ends first.
  auto turned_mesh =
      std::async(std::launch::async, [&] { return make_stitch_mesh(other, params); });
  StitchMeshResult as_cut = make_stitch_mesh(disc, params);
  StitchMeshResult turned_result = turned_mesh.get();
  chosen.score_as_cut = stitch_mesh_score(as_cut, disc, params);
  chosen.score_turned = stitch_mesh_score(turned_result, other, params);
  chosen.compared = true;
  chosen.turned = chosen.score_turned > chosen.score_as_cut;
  chosen.result = chosen.turned ? std::move(turned_result) : std::move(as_cut);
  return chosen;
}

}  // namespace planner
