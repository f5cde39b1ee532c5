// §7.3: one knitting order simulated on the needle bed (simulate_order).
#include <algorithm>
#include <cstdlib>

#include "planner/schedule/schedule.hpp"

namespace planner {
namespace {

// §7.3: knit the rows patch by patch on a needle bed that keeps every loop
// whose consumer is not knit yet. A row that needs a needle holding a loop
// meant for another row overlaps it: cut the rows that loop joins.
class OrderSimulation {
 public:
  // Needles lo..hi (and max_shift + max_aside beyond) may hold loops.
  OrderSimulation(const Schedule& s, int lo, int hi, int max_shift, int max_aside,
                  std::vector<AsideMove>* asides)
      : s_(s),
        max_shift_(max_shift),
        max_aside_(max_aside),
        lo_(lo - max_shift - max_aside),
        shift_(s.patches.size(), 0),
        aside_(s.edges.size(), 0),
        held_(static_cast<std::size_t>(hi + max_shift + max_aside - lo_ + 1)),
        place_(s.rows.size(), 0),
        in_patch_(held_.size(), 0),
        asides_(asides) {
    // Each row's place in its patch (rows of a patch are knit in that order).
    for (const Patch& patch : s_.patches) {
      for (std::size_t i = 0; i < patch.rows.size(); ++i)
        place_[static_cast<std::size_t>(patch.rows[i])] = static_cast<int>(i);
    }
  }

  void knit_patch(int p) {
    place_patch(p);
    for (int r : s_.patches[static_cast<std::size_t>(p)].rows) knit_row(r);
  }

  std::vector<std::pair<int, int>>& cuts() { return cuts_; }
  std::vector<CutCause>& causes() { return causes_; }
  std::vector<int>& shift() { return shift_; }

 private:
  int row_of(int f) const { return s_.face_row[static_cast<std::size_t>(f)]; }
  bool is_cut(int a, int b) const {
    return std::find(cuts_.begin(), cuts_.end(), std::make_pair(a, b)) != cuts_.end();
  }
  // Where edge e's loop is made: its needle, moved with the patch that makes
  // it (or, cast on, with the patch that knits it).
  int owner(const CourseEdge& ce) const {
    return s_.rows[static_cast<std::size_t>(row_of(ce.lower != kNone ? ce.lower : ce.upper))].patch;
  }
  int needle_of(int e) const {
    const CourseEdge& ce = s_.edges[static_cast<std::size_t>(e)];
    return ce.needle + shift_[static_cast<std::size_t>(owner(ce))];
  }
  // Where a made loop is now.
  int held_at(int e) const { return needle_of(e) + aside_[static_cast<std::size_t>(e)]; }
  std::vector<int>& bucket_at(int n) { return held_[static_cast<std::size_t>(n - lo_)]; }

  // The needles row r needs: its top needles and those its loops come from.
  void span(int r, int& rlo, int& rhi) const {
    rlo = 1 << 30;
    rhi = -(1 << 30);
    for (int f : s_.rows[static_cast<std::size_t>(r)].faces) {
      const FaceLinks& fl = s_.faces[static_cast<std::size_t>(f)];
      for (int e : fl.out) {
        rlo = std::min(rlo, needle_of(e));
        rhi = std::max(rhi, needle_of(e));
      }
      for (int e : fl.in) {
        const CourseEdge& ce = s_.edges[static_cast<std::size_t>(e)];
        if (ce.lower == kNone || is_cut(row_of(ce.lower), r)) continue;
        rlo = std::min(rlo, held_at(e));
        rhi = std::max(rhi, held_at(e));
      }
    }
  }

  // The row pairs whose loops, held now, the rows of patch p would cover
  // (a loop for a row of p that is knit by then is not in the way), and the
  // needles p's rows need (`in_patch_`, from `lo_`).
  int count_covered(int p) {
    covered_.clear();
    std::fill(in_patch_.begin(), in_patch_.end(), 0);
    for (int r : s_.patches[static_cast<std::size_t>(p)].rows) {
      int rlo = 0, rhi = 0;
      span(r, rlo, rhi);
      for (int n = rlo; n <= rhi; ++n) {
        in_patch_[static_cast<std::size_t>(n - lo_)] = 1;
        for (int e : bucket_at(n)) {
          const CourseEdge& ce = s_.edges[static_cast<std::size_t>(e)];
          const int b = row_of(ce.upper);
          if (s_.rows[static_cast<std::size_t>(b)].patch == p &&
              place_[static_cast<std::size_t>(b)] <= place_[static_cast<std::size_t>(r)])
            continue;
          covered_.emplace_back(row_of(ce.lower), b);
        }
      }
    }
    std::sort(covered_.begin(), covered_.end());
    covered_.erase(std::unique(covered_.begin(), covered_.end()), covered_.end());
    return static_cast<int>(covered_.size());
  }

  // The held loops that join rows a and b.
  std::vector<int> held_between(int a, int b) {
    std::vector<int> edges;
    for (int f : s_.rows[static_cast<std::size_t>(a)].faces) {
      for (int e : s_.faces[static_cast<std::size_t>(f)].out) {
        const CourseEdge& ce = s_.edges[static_cast<std::size_t>(e)];
        if (ce.upper == kNone || row_of(ce.upper) != b) continue;
        const auto& bucket = bucket_at(held_at(e));
        if (std::find(bucket.begin(), bucket.end(), e) != bucket.end()) edges.push_back(e);
      }
    }
    return edges;
  }

  // The move (in needles) that takes every loop of `edges` off the needles
  // of the patch counted last (`in_patch_`) onto needles that hold no other
  // loop, at most max_aside from where each was made; the fewest needles,
  // away from the patch's middle first. 0 when none does.
  int aside_move(const std::vector<int>& edges, int middle) {
    if (edges.empty()) return 0;
    const int away = held_at(edges.front()) >= middle ? 1 : -1;
    for (int k = 1; k <= 2 * max_aside_; ++k) {
      const int d = (k % 2 == 1 ? away : -away) * ((k + 1) / 2);
      bool fits = true;
      for (int e : edges) {
        const int n = held_at(e) + d;
        if (std::abs(aside_[static_cast<std::size_t>(e)] + d) > max_aside_ ||
            in_patch_[static_cast<std::size_t>(n - lo_)] != 0 ||
            !std::all_of(bucket_at(n).begin(), bucket_at(n).end(), [&](int other) {
              return std::find(edges.begin(), edges.end(), other) != edges.end();
            })) {
          fits = false;
          break;
        }
      }
      if (fits) return d;
    }
    return 0;
  }

  // The middle of the needles the patch counted last needs.
  int patch_middle() const {
    int first = -1, last = -1;
    for (std::size_t i = 0; i < in_patch_.size(); ++i) {
      if (in_patch_[i] == 0) continue;
      if (first < 0) first = static_cast<int>(i);
      last = static_cast<int>(i);
    }
    return lo_ + (first + last) / 2;
  }

  // Row pairs the patch counted last would cover that no move aside clears.
  int left_covered() {
    if (max_aside_ == 0) return static_cast<int>(covered_.size());
    const int middle = patch_middle();
    int left = 0;
    for (const auto& [a, b] : covered_) {
      if (aside_move(held_between(a, b), middle) == 0) ++left;
    }
    return left;
  }

  // A patch that would cover loops held for other rows is moved sideways
  // as a whole (Fig. 9c, but by one transfer at the patch's start rather
  // than one needle per row): by the fewest needles, within ±max_shift,
  // that leaves the fewest row pairs to cut once the loops that can be are
  // moved aside. Then the held loops it would cover are moved out of its
  // way, one row pair at a time, where that clears them.
  void place_patch(int p) {
    const auto& rows = s_.patches[static_cast<std::size_t>(p)].rows;
    int best = 0, best_count = count_covered(p);
    int best_left = best_count > 0 ? left_covered() : 0;
    for (int d = 1; d <= 2 * max_shift_ && best_count > 0; ++d) {
      shift_[static_cast<std::size_t>(p)] = d % 2 == 1 ? (d + 1) / 2 : -(d / 2);
      const int c = count_covered(p);
      const int left = c > 0 ? left_covered() : 0;
      if (left < best_left || (left == best_left && c < best_count)) {
        best = shift_[static_cast<std::size_t>(p)];
        best_count = c;
        best_left = left;
      }
    }
    shift_[static_cast<std::size_t>(p)] = best;
    if (best_count == 0 || max_aside_ == 0) return;
    count_covered(p);
    const int middle = patch_middle();
    const std::vector<std::pair<int, int>> pairs = covered_;
    for (const auto& [a, b] : pairs) {
      const std::vector<int> edges = held_between(a, b);
      const int d = aside_move(edges, middle);
      if (d == 0) continue;
      for (int e : edges) {
        auto& from = bucket_at(held_at(e));
        from.erase(std::remove(from.begin(), from.end(), e), from.end());
      }
      for (int e : edges) {
        aside_[static_cast<std::size_t>(e)] += d;
        bucket_at(held_at(e)).push_back(e);
        if (asides_ != nullptr) asides_->push_back({rows.front(), e, held_at(e)});
      }
    }
  }

  // Knits row r: the loops it covers that another row needs are cut (every
  // loop joining those two rows is bound off), its own loops leave the bed
  // and the loops it makes are held.
  void knit_row(int r) {
    const Row& row = s_.rows[static_cast<std::size_t>(r)];
    int rlo = 0, rhi = 0;
    span(r, rlo, rhi);
    for (int n = rlo; n <= rhi; ++n) {
      auto& bucket = bucket_at(n);
      for (std::size_t k = 0; k < bucket.size(); ++k) {
        const CourseEdge& ce = s_.edges[static_cast<std::size_t>(bucket[k])];
        const int a = row_of(ce.lower), b = row_of(ce.upper);
        if (b == r) continue;
        cuts_.emplace_back(a, b);
        causes_.push_back({r, n});
        // Every loop joining the two rows is bound off: none stays held.
        for (int e : held_between(a, b)) {
          auto& other = bucket_at(held_at(e));
          other.erase(std::remove(other.begin(), other.end(), e), other.end());
        }
        k = static_cast<std::size_t>(-1);  // the bucket changed: look again
      }
    }
    for (int f : row.faces) {
      const FaceLinks& fl = s_.faces[static_cast<std::size_t>(f)];
      for (int e : fl.in) {
        const CourseEdge& ce = s_.edges[static_cast<std::size_t>(e)];
        if (ce.lower == kNone) continue;
        auto& bucket = bucket_at(held_at(e));
        bucket.erase(std::remove(bucket.begin(), bucket.end(), e), bucket.end());
      }
      for (int e : fl.out) {
        const CourseEdge& ce = s_.edges[static_cast<std::size_t>(e)];
        if (ce.upper == kNone) continue;
        bucket_at(held_at(e)).push_back(e);
      }
    }
  }

  const Schedule& s_;
  const int max_shift_;
  const int max_aside_;
  const int lo_;                              // the needle of held_[0]
  std::vector<int> shift_;                    // needles each patch was moved
  std::vector<int> aside_;                    // needles each held loop was moved aside since made
  std::vector<std::vector<int>> held_;        // needle (from lo_) -> edges whose loops it holds
  std::vector<int> place_;                    // each row's place in its patch
  std::vector<std::pair<int, int>> covered_;  // see count_covered
  std::vector<char> in_patch_;                // see count_covered
  std::vector<std::pair<int, int>> cuts_;     // row pairs cut so far
  std::vector<CutCause> causes_;              // why, per cut
  std::vector<AsideMove>* asides_;
};

}  // namespace

std::vector<std::pair<int, int>> simulate_order(const Schedule& s, const std::vector<int>& order,
                                                int max_shift, std::vector<int>* patch_shift,
                                                int max_aside, std::vector<AsideMove>* asides,
                                                std::vector<CutCause>* causes) {
  if (asides != nullptr) asides->clear();
  if (causes != nullptr) causes->clear();
  if (s.edges.empty()) return {};
  int lo = 1 << 30, hi = -(1 << 30);
  for (const CourseEdge& e : s.edges) {
    lo = std::min(lo, e.needle);
    hi = std::max(hi, e.needle);
  }
  OrderSimulation simulation(s, lo, hi, std::max(0, max_shift), std::max(0, max_aside), asides);
  for (int p : order) simulation.knit_patch(p);
  if (patch_shift != nullptr) *patch_shift = std::move(simulation.shift());
  if (causes != nullptr) *causes = std::move(simulation.causes());
  return std::move(simulation.cuts());
}

}  // namespace planner
