// PieceEmitter (piece_emitter.hpp): bind-off tails kept on the bed, and
// held loops set aside (§7.3, Schedule::aside_moves).
#include <algorithm>
#include <limits>
#include <stdexcept>

#include "planner/schedule/piece_emitter.hpp"

namespace planner {

int PieceEmitter::drop_tail(int n, bool knit_through, bool elsewhere) {
  auto& loops = front_[n];
  if (std::find(loops.begin(), loops.end(), kTail) == loops.end()) return kNoNeedle;
  if (std::any_of(loops.begin(), loops.end(), [](int t) { return t != kTail; }))
    throw std::logic_error("a bind-off tail shares f" + std::to_string(n) + " with other loops");
  const int to = parking_needle(n, row_index_ - 1, +1);
  if (to != n) {
    move_loop(n, to);
    return kNoNeedle;
  }
  if (knit_through) return n;
  const Holder holder = holding_needle(n);
  if (holder.needle != n) {
    // The tail joins a live loop that waits there: the stitch that later
    // knits that loop holds the chain, as the holder of a chain does.
    if (holder.via != kNoNeedle) move_loop(n, holder.via);
    move_loop(holder.via != kNoNeedle ? holder.via : n, holder.needle);
    relabel(holder.needle, front_[holder.needle].front());
    return kNoNeedle;
  }
  if (elsewhere) {
    for (int d = 1; d <= 8; ++d) {
      for (int w : {n + d, n - d}) {
        if (stay_.count(w) == 0 || !front_[w].empty() || !back_[w].empty()) continue;
        stay_.erase(w);
        move_loop(n, w);
        return w;
      }
    }
  }
  drop(n);
  return kNoNeedle;
}

int PieceEmitter::next_use(int n, int after) const {
  auto it = uses_.find(n);
  if (it == uses_.end()) return std::numeric_limits<int>::max();
  auto next = std::upper_bound(it->second.begin(), it->second.end(), after);
  return next == it->second.end() ? std::numeric_limits<int>::max() : *next;
}

bool PieceEmitter::needed_later(int n) const {
  return next_use(n, row_index_) != std::numeric_limits<int>::max();
}

int PieceEmitter::parking_needle(int from, int after, int prefer, const std::set<int>* avoid) {
  int best = from;
  int best_use = next_use(from, after);
  if (avoid != nullptr && avoid->count(from) != 0) best_use = std::numeric_limits<int>::min();
  for (int d = 1; d <= 8; ++d) {
    for (int n : {from + prefer * d, from - prefer * d}) {
      if (n < params_.first_needle || n > params_.machine_needles) continue;
      if (!front_[n].empty() || !back_[n].empty()) continue;
      if (avoid != nullptr && avoid->count(n) != 0) continue;
      const int use = next_use(n, after);
      if (use > best_use) {
        best = n;
        best_use = use;
      }
    }
  }
  return best;
}

PieceEmitter::Holder PieceEmitter::holding_needle(int from) {
  const auto empty = [&](const std::map<int, std::vector<int>>& bed, int n) {
    const auto it = bed.find(n);
    return it == bed.end() || it->second.empty();
  };
  for (int d = 1; d <= 16; ++d) {
    for (int n : {from + d, from - d}) {
      const auto it = front_.find(n);
      if (it == front_.end() || it->second.empty() || it->second.size() >= kMaxLoops) continue;
      if (std::any_of(it->second.begin(), it->second.end(), [](int t) { return t < 0; })) continue;
      if (!empty(back_, n)) continue;
      int via = kNoNeedle;
      if (d > 8) {
        const int step = n > from ? 1 : -1;
        for (int k = 8; k >= d - 8 && via == kNoNeedle; --k) {
          const int m = from + step * k;
          if (empty(front_, m) && empty(back_, m)) via = m;
        }
        if (via == kNoNeedle) continue;
      }
      if (row_needles_.count(n) != 0) {
        const auto to = destination_.find(n);
        if (to == destination_.end() || to->second == kNoNeedle) continue;
        std::size_t& stack = arriving_[to->second];
        if (stack >= kMaxLoops) continue;
        ++stack;
      }
      return {n, via};
    }
  }
  return {from, kNoNeedle};
}

void PieceEmitter::set_aside(const std::vector<AsideMove>& batch) {
  // Several moves of one loop (planned before rows of other pieces) make
  // one: to where the last one puts it.
  std::map<int, int> last;
  for (const AsideMove& m : batch) last[m.edge] = m.to + shift_;
  std::vector<LoopMove> moves;
  std::vector<int> edges;
  std::set<int> to;
  for (const auto& [edge, needle] : last) {
    const auto it = where_.find(edge);
    if (it == where_.end() || it->second == needle) continue;
    moves.push_back({it->second, needle});
    edges.push_back(edge);
    to.insert(needle);
  }
  if (moves.empty()) return;
  std::set<int> from;
  for (const LoopMove& m : moves) from.insert(m.from);
  for (const LoopMove& m : moves) {
    auto& loops = front_[m.to];
    if (loops.empty() || from.count(m.to) != 0) continue;
    if (std::any_of(loops.begin(), loops.end(), [](int t) { return t != kTail; }))
      throw std::logic_error("f" + std::to_string(m.to) +
                             " holds a live loop where a held loop is set aside");
    const int park = parking_needle(m.to, row_index_ - 1, m.to >= m.from ? +1 : -1, &to);
    if (park != m.to) {
      move_loop(m.to, park);
    } else if (loops.size() + front_[m.from].size() > kMaxLoops) {
      drop(m.to);
    }
  }
  const std::vector<Transfer> plan = schoolbus(
      moves,
      [&](int n) {
        const auto it = front_.find(n);
        return it != front_.end() && !it->second.empty() && from.count(n) == 0;
      },
      8);
  make_transfers(plan);
  end_pass();
  for (std::size_t i = 0; i < edges.size(); ++i) {
    where_[edges[i]] = moves[i].to;
    // A tail that stayed joins the loop, as it joins a holder.
    relabel(moves[i].to, edges[i]);
  }
}

}  // namespace planner
