#include "planner/stitch_mesh/stitch_mesher.hpp"

#include <Eigen/Geometry>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <queue>
#include <set>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "planner/common/index.hpp"
#include "planner/stitch_mesh/stitch_meshing.hpp"
#include "simulators/cloth/sdf.hpp"

namespace planner {
namespace stitch_meshing {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// ---------------------------------------------------------------------------
// Steps 3-4: chains of each strip, stitch vertices, faces.

// A saddle split (split_folds) takes a splitting edge up to this many wales
// longer to make strips whose bottom and top lengths differ by one unit of
// |ln(bottom / top)| less. 1 left the fans of `teddy-quad`; 2 and 4 gave the
// same stitch meshes on the 38 shared meshes (docs/stitch-mesh.md, "Saddle
// splits").
constexpr double kSplitBalance = 2.0;

// Saddles on a level (pin_saddles) are looked for in X-shaped strips and in
// strips whose bottom and top chains differ in length by more than this
// ratio, the longer at least kLopsidedWales wales long. 1.3 to 1.5 and 10
// to 20 wales gave 37 of the 38 shared meshes meeting every figure of issue
// 8; without the length, jagged cut boundaries lost stitches' shape
// (docs/stitch-mesh.md, "Saddles on a level").
constexpr double kLopsidedRatio = 1.3;
constexpr double kLopsidedWales = 20.0;

// A boundary run's sides are placed so that fewest fall more than
// kLengthTolerance off their target (each costs this much more than its
// squared relative error): with 1, 0.05 (the zip's outside_cost) or points
// every course / 8, 16 or 32, all 38 shared meshes met the size targets of
// the shared-mesh test (docs/stitch-mesh.md, step 3).
constexpr double kBoundaryOutsideCost = 1.0;

Vec3 polygon_normal(const StitchMesh& mesh, const StitchFace& face) {
  Vec3 normal = Vec3::Zero();
  const std::size_t n = face.vertices.size();
  for (std::size_t i = 0; i < n; ++i) {
    normal += mesh.positions[face.vertices[i]].cross(mesh.positions[face.vertices[(i + 1) % n]]);
  }
  return normal;
}

// Step 5, relaxing (docs/stitch-mesh.md): the stitch vertices inside the
// sheet move over the cut mesh so that the sides come closer to their
// target lengths, course or wale; the boundary's vertices stay. Each sweep
// moves each inner vertex to where its sides, as springs of their target
// lengths, would hold it (each weighted by 1 / target^2, and less the
// farther it is off, so a fan's chord across a hole does not drag the
// sheet), then onto the nearest point of the surface. A move that turns an
// incident face over is not made. The faces and their types do not change.
// Returns the number of sweeps made.
int relax_positions(StitchMesh& mesh, const LabelledDisc& disc, int sweeps) {
  if (sweeps <= 0) return 0;
  const cloth::TriangleMeshQuery surface = disc_surface(disc);
  struct Spring {
    std::uint32_t other;
    double target;
  };
  const std::size_t count = mesh.positions.size();
  std::vector<std::vector<Spring>> springs(count);
  std::vector<std::vector<std::size_t>> faces_of(count);
  std::map<std::pair<std::uint32_t, std::uint32_t>, EdgeRole> sides;
  std::set<std::pair<std::uint32_t, std::uint32_t>> directed;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const StitchFace& face = mesh.faces[f];
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t a = face.vertices[i];
      const std::uint32_t b = face.vertices[(i + 1) % n];
      faces_of[a].push_back(f);
      directed.insert({a, b});
      sides.emplace(std::make_pair(std::min(a, b), std::max(a, b)), face.roles[i]);
    }
  }
  std::vector<bool> fixed(count, false);
  for (const auto& [a, b] : directed) {
    if (directed.count({b, a}) == 0) fixed[a] = fixed[b] = true;
  }
  for (const auto& [side, role] : sides) {
    const double target = role == EdgeRole::Wale ? mesh.wale_mm : mesh.course_mm;
    springs[side.first].push_back({side.second, target});
    springs[side.second].push_back({side.first, target});
  }
  std::vector<Vec3> normals;
  for (const StitchFace& face : mesh.faces) normals.push_back(polygon_normal(mesh, face));
  // A vertex is visited again only while it or a neighbour still moves.
  const double still = 1e-4 * mesh.course_mm;
  std::vector<bool> active(count, true);
  std::vector<bool> moved(count, false);
  int sweep = 0;
  while (sweep < sweeps) {
    ++sweep;
    std::fill(moved.begin(), moved.end(), false);
    for (std::size_t v = 0; v < count; ++v) {
      if (fixed[v] || springs[v].empty() || !active[v]) continue;
      const Vec3 x = mesh.positions[v];
      Vec3 sum = Vec3::Zero();
      double weights = 0;
      for (const Spring& s : springs[v]) {
        const Vec3 d = x - mesh.positions[s.other];
        const double length = d.norm();
        if (!(length > 0)) continue;
        const double off = (length - s.target) / (0.5 * s.target);
        const double w = 1.0 / (s.target * s.target * (1 + off * off));
        sum += w * (mesh.positions[s.other] + s.target / length * d);
        weights += w;
      }
      if (!(weights > 0)) continue;
      mesh.positions[v] = surface.closest_point(sum / weights);
      for (std::size_t f : faces_of[v]) {
        if (polygon_normal(mesh, mesh.faces[f]).dot(normals[f]) <= 0) {
          mesh.positions[v] = x;
          break;
        }
      }
      moved[v] = (mesh.positions[v] - x).norm() > still;
    }
    bool any = false;
    for (std::size_t v = 0; v < count; ++v) {
      active[v] = moved[v];
      for (const Spring& s : springs[v]) active[v] = active[v] || moved[s.other];
      any = any || active[v];
    }
    if (!any) break;
  }
  return sweep;
}

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
  std::vector<Triangle> tris = triangulate(disc);
  Eigen::VectorXd t = row_time(disc, tris, params, result.stats);
  result.stats.solve_seconds = seconds_since(start);
  int bands = 1;
  BandSlices slices;
  Strips strips;
  // Rows, slices and strips from t. A strip with a hole (an interior
  // extremum of t) makes the row time be levelled and the rows be placed
  // again; a row time without one is used as fitted.
  auto make_strips = [&](const std::vector<bool>& candidates) {
    Eigen::VectorXd rows = row_levels(disc, tris, t, params, bands);
    const std::vector<int> pin =
        pin_saddles(disc, tris, rows, bands, 0.4 * params.saddle_wales * params.wale_mm,
                    params.saddle_wales * params.wale_mm, candidates, result.stats.saddles_pinned);
    slices = slice(disc, tris, rows, 1.0, bands, pin);
    strips = find_strips(slices);
  };
  make_strips({});
  if (strips.has_hole()) {
    result.stats.row_time_levelled = level_interior_extrema(disc, tris, t);
    make_strips({});
  }
  // Saddles on a level: those among the vertices of strips with two bottom
  // and two top chains, or whose bottom and top differ in length by more
  // than kLopsidedRatio, are held on a level and the rows are made again.
  if (params.saddle_wales > 0) {
    std::set<int> roots;
    ChainMaker probe(slices, tris, params);
    for (const auto& [root, strip_loops] : strips.loops) {
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
    if (!roots.empty()) {
      std::vector<bool> candidates(disc.positions.size(), false);
      for (std::size_t p = 0; p < at(slices.num_slices()); ++p) {
        if (roots.count(strips.root[p]) == 0) continue;
        for (int v : tris[at(slices.tri[p])].v) candidates[at(v)] = true;
      }
      make_strips(candidates);
      // Held saddles make no extremum, so no strip with a hole; should one
      // appear all the same, the rows are made as before.
      if (strips.has_hole()) make_strips({});
    }
  }
  // Row ends: the boundary points 0.9 wale (`tip_side_wales`) from where a row's chains meet
  // become slice vertices, so those rows can end in a wale side there.
  if (params.tip_side_wales > 0) {
    std::vector<HalfedgeSplit> splits;
    {
      ChainMaker probe(slices, tris, params);
      for (const auto& [root, strip_loops] : strips.loops) {
        if (strip_loops.size() == 1) probe.chains(strip_loops.front(), slices.band[at(root)]);
      }
      splits = probe.tip_splits();
    }
    if (!splits.empty()) {
      slices = split_halfedges(slices, std::move(splits));
      strips = find_strips(slices);
    }
  }
  StripMesher builder(disc, params, slices);
  ChainMaker chain_maker(slices, tris, params);
  // Strips in row order, so level curves are sampled from below first.
  std::vector<std::pair<int, int>> order;
  for (const auto& [root, strip_loops] : strips.loops)
    order.push_back({slices.band[at(root)], root});
  std::sort(order.begin(), order.end());
  // Each strip's chains, made once (empty for a strip with a hole).
  std::vector<std::vector<Chain>> strip_chains(order.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto& [band, root] = order[i];
    const std::vector<std::vector<int>>& strip_loops = strips.loops[root];
    if (strip_loops.size() == 1) {
      strip_chains[i] = chain_maker.chains(strip_loops.front(), band);
    }
  }
  for (auto it = strip_chains.rbegin(); it != strip_chains.rend(); ++it) builder.plan_minimums(*it);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const auto& [band, root] = order[i];
    const std::vector<std::vector<int>>& strip_loops = strips.loops[root];
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
  result.stats.rows = bands;
  result.stats.strips = static_cast<int>(order.size());
  result.stats.lenses_skipped = builder.stats().lenses_skipped;
  result.stats.saddles_split = builder.stats().saddles_split;
  result.stats.invalid_faces = builder.stats().invalid_faces;
  result.stats.boundary_sides = builder.stats().boundary_sides;
  result.stats.sides_split_below = builder.stats().sides_split_below;
  result.stats.tip_sides = chain_maker.tip_sides();
  result.mesh = std::move(builder.mesh());
  const auto relax_start = std::chrono::steady_clock::now();
  result.stats.relax_sweeps = relax_positions(result.mesh, disc, params.relax_sweeps);
  result.stats.relax_seconds = seconds_since(relax_start);
  result.problems = std::move(builder.problems());
  for (std::string& line : check(result.mesh)) result.problems.push_back(std::move(line));
  result.stats.total_seconds = seconds_since(start);
  return result;
}

}  // namespace planner
