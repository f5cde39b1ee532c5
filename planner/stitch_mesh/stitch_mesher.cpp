// The steps are in files of their own (stitch_meshing.hpp lists them); this
// file checks the input and runs them in order.
#include "planner/stitch_mesh/stitch_mesher.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner {
namespace stitch_meshing {
namespace {

// Saddles on a level (pin_saddles) are looked for in X-shaped strips and in
// strips whose bottom and top chains differ in length by more than this
// ratio, the longer at least kLopsidedWales wales long. 1.3 to 1.5 and 10
// to 20 wales gave 37 of the 38 shared meshes meeting the size targets of
// the shared-mesh test; without the length, jagged cut boundaries lost
// stitches' shape (docs/stitch-mesh.md, "Saddles on a level").
constexpr double kLopsidedRatio = 1.3;
constexpr double kLopsidedWales = 20.0;

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The rows: how many, the slices between their levels and the strips.
struct Rows {
  int bands = 1;
  BandSlices slices;
  Strips strips;
};

// Rows placed on t by height, with the saddles among `candidates` (per disc
// vertex; empty for none) held on a level, sliced and grouped into strips.
// Sets stats.saddles_pinned.
Rows make_rows(const LabelledDisc& disc, const std::vector<Triangle>& tris,
               const Eigen::VectorXd& t, const StitchMeshParams& params,
               const std::vector<bool>& candidates, StitchMeshStats& stats) {
  Rows rows;
  Eigen::VectorXd levels = row_levels(disc, tris, t, params, rows.bands);
  const std::vector<int> pin =
      pin_saddles(disc, tris, levels, rows.bands, 0.4 * params.saddle_wales * params.wale_mm,
                  params.saddle_wales * params.wale_mm, candidates, stats.saddles_pinned);
  rows.slices = slice(disc, tris, levels, 1.0, rows.bands, pin);
  rows.strips = find_strips(rows.slices);
  return rows;
}

// The disc vertices of strips with two bottom and two top chains, or whose
// bottom and top differ in length by more than kLopsidedRatio: the saddles
// among them are to be held on a level. Empty when there are none.
std::vector<bool> saddle_candidates(const LabelledDisc& disc, const std::vector<Triangle>& tris,
                                    const Rows& rows, const StitchMeshParams& params) {
  const BandSlices& slices = rows.slices;
  std::set<int> roots;
  ChainMaker probe(slices, tris, params);
  for (const auto& [root, strip_loops] : rows.strips.loops) {
    if (strip_loops.size() != 1) continue;
    int lows = 0;
    int highs = 0;
    double bottom = 0;
    double top = 0;
    for (const Chain& c : probe.chains(strip_loops.front(), slices.band[at(root)])) {
      lows += c.side == Side::Low ? 1 : 0;
      highs += c.side == Side::High ? 1 : 0;
      if (c.side != Side::Wale) (c.side == Side::Low ? bottom : top) += chain_length(c);
    }
    const bool x_shaped = lows >= 2 && lows == highs;
    const bool lopsided = bottom > 0 && top > 0 &&
                          std::abs(std::log(bottom / top)) > std::log(kLopsidedRatio) &&
                          std::max(bottom, top) >= kLopsidedWales * params.wale_mm;
    if (x_shaped || lopsided) roots.insert(root);
  }
  if (roots.empty()) return {};
  std::vector<bool> candidates(disc.positions.size(), false);
  for (std::size_t p = 0; p < at(slices.num_slices()); ++p) {
    if (roots.count(rows.strips.root[p]) == 0) continue;
    for (int v : tris[at(slices.tri[p])].v) candidates[at(v)] = true;
  }
  return candidates;
}

// Row ends: the boundary points 0.9 wale (`tip_side_wales`) from where a
// row's chains meet become slice vertices, so those rows can end in a wale
// side there.
void add_row_end_points(const std::vector<Triangle>& tris, const StitchMeshParams& params,
                        Rows& rows) {
  std::vector<HalfedgeSplit> splits;
  {
    ChainMaker probe(rows.slices, tris, params);
    for (const auto& [root, strip_loops] : rows.strips.loops) {
      if (strip_loops.size() == 1) probe.chains(strip_loops.front(), rows.slices.band[at(root)]);
    }
    splits = probe.tip_splits();
  }
  if (!splits.empty()) {
    rows.slices = split_halfedges(rows.slices, std::move(splits));
    rows.strips = find_strips(rows.slices);
  }
}

// Steps 3-4: the chains of every strip, then its stitch vertices and faces,
// strip by strip from the bottom row up. Sets the mesh, the problems and the
// stitch-making figures of `result`.
void mesh_strips(const LabelledDisc& disc, const std::vector<Triangle>& tris, const Rows& rows,
                 const StitchMeshParams& params, StitchMeshResult& result) {
  const BandSlices& slices = rows.slices;
  StripMesher builder(disc, params, slices);
  ChainMaker chain_maker(slices, tris, params);
  // Strips in row order, so level curves are sampled from below first.
  std::vector<std::pair<int, int>> order;
  for (const auto& [root, strip_loops] : rows.strips.loops) {
    order.push_back({slices.band[at(root)], root});
  }
  std::sort(order.begin(), order.end());
  // Each strip's chains, made once (empty for a strip with a hole).
  std::vector<std::vector<Chain>> strip_chains(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto& [band, root] = order[i];
    const std::vector<std::vector<int>>& strip_loops = rows.strips.loops.at(root);
    if (strip_loops.size() == 1) strip_chains[i] = chain_maker.chains(strip_loops.front(), band);
  }
  for (auto it = strip_chains.rbegin(); it != strip_chains.rend(); ++it) builder.plan_minimums(*it);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto& [band, root] = order[i];
    const std::vector<std::vector<int>>& strip_loops = rows.strips.loops.at(root);
    const std::string where =
        "row " + std::to_string(band) + " strip at slice " + std::to_string(root);
    if (strip_loops.size() != 1) {
      builder.add_problem(where + ": " + std::to_string(strip_loops.size()) +
                          " boundary loops (a strip with a hole: the row time has an "
                          "interior extremum)");
      continue;
    }
    builder.strip(where, std::move(strip_chains[i]));
  }
  result.stats.rows = rows.bands;
  result.stats.strips = static_cast<int>(order.size());
  result.stats.lenses_skipped = builder.stats().lenses_skipped;
  result.stats.saddles_split = builder.stats().saddles_split;
  result.stats.invalid_faces = builder.stats().invalid_faces;
  result.stats.boundary_sides = builder.stats().boundary_sides;
  result.stats.sides_split_below = builder.stats().sides_split_below;
  result.stats.tip_sides = chain_maker.tip_sides();
  result.mesh = std::move(builder.mesh());
  result.problems = std::move(builder.problems());
}

}  // namespace
}  // namespace stitch_meshing

std::vector<std::string> check_disc(const LabelledDisc& disc) {
  std::vector<std::string> problems;
  if (disc.faces.empty()) problems.push_back("the disc has no faces");
  if (disc.directions.size() != disc.faces.size()) {
    problems.push_back(std::to_string(disc.faces.size()) + " faces but " +
                       std::to_string(disc.directions.size()) + " direction lists");
    return problems;
  }
  if (!disc.arcs.empty() && disc.arcs.size() != disc.faces.size()) {
    problems.push_back(std::to_string(disc.faces.size()) + " faces but " +
                       std::to_string(disc.arcs.size()) + " arc lists");
  }
  for (std::size_t f = 0; f < disc.faces.size(); ++f) {
    const std::vector<int>& face = disc.faces[f];
    const std::string where = "face " + std::to_string(f);
    if (face.size() < 3) problems.push_back(where + ": fewer than 3 corners");
    if (disc.directions[f].size() != face.size()) {
      problems.push_back(where + ": " + std::to_string(face.size()) + " corners but " +
                         std::to_string(disc.directions[f].size()) + " side directions");
      continue;
    }
    if (!disc.arcs.empty() && f < disc.arcs.size() && disc.arcs[f].size() != face.size()) {
      problems.push_back(where + ": " + std::to_string(face.size()) + " corners but " +
                         std::to_string(disc.arcs[f].size()) + " side arcs");
    }
    bool ok = true;
    for (int v : face) {
      if (v < 0 || at(v) >= disc.positions.size()) {
        problems.push_back(where + ": vertex " + std::to_string(v) + " out of range");
        ok = false;
      }
    }
    for (int d : disc.directions[f]) {
      if (d < 0 || d > 3) {
        problems.push_back(where + ": side direction " + std::to_string(d) + " is not 0..3");
        ok = false;
      }
    }
    if (!ok) continue;
    if (stitch_meshing::face_normal(disc, face).norm() <= 1e-12)
      problems.push_back(where + ": zero area");
    bool has_course = false;
    bool has_wale = false;
    for (int d : disc.directions[f]) (d % 2 == 0 ? has_course : has_wale) = true;
    if (!has_course && !has_wale) problems.push_back(where + ": no labelled side");
  }
  return problems;
}

StitchMeshResult make_stitch_mesh(const LabelledDisc& disc, const StitchMeshParams& params) {
  using namespace stitch_meshing;
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::string> input_problems = check_disc(disc);
  if (!input_problems.empty()) {
    throw std::invalid_argument("make_stitch_mesh: " + input_problems.front());
  }
  if (!(params.course_mm > 0) || !(params.wale_mm > 0)) {
    throw std::invalid_argument("make_stitch_mesh: course_mm and wale_mm must be positive");
  }
  StitchMeshResult result;
  try {
    mesh_disc(disc, params, result);
  } catch (const std::runtime_error& e) {
    // The rows of this disc cannot be made into strips (a failure of the
    // method on this cut, named with its place), not a fault of the input.
    result.mesh = StitchMesh{};
    result.problems.push_back(e.what());
  }
  result.stats.total_seconds = seconds_since(start);
  return result;
}

namespace stitch_meshing {

void mesh_disc(const LabelledDisc& disc, const StitchMeshParams& params, StitchMeshResult& result) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<Triangle> tris = triangulate(disc);
  Eigen::VectorXd t = row_time(disc, tris, params, result.stats);
  result.stats.solve_seconds = seconds_since(start);
  // Rows, slices and strips from t. A strip with a hole (an interior
  // extremum of t) makes the row time be drained, and what is left of the
  // extrema levelled, and the rows be placed again; a row time without
  // one is used as fitted.
  Rows rows = make_rows(disc, tris, t, params, {}, result.stats);
  if (rows.strips.has_hole() && params.drain_fits > 0) {
    result.stats.row_time_drained =
        drain_interior_extrema(disc, tris, t, params, params.drain_fits);
    rows = make_rows(disc, tris, t, params, {}, result.stats);
  }
  if (rows.strips.has_hole()) {
    result.stats.row_time_levelled = level_interior_extrema(disc, tris, t);
    rows = make_rows(disc, tris, t, params, {}, result.stats);
  }
  // Saddles on a level: held, and the rows made again.
  if (params.saddle_wales > 0) {
    const std::vector<bool> candidates = saddle_candidates(disc, tris, rows, params);
    if (!candidates.empty()) {
      rows = make_rows(disc, tris, t, params, candidates, result.stats);
      // Held saddles make no extremum, so no strip with a hole; should one
      // appear all the same, the rows are made as before.
      if (rows.strips.has_hole()) rows = make_rows(disc, tris, t, params, {}, result.stats);
    }
  }
  if (params.tip_side_wales > 0) add_row_end_points(tris, params, rows);
  mesh_strips(disc, tris, rows, params, result);
  const auto relax_start = std::chrono::steady_clock::now();
  result.stats.relax_sweeps = relax_positions(result.mesh, disc, params.relax_sweeps);
  result.stats.relax_seconds = seconds_since(relax_start);
  for (std::string& line : check(result.mesh)) result.problems.push_back(std::move(line));
}

}  // namespace stitch_meshing

}  // namespace planner
