// Step 3 of the stitch mesher (stitch_mesher.hpp), §6.2: a strip's boundary
// loop as chains, bottom (course-in), top (course-out) and wale sides, with
// the row ends on an oblique boundary made wale sides.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner::stitch_meshing {
namespace {

// Neighbouring chains of one kind (also the last and the first) become one.
void merge_neighbours_of_one_kind(std::vector<Chain>& out) {
  std::vector<Chain> merged;
  for (Chain& c : out) {
    if (!merged.empty() && merged.back().side == c.side) {
      for (Run& r : c.runs) merged.back().runs.push_back(std::move(r));
    } else {
      merged.push_back(std::move(c));
    }
  }
  if (merged.size() > 1 && merged.front().side == merged.back().side) {
    for (Run& r : merged.front().runs) merged.back().runs.push_back(std::move(r));
    merged.erase(merged.begin());
  }
  out = std::move(merged);
}

// Splits run `r` after its first `count` half-edges.
std::pair<Run, Run> split_run(const Run& r, std::size_t count, const BandSlices& slices) {
  Run a;
  Run b;
  a.side = b.side = r.side;
  a.level = b.level = r.level;
  for (std::size_t k = 0; k < r.halfedges.size(); ++k) {
    const int h = r.halfedges[k];
    Run& into = k < count ? a : b;
    into.halfedges.push_back(h);
    into.length += slices.length(h);
  }
  return {a, b};
}

}  // namespace

double chain_length(const Chain& chain) {
  double length = 0;
  for (const Run& r : chain.runs) length += r.length;
  return length;
}

bool boundary_only(const Chain& chain) {
  return std::none_of(chain.runs.begin(), chain.runs.end(), [](const Run& r) { return r.level; });
}

void join_boundary_runs(Chain& chain) {
  std::vector<Run> joined;
  for (Run& r : chain.runs) {
    if (!joined.empty() && !joined.back().level && !r.level) {
      joined.back().halfedges.insert(joined.back().halfedges.end(), r.halfedges.begin(),
                                     r.halfedges.end());
      joined.back().length += r.length;
    } else {
      joined.push_back(std::move(r));
    }
  }
  chain.runs = std::move(joined);
}

std::vector<Chain> ChainMaker::chains(const std::vector<int>& loop, int band) {
  std::vector<Run> runs = loop_runs(loop, band);
  // Short boundary course runs become wale.
  for (Run& run : runs) {
    if (!run.level && run.side != Side::Wale && run.length < 0.5 * params_.course_mm) {
      run.side = Side::Wale;
    }
  }
  std::vector<Chain> out;
  for (Run& run : runs) {
    Chain c;
    c.side = run.side;
    c.runs.push_back(std::move(run));
    out.push_back(std::move(c));
  }
  merge_neighbours_of_one_kind(out);
  settle_kinds(out);
  // Neighbouring boundary runs of one chain are one stretch of boundary.
  for (Chain& c : out) join_boundary_runs(c);
  short_ends_to_wale_sides(out);
  end_rows_in_wale_sides(out);
  return out;
}

std::vector<Run> ChainMaker::loop_runs(const std::vector<int>& loop, int band) const {
  std::vector<Run> runs;
  for (int h : loop) {
    Run part;
    const double length = slices_.length(h);
    const int level = slices_.level[at(h)];
    if (level >= 0) {
      part.level = true;
      part.side = level == band ? Side::Low : Side::High;
    } else {
      // §6.2: the side's direction against the row direction.
      const Triangle& tri = tris_[at(slices_.tri[at(slices_.slice(h))])];
      const Vec3 e = slices_.position(slices_.to(h)) - slices_.position(slices_.from(h));
      const Vec3 outward = e.cross(tri.normal);
      const double c = tri.grad.norm() > 0 && outward.norm() > 0
                           ? tri.grad.normalized().dot(outward.normalized())
                           : 0.0;
      part.side = c > params_.side_cosine    ? Side::High
                  : c < -params_.side_cosine ? Side::Low
                                             : Side::Wale;
    }
    // A level curve through a pinned saddle is two runs there, so the
    // saddle is a stitch vertex of both (it is where four runs meet).
    const bool breaks = part.level && slices_.is_pinned(slices_.from(h));
    if (!runs.empty() && runs.back().level == part.level && runs.back().side == part.side &&
        !breaks) {
      runs.back().halfedges.push_back(h);
      runs.back().length += length;
    } else {
      part.halfedges.push_back(h);
      part.length = length;
      runs.push_back(std::move(part));
    }
  }
  if (runs.size() > 1 && runs.front().level == runs.back().level &&
      runs.front().side == runs.back().side &&
      !(runs.front().level && slices_.is_pinned(slices_.from(runs.front().halfedges.front())))) {
    runs.back().halfedges.insert(runs.back().halfedges.end(), runs.front().halfedges.begin(),
                                 runs.front().halfedges.end());
    runs.back().length += runs.front().length;
    runs.erase(runs.begin());
  }
  return runs;
}

void ChainMaker::settle_kinds(std::vector<Chain>& out) const {
  bool changed = true;
  while (changed && out.size() > 2) {
    changed = false;
    // A wale chain between two chains of one kind joins them.
    for (std::size_t i = 0; i < out.size(); ++i) {
      const Chain& before = out[(i + out.size() - 1) % out.size()];
      const Chain& after = out[(i + 1) % out.size()];
      if (out[i].side == Side::Wale && before.side == after.side) {
        out[i].side = before.side;
        changed = true;
      }
    }
    merge_neighbours_of_one_kind(out);
    // A short stretch of boundary facing up or down between chains of the
    // other kind is a step of a jagged cut, not a row end: a wale side.
    if (!changed && out.size() > 2) {
      for (Chain& c : out) {
        if (c.side == Side::Wale) continue;
        if (boundary_only(c) && chain_length(c) < params_.step_mm_factor * params_.wale_mm) {
          c.side = Side::Wale;
          changed = true;
          break;
        }
      }
      merge_neighbours_of_one_kind(out);
    }
    // Still more than one chain of a kind: the boundary folds against the
    // rows. The shortest boundary-only course chain gives way first (it
    // joins its neighbours' kind, or becomes a side).
    int lows = 0;
    for (const Chain& c : out) lows += c.side == Side::Low;
    if (!changed && lows > 1) {
      double shortest = std::numeric_limits<double>::infinity();
      Chain* pick = nullptr;
      for (Chain& c : out) {
        if (c.side == Side::Wale) continue;
        const double length = chain_length(c);
        if (boundary_only(c) && length < shortest) {
          shortest = length;
          pick = &c;
        }
      }
      if (pick != nullptr) {
        pick->side = Side::Wale;
        changed = true;
      }
      merge_neighbours_of_one_kind(out);
    }
  }
}

void ChainMaker::short_ends_to_wale_sides(std::vector<Chain>& out) const {
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (out[i].side != Side::Wale) continue;
    Chain& before = out[(i + out.size() - 1) % out.size()];
    Chain& after = out[(i + 1) % out.size()];
    if (before.side != Side::Wale && before.runs.size() > 1 && !before.runs.back().level &&
        before.runs.back().length < 0.5 * params_.course_mm) {
      out[i].runs.insert(out[i].runs.begin(), std::move(before.runs.back()));
      before.runs.pop_back();
    }
    if (after.side != Side::Wale && after.runs.size() > 1 && !after.runs.front().level &&
        after.runs.front().length < 0.5 * params_.course_mm) {
      out[i].runs.push_back(std::move(after.runs.front()));
      after.runs.erase(after.runs.begin());
    }
  }
}

// §6.3, row ends. A row that ends where its bottom and top chains meet on
// the boundary (a wedge: the boundary crosses the rows obliquely) ends
// instead in a wale side: the stretch of the oblique boundary next to the
// point, `tip_side_wales` (0.9) wales long in a straight line. The faces
// before it lean towards the boundary and keep their height, where a wedge
// would shrink them to nothing and fan increases or decreases into its
// point (docs/stitch-mesh.md, step 4, "Row ends"). A wale side on the
// boundary shorter than that (the boundary turns from along the wale to
// oblique within the row) is lengthened the same way.
void ChainMaker::end_rows_in_wale_sides(std::vector<Chain>& out) {
  if (!(params_.tip_side_wales > 0) || out.size() < 2) return;
  const double length = row_end_length();
  const double tolerance = row_end_tolerance();
  auto point = [&](int vertex) { return slices_.position(vertex); };
  for (std::size_t i = 0; i < out.size(); ++i) {
    Chain& c = out[i];
    if (c.side != Side::Wale) {
      // A point where this chain meets the next course chain.
      Chain& b = out[(i + 1) % out.size()];
      if (&c == &b || b.side == Side::Wale || b.side == c.side) continue;
      const Vec3 tip = point(slices_.from(b.runs.front().halfedges.front()));
      bool from_b = false;
      std::optional<Run> stretch = take_stretch(c, b, tip, tip, from_b);
      if (!stretch) continue;
      Chain wale_side;
      wale_side.side = Side::Wale;
      wale_side.runs.push_back(std::move(*stretch));
      ++tip_sides_;
      out.insert(out.begin() + static_cast<std::ptrdiff_t>(i) + 1, std::move(wale_side));
      ++i;
      continue;
    }
    // A short wale side on the boundary between two course chains.
    Chain& a = out[(i + out.size() - 1) % out.size()];
    Chain& b = out[(i + 1) % out.size()];
    if (&a == &b || a.side == Side::Wale || b.side == Side::Wale) continue;
    if (!boundary_only(c)) continue;
    const Vec3 start = point(slices_.from(c.runs.front().halfedges.front()));
    const Vec3 end = point(slices_.to(c.runs.back().halfedges.back()));
    if ((end - start).norm() >= length - tolerance) continue;
    bool from_b = false;
    std::optional<Run> stretch = take_stretch(a, b, end, start, from_b);
    if (!stretch) continue;
    if (from_b) {
      c.runs.push_back(std::move(*stretch));
    } else {
      c.runs.insert(c.runs.begin(), std::move(*stretch));
    }
    ++tip_sides_;
  }
}

std::optional<std::size_t> ChainMaker::cut_at(const Vec3& origin, const Run& r, bool from_front) {
  const double length = row_end_length();
  const double tolerance = row_end_tolerance();
  if (r.level || r.length < length - tolerance) return std::nullopt;
  const std::size_t n = r.halfedges.size();
  for (std::size_t k = 0; k < n; ++k) {
    const int h = from_front ? r.halfedges[k] : r.halfedges[n - 1 - k];
    const Vec3 near = slices_.position(from_front ? slices_.from(h) : slices_.to(h));
    const Vec3 far = slices_.position(from_front ? slices_.to(h) : slices_.from(h));
    const double d_far = (far - origin).norm();
    if (d_far < length - tolerance) continue;
    if (std::abs(d_far - length) <= tolerance) {
      if (k + 1 == n) return std::nullopt;  // the whole run: nothing left of it
      return from_front ? k + 1 : n - 1 - k;
    }
    if (std::abs((near - origin).norm() - length) <= tolerance && k > 0) {
      return from_front ? k : n - k;
    }
    // The point of this half-edge at that distance.
    const Vec3 e = far - near;
    if (const std::optional<double> exit = sphere_exit(near, e, origin, length)) {
      const double s = std::clamp(*exit, 0.0, 1.0);
      // Parameter from the half-edge's own start.
      tip_splits_.push_back({h, from_front ? s : 1.0 - s, near + s * e});
    }
    return std::nullopt;
  }
  return std::nullopt;
}

std::optional<Run> ChainMaker::take_stretch(Chain& a, Chain& b, const Vec3& origin_a,
                                            const Vec3& origin_b, bool& from_b) {
  const bool prefer_b = b.runs.front().length >= a.runs.back().length;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const bool use_b = (attempt == 0) == prefer_b;
    if (use_b) {
      if (auto cut = cut_at(origin_b, b.runs.front(), true)) {
        auto [near, far] = split_run(b.runs.front(), *cut, slices_);
        b.runs.front() = std::move(far);
        near.side = Side::Wale;
        from_b = true;
        return near;
      }
    } else if (auto cut = cut_at(origin_a, a.runs.back(), false)) {
      auto [far, near] = split_run(a.runs.back(), *cut, slices_);
      a.runs.back() = std::move(far);
      near.side = Side::Wale;
      from_b = false;
      return near;
    }
  }
  return std::nullopt;
}

}  // namespace planner::stitch_meshing
