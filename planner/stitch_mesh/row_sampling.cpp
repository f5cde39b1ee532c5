// Step 3 of the stitch mesher (stitch_mesher.hpp), §6.2: stitch vertices
// along a strip's chains, every ~course_mm; level curves are sampled once,
// by the strip below them, and the segment counts are planned so that every
// strip can be zipped.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <vector>

#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner::stitch_meshing {
namespace {

// A boundary run's sides are placed so that fewest fall more than
// kLengthTolerance off their target (each costs this much more than its
// squared relative error): with 1, 0.05 (the zip's outside_cost) or points
// every course / 8, 16 or 32, all 38 shared meshes met the size targets of
// the shared-mesh test (docs/stitch-mesh.md, step 3).
constexpr double kBoundaryOutsideCost = 1.0;

}  // namespace

int StripMesher::stitch_vertex(int slice_vertex) {
  auto [it, inserted] = anchor_.emplace(slice_vertex, 0);
  if (inserted) {
    it->second = static_cast<int>(mesh_.positions.size());
    mesh_.positions.push_back(slices_.position(slice_vertex));
  }
  return it->second;
}

std::int32_t StripMesher::arc_of(int h) const {
  const int f = slices_.source_face[at(h)];
  if (f < 0 || disc_.arcs.empty()) return kNoArc;
  return disc_.arcs[at(f)][at(slices_.source_side[at(h)])];
}

double StripMesher::straight_length(const Run& run) const {
  const std::vector<double> along = lengths_along(run.halfedges);
  const std::vector<double> walk = straight_walk(run.halfedges, along, params_.course_mm);
  const Vec3 last = walk.empty() ? slices_.position(slices_.from(run.halfedges.front()))
                                 : point_along(run.halfedges, along, walk.back());
  const Vec3 end = slices_.position(slices_.to(run.halfedges.back()));
  return static_cast<double>(walk.size()) * params_.course_mm + (end - last).norm();
}

int StripMesher::auto_count(double length) const {
  return std::max(1, static_cast<int>(std::lround(length / params_.course_mm)));
}

std::vector<double> StripMesher::lengths_along(const std::vector<int>& halfedges) const {
  std::vector<double> along{0};
  for (int h : halfedges) {
    along.push_back(along.back() + slices_.length(h));
  }
  return along;
}

Vec3 StripMesher::point_along(const std::vector<int>& halfedges, const std::vector<double>& along,
                              double t) const {
  std::size_t k = 0;
  while (k + 1 < halfedges.size() && along[k + 1] < t) ++k;
  const double span = along[k + 1] - along[k];
  const double w = span > 0 ? std::clamp((t - along[k]) / span, 0.0, 1.0) : 0.0;
  return (1 - w) * slices_.position(slices_.from(halfedges[k])) +
         w * slices_.position(slices_.to(halfedges[k]));
}

std::vector<double> StripMesher::straight_walk(const std::vector<int>& halfedges,
                                               const std::vector<double>& along,
                                               double step) const {
  std::vector<double> out;
  Vec3 last = slices_.position(slices_.from(halfedges.front()));
  for (std::size_t k = 0; k < halfedges.size(); ++k) {
    const Vec3 a = slices_.position(slices_.from(halfedges[k]));
    const Vec3 e = slices_.position(slices_.to(halfedges[k])) - a;
    double from = 0;
    while (true) {
      // The farther point of this half-edge `step` from the last one.
      const std::optional<double> exit = sphere_exit(a, e, last, step);
      if (!exit) break;
      const double t = *exit;
      if (t > 1 || t < from) break;
      last = a + t * e;
      from = t;
      out.push_back(along[k] + t * (along[k + 1] - along[k]));
    }
  }
  return out;
}

std::vector<double> StripMesher::straight_sides(const std::vector<int>& halfedges,
                                                const std::vector<double>& along, int n) const {
  const double spacing = params_.course_mm / 16;
  std::vector<Vec3> point;
  std::vector<double> arc;
  for (std::size_t k = 0; k < halfedges.size(); ++k) {
    const Vec3 a = slices_.position(slices_.from(halfedges[k]));
    const Vec3 b = slices_.position(slices_.to(halfedges[k]));
    const int parts = std::max(1, static_cast<int>(std::ceil((along[k + 1] - along[k]) / spacing)));
    for (int i = 0; i < parts; ++i) {
      const double w = static_cast<double>(i) / parts;
      point.push_back((1 - w) * a + w * b);
      arc.push_back(along[k] + w * (along[k + 1] - along[k]));
    }
  }
  point.push_back(slices_.position(slices_.to(halfedges.back())));
  arc.push_back(along.back());
  const std::size_t m = point.size();
  // A side spans at most this much of the run's length.
  const double reach = 3 * std::max(params_.course_mm, along.back() / n);
  auto cost = [&](const Vec3& a, const Vec3& b) {
    return length_cost((a - b).norm() / params_.course_mm - 1, kBoundaryOutsideCost);
  };
  constexpr double kNone = std::numeric_limits<double>::infinity();
  std::vector<double> previous(m, kNone);
  std::vector<double> current(m, kNone);
  std::vector<std::uint32_t> from(static_cast<std::size_t>(n) * m, 0);
  previous[0] = 0;
  for (int k = 1; k <= n; ++k) {
    std::fill(current.begin(), current.end(), kNone);
    std::size_t first = 0;
    for (std::size_t j = 1; j < m; ++j) {
      while (arc[j] - arc[first] > reach) ++first;
      for (std::size_t i = first; i < j; ++i) {
        if (previous[i] == kNone) continue;
        const double c = previous[i] + cost(point[i], point[j]);
        if (c < current[j]) {
          current[j] = c;
          from[static_cast<std::size_t>(k - 1) * m + j] = static_cast<std::uint32_t>(i);
        }
      }
    }
    std::swap(previous, current);
  }
  if (previous[m - 1] == kNone) return {};
  std::vector<double> out(static_cast<std::size_t>(n - 1));
  std::size_t j = m - 1;
  for (int k = n; k > 1; --k) {
    j = from[static_cast<std::size_t>(k - 1) * m + j];
    out[at(k - 2)] = arc[j];
  }
  return out;
}

std::vector<int> StripMesher::sample(const std::vector<int>& halfedges,
                                     std::vector<std::int32_t>* arcs, int n, bool straight) {
  const std::vector<double> along = lengths_along(halfedges);
  const double total = along.back();
  std::vector<double> at_length;
  for (int i = 1; i < n; ++i) at_length.push_back(total * i / n);
  if (straight && n > 1) {
    std::vector<double> sides = straight_sides(halfedges, along, n);
    if (!sides.empty()) at_length = std::move(sides);
  }
  std::vector<int> out{stitch_vertex(slices_.from(halfedges.front()))};
  for (int i = 1; i <= n; ++i) {
    const double s = i < n ? at_length[at(i - 1)] : total;
    const double mid = 0.5 * ((i > 1 ? at_length[at(i - 2)] : 0.0) + s);
    std::size_t m = 0;
    while (m + 1 < halfedges.size() && along[m + 1] < mid) ++m;
    if (arcs != nullptr) arcs->push_back(arc_of(halfedges[m]));
    if (i == n) {
      out.push_back(stitch_vertex(slices_.to(halfedges.back())));
      break;
    }
    out.push_back(static_cast<int>(mesh_.positions.size()));
    mesh_.positions.push_back(point_along(halfedges, along, s));
  }
  return out;
}

std::uint64_t StripMesher::undirected(int h) const {
  const int a = slices_.from(h);
  const int b = slices_.to(h);
  return key(std::min(a, b), std::max(a, b));
}

const std::vector<int>* StripMesher::sampled_curve(const Run& run) const {
  auto it = curve_of_edge_.find(undirected(run.halfedges.front()));
  return it == curve_of_edge_.end() ? nullptr : &curve_samples_[at(it->second)];
}

std::vector<int> StripMesher::level_samples(const Run& run, int n) {
  auto it = curve_of_edge_.find(undirected(run.halfedges.front()));
  if (it == curve_of_edge_.end()) {
    const int id = static_cast<int>(curve_samples_.size());
    curve_samples_.push_back(sample(run.halfedges, nullptr, n));
    curve_first_.push_back(slices_.from(run.halfedges.front()));
    for (int h : run.halfedges) curve_of_edge_[undirected(h)] = id;
    return curve_samples_.back();
  }
  std::vector<int> samples = curve_samples_[at(it->second)];
  if (curve_first_[at(it->second)] != slices_.from(run.halfedges.front())) {
    std::reverse(samples.begin(), samples.end());
  }
  return samples;
}

int StripMesher::minimum(const Run& run) const {
  if (!run.level) return 1;
  auto it = min_segments_.find(undirected(run.halfedges.front()));
  return it == min_segments_.end() ? 1 : it->second;
}

std::vector<int> StripMesher::run_counts(const Chain& chain) const {
  std::vector<int> counts;
  for (const Run& run : chain.runs) {
    const std::vector<int>* done = run.level ? sampled_curve(run) : nullptr;
    counts.push_back(
        done != nullptr
            ? static_cast<int>(done->size()) - 1
            : std::max(minimum(run), auto_count(run.level ? run.length : straight_length(run))));
  }
  return counts;
}

void StripMesher::plan_minimums(const std::vector<Chain>& loop) {
  const Chain* low = nullptr;
  int lows = 0;
  int highs = 0;
  int top_runs = 0;
  for (const Chain& c : loop) {
    if (c.side == Side::Low) {
      ++lows;
      low = &c;
    } else if (c.side == Side::High) {
      ++highs;
      top_runs = 0;
      for (const Run& run : c.runs) top_runs += minimum(run);
    }
  }
  if (lows != 1 || highs != 1 || low->runs.size() != 1 || !low->runs.front().level) return;
  int shared = 2;
  for (const Chain& c : loop) shared -= c.side == Side::Wale;
  shared = std::max(0, shared);
  const int need = shared + (std::max(0, top_runs - shared) + 1) / 2;
  if (need <= 1) return;
  for (int h : low->runs.front().halfedges) {
    int& m = min_segments_[undirected(h)];
    m = std::max(m, need);
  }
}

void StripMesher::rescale(const Chain& chain, const std::vector<bool>& fixed,
                          std::vector<int>& counts, int total) const {
  int current = std::accumulate(counts.begin(), counts.end(), 0);
  for (int guard = 0; current != total && guard < 100000; ++guard) {
    // Add to the free run with the longest segments, or take from the one
    // with the shortest.
    int best = -1;
    double best_value = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
      if (fixed[r]) continue;
      const double per = chain.runs[r].length / counts[r];
      if (current < total) {
        if (best < 0 || per > best_value) best = static_cast<int>(r), best_value = per;
      } else if (counts[r] > minimum(chain.runs[r])) {
        if (best < 0 || per < best_value) best = static_cast<int>(r), best_value = per;
      }
    }
    if (best < 0) return;
    counts[at(best)] += current < total ? 1 : -1;
    current += current < total ? 1 : -1;
  }
}

std::vector<bool> StripMesher::fixed_runs(const Chain& chain) const {
  std::vector<bool> fixed;
  for (const Run& run : chain.runs) fixed.push_back(run.level && sampled_curve(run) != nullptr);
  return fixed;
}

std::vector<int> StripMesher::chain_vertices(const Chain& chain, const std::vector<int>& counts,
                                             std::vector<std::int32_t>& arcs,
                                             std::vector<bool>* on_level) {
  std::vector<int> out;
  for (std::size_t r = 0; r < chain.runs.size(); ++r) {
    const Run& run = chain.runs[r];
    std::vector<std::int32_t> run_arcs;
    std::vector<int> v;
    if (run.level) {
      v = level_samples(run, counts[r]);
      run_arcs.assign(v.size() - 1, kNoArc);
    } else {
      v = sample(run.halfedges, &run_arcs, counts[r], /*straight=*/true);
    }
    if (!out.empty() && out.back() == v.front()) {
      out.insert(out.end(), v.begin() + 1, v.end());
    } else {
      if (!out.empty()) {
        throw std::logic_error("stitch meshing: chain runs do not meet");
      }
      out = v;
    }
    arcs.insert(arcs.end(), run_arcs.begin(), run_arcs.end());
    if (on_level != nullptr) on_level->insert(on_level->end(), run_arcs.size(), run.level);
  }
  return out;
}

}  // namespace planner::stitch_meshing
