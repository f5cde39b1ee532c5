// PieceEmitter (piece_emitter.hpp): one row, with transfers in, cast-on,
// two passes and bind-off (§7.4-7.5).
#include <algorithm>
#include <cstdlib>
#include <stdexcept>

#include "planner/schedule/piece_emitter.hpp"

namespace planner {
namespace {

// The end of the run of faces to cast on that starts at order[i].
std::size_t run_end(const std::vector<bool>& cast, std::size_t i) {
  while (i < cast.size() && cast[i]) ++i;
  return i;
}

}  // namespace

bool PieceEmitter::loop_below(int edge) const {
  const CourseEdge& e = s_.edges[static_cast<std::size_t>(edge)];
  return e.lower != kNone && !e.cut;
}

bool PieceEmitter::loop_above(int edge) const {
  const CourseEdge& e = s_.edges[static_cast<std::size_t>(edge)];
  return e.upper != kNone && !e.cut;
}

bool PieceEmitter::is_triangle(int f) const {
  return mesh_.faces[static_cast<std::size_t>(f)].type == FaceType::ShortRow ||
         mesh_.faces[static_cast<std::size_t>(f)].vertices.size() == 3;
}

bool PieceEmitter::purl(int row_index, int pass, int n) const {
  return params_.pattern == StitchPattern::Seed && ((2 * row_index + pass + n) % 2 + 2) % 2 == 1;
}

void PieceEmitter::knit_row(int r, int row_index) {
  const auto& faces = s_.rows[static_cast<std::size_t>(r)].faces;
  const int left = work(faces.front());
  const int right = needle(s_.faces[static_cast<std::size_t>(faces.back())].out.back());

  const std::vector<LoopMove> moves = loops_in(faces);
  note_row_needles(faces, moves);
  const std::vector<int> kept = clear_tails(faces);
  const std::vector<Transfer> plan = plan_row_transfers(moves, kept);

  // Yarn: start the row on the side nearer the carrier; cut and bring the
  // yarn in again rather than float far.
  int dir = +1;
  const int yarn_at = yarn_after(plan);
  if (in_ && std::abs(yarn_at - right) < std::abs(yarn_at - left)) dir = -1;
  const int start = dir > 0 ? left : right;
  cut_yarn_if_far(start, yarn_at);
  std::vector<int> order(faces.begin(), faces.end());  // in pass A's direction
  if (dir < 0) std::reverse(order.begin(), order.end());
  make_transfers(plan);
  check_row_needles(r, faces);
  for (int f : faces) {
    for (int e : s_.faces[static_cast<std::size_t>(f)].in) where_.erase(e);
  }

  // Cast-on (§7.5): an alternating tuck cast-on on the needles of faces
  // with a course edge below that has no loop. Each run of such faces
  // (consecutive in pass A's order) is cast on where the yarn is when it
  // gets there: a run at the row's start before the pass, any other run
  // in the middle of pass A, just before its faces are knit. Casting every
  // run on before the pass would float the yarn from the row's start to
  // the run and back (V054: 75 needles each way on a widening row of
  // fertility).
  std::vector<bool> cast(order.size(), false);
  for (std::size_t i = 0; i < order.size(); ++i) {
    const FaceLinks& fl = s_.faces[static_cast<std::size_t>(order[i])];
    // A face that some loop from below reaches is held by it: a tuck there
    // would only add to the needle's stack.
    cast[i] = std::none_of(fl.in.begin(), fl.in.end(), [&](int e) { return loop_below(e); });
  }
  pass_a(faces, order, cast, dir, row_index);
  pass_b(faces, order, dir, row_index);
  // The new loops now belong to the course edges above.
  for (int f : faces) {
    const FaceLinks& fl = s_.faces[static_cast<std::size_t>(f)];
    relabel(work(f), fl.out[0]);
    for (int e : fl.out) where_[e] = needle(e);
  }
  bind_off_row(order, dir);
}

std::vector<LoopMove> PieceEmitter::loops_in(const std::vector<int>& faces) const {
  std::vector<LoopMove> moves;
  for (int f : faces) {
    for (int e : s_.faces[static_cast<std::size_t>(f)].in) {
      if (!loop_below(e)) continue;
      auto it = where_.find(e);
      if (it == where_.end())
        throw std::logic_error("the loop of course edge " + std::to_string(e) +
                               " is not on the bed when face " + std::to_string(f) + " needs it");
      moves.push_back({it->second, work(f)});
    }
  }
  return moves;
}

void PieceEmitter::note_row_needles(const std::vector<int>& faces,
                                    const std::vector<LoopMove>& moves) {
  arriving_.clear();  // work needle -> loops the transfers bring
  {
    std::map<int, std::vector<int>> from;
    for (const LoopMove& m : moves) {
      auto& list = from[m.to];
      if (std::find(list.begin(), list.end(), m.from) == list.end()) list.push_back(m.from);
    }
    for (const auto& [to, list] : from) {
      for (int n : list) arriving_[to] += front_[n].size();
    }
  }
  row_needles_.clear();
  for (const LoopMove& m : moves) row_needles_.insert({m.from, m.to});
  for (int f : faces) {
    for (int e : s_.faces[static_cast<std::size_t>(f)].out) row_needles_.insert(needle(e));
  }
  destination_.clear();  // source needle -> where its loops go (kNoNeedle: several places)
  for (const LoopMove& m : moves) {
    const auto [it, added] = destination_.emplace(m.from, m.to);
    if (!added && it->second != m.to) it->second = kNoNeedle;
  }
  stay_.clear();  // empty work needles whose stack has room for a tail
  for (int f : faces) {
    const int w = work(f);
    if (!front_[w].empty() || !back_[w].empty()) continue;
    const std::size_t cast_on = arriving_.count(w) == 0 ? 1 : 0;
    const auto it = arriving_.find(w);
    if ((it == arriving_.end() ? 0 : it->second) + cast_on + 1 <= kMaxLoops) stay_.insert(w);
  }
}

std::vector<int> PieceEmitter::clear_tails(const std::vector<int>& faces) {
  std::vector<int> kept;  // tails left to be knit through
  for (int f : faces) {
    const auto& out = s_.faces[static_cast<std::size_t>(f)].out;
    for (std::size_t k = 0; k < out.size(); ++k) {
      const int n = needle(out[k]);
      const auto it = front_.find(n);
      const std::size_t tail = it == front_.end() ? 0 : it->second.size();
      const std::size_t cast_on = arriving_.count(n) == 0 ? 1 : 0;  // its tuck
      const int stays = drop_tail(n, k == 0 && arriving_[n] + tail + cast_on <= kMaxLoops, true);
      if (stays != kNoNeedle) kept.push_back(stays);
    }
  }
  return kept;
}

std::vector<Transfer> PieceEmitter::plan_row_transfers(const std::vector<LoopMove>& moves,
                                                       const std::vector<int>& kept) {
  std::map<int, bool> moving;
  for (const LoopMove& m : moves) moving[m.from] = m.from != m.to;
  const auto plan_transfers = [&] {
    return schoolbus(
        moves,
        [&](int n) {
          auto it = front_.find(n);
          if (it == front_.end() || it->second.empty()) return false;
          auto mv = moving.find(n);
          return mv == moving.end() || !mv->second;
        },
        8);
  };
  // No needle may end up with more loops than it holds (V037). A kept
  // tail occupies its needle, so a far-travelling loop may find no stop
  // on its way, or a decrease no room: then the kept tails are dropped
  // after all (V053) and the transfers planned without them.
  std::vector<int> knit_first;
  std::vector<Transfer> plan;
  try {
    knit_first = consolidation(moves);
    plan = plan_transfers();
  } catch (const std::logic_error&) {
    if (kept.empty()) throw;
    for (int n : kept) drop_tail(n, false, false);
    knit_first = consolidation(moves);
    plan = plan_transfers();
  }
  knit_stacks(knit_first);
  return plan;
}

std::vector<int> PieceEmitter::consolidation(const std::vector<LoopMove>& moves) {
  std::map<int, std::vector<int>> sources;  // destination -> source needles
  for (const LoopMove& m : moves) {
    auto& list = sources[m.to];
    if (std::find(list.begin(), list.end(), m.from) == list.end()) list.push_back(m.from);
  }
  std::vector<int> knit;
  for (auto& [to, list] : sources) {
    std::size_t total = 0;
    for (int n : list) total += front_[n].size();
    // A bind-off tail waiting there to be knit through (loops that leave
    // the needle in these transfers do not count).
    const int needle = to;
    if (std::none_of(moves.begin(), moves.end(),
                     [needle](const LoopMove& m) { return m.from == needle; }))
      total += front_[to].size();
    if (total <= kMaxLoops) continue;
    std::stable_sort(list.begin(), list.end(),
                     [&](int a, int b) { return front_[a].size() > front_[b].size(); });
    for (int n : list) {
      if (total <= kMaxLoops || front_[n].size() < 2) break;
      total -= front_[n].size() - 1;
      knit.push_back(n);
    }
    if (total > kMaxLoops)
      throw std::logic_error("f" + std::to_string(to) + " would take " + std::to_string(total) +
                             " loops from " + std::to_string(list.size()) + " needles");
  }
  return knit;
}

void PieceEmitter::knit_stacks(std::vector<int> knit) {
  if (knit.empty()) return;
  std::sort(knit.begin(), knit.end());
  int dir = +1;
  if (in_ && std::abs(carrier_at_ - knit.back()) < std::abs(carrier_at_ - knit.front())) dir = -1;
  if (dir < 0) std::reverse(knit.begin(), knit.end());
  end_pass();
  cut_yarn_if_far(knit.front(), carrier_at_);
  for (int n : knit) stitch("knit", dir, 'f', n, front_[n].front());
  release_if_pending();
}

void PieceEmitter::check_row_needles(int r, const std::vector<int>& faces) {
  for (int f : faces) {
    const FaceLinks& fl = s_.faces[static_cast<std::size_t>(f)];
    auto& loops = front_[work(f)];
    for (int t : loops) {
      if (t != kTail && std::find(fl.in.begin(), fl.in.end(), t) == fl.in.end())
        throw std::logic_error("row " + std::to_string(r) + ": needle f" + std::to_string(work(f)) +
                               " of face " + std::to_string(f) +
                               " holds a loop that is not the face's (token " + std::to_string(t) +
                               ")");
    }
    for (std::size_t k = 1; k < fl.out.size(); ++k) {
      if (!front_[needle(fl.out[k])].empty())
        throw std::logic_error("row " + std::to_string(r) + ": the new needle f" +
                               std::to_string(needle(fl.out[k])) + " of increase face " +
                               std::to_string(f) + " is not empty");
    }
  }
}

void PieceEmitter::cast_on(const std::vector<int>& order, std::size_t i, std::size_t j, int dir,
                           int row_index, bool pass_a_bed) {
  auto bed_of = [&](int n) { return pass_a_bed && purl(row_index, 0, n) ? 'b' : 'f'; };
  for (std::size_t k = i; k < j; k += 2) {
    const int n = work(order[k]);
    stitch("tuck", dir, bed_of(n), n, intermediate(order[k]));
  }
  for (std::size_t k = j; k-- > i;) {
    if ((k - i) % 2 == 0) continue;
    const int n = work(order[k]);
    stitch("tuck", -dir, bed_of(n), n, intermediate(order[k]));
  }
}

void PieceEmitter::purls_to_back(const std::vector<int>& faces, int row_index, int pass) {
  end_pass();
  for (int f : faces) {
    if (pass == 1 && is_triangle(f)) continue;
    // A face cast on later in pass A has nothing to move yet: its tuck
    // goes straight onto the back bed.
    if (purl(row_index, pass, work(f)) && !front_[work(f)].empty())
      xfer('f', work(f), 'b', work(f));
  }
}

void PieceEmitter::purls_to_front(const std::vector<int>& faces, int row_index, int pass) {
  end_pass();
  for (int f : faces) {
    if (pass == 1 && is_triangle(f)) continue;
    if (purl(row_index, pass, work(f))) xfer('b', work(f), 'f', work(f));
  }
}

void PieceEmitter::pass_a(const std::vector<int>& faces, const std::vector<int>& order,
                          const std::vector<bool>& cast, int dir, int row_index) {
  const bool seed = params_.pattern == StitchPattern::Seed;
  if (!order.empty() && cast[0]) {
    end_pass();
    cast_on(order, 0, run_end(cast, 0), dir, row_index, false);
    release_if_pending();
  }
  if (seed) purls_to_back(faces, row_index, 0);
  end_pass();
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i > 0 && cast[i] && !cast[i - 1]) cast_on(order, i, run_end(cast, i), dir, row_index, true);
    const int f = order[i];
    const int n = work(f);
    const char b = purl(row_index, 0, n) ? 'b' : 'f';
    stitch("knit", dir, b, n, intermediate(f));
    result_.trace.push_back({f, 0, b, n, line_});
  }
  // The hook lets go of the yarn end once a pass of stitches holds it,
  // right after that pass (the reference backend wants no other pass
  // between them).
  release_if_pending();
  if (seed) purls_to_front(faces, row_index, 0);
}

void PieceEmitter::pass_b(const std::vector<int>& faces, const std::vector<int>& order, int dir,
                          int row_index) {
  const bool seed = params_.pattern == StitchPattern::Seed;
  if (seed) purls_to_back(faces, row_index, 1);
  end_pass();
  for (std::size_t i = order.size(); i-- > 0;) {
    const int f = order[i];
    const FaceLinks& fl = s_.faces[static_cast<std::size_t>(f)];
    const int n = work(f);
    if (is_triangle(f)) {
      // Short-row end: the far one gets a tuck as the yarn turns (Fig. 12),
      // the near one is missed.
      if (i + 1 == order.size() && order.size() > 1) stitch("tuck", -dir, 'f', n, intermediate(f));
      continue;
    }
    const char b = purl(row_index, 1, n) ? 'b' : 'f';
    if (fl.out.size() > 1 && -dir < 0) stitch("tuck", -dir, 'f', needle(fl.out[1]), fl.out[1]);
    stitch("knit", -dir, b, n, fl.out[0]);
    result_.trace.push_back({f, 1, b, n, line_});
    if (fl.out.size() > 1 && -dir > 0) stitch("tuck", -dir, 'f', needle(fl.out[1]), fl.out[1]);
  }
  if (seed) purls_to_front(faces, row_index, 1);
}

void PieceEmitter::bind_off_row(const std::vector<int>& order, int dir) {
  std::vector<int> tops;
  for (int f : order) {
    const auto& out = s_.faces[static_cast<std::size_t>(f)].out;
    if (dir > 0) {
      tops.insert(tops.end(), out.begin(), out.end());
    } else {
      tops.insert(tops.end(), out.rbegin(), out.rend());
    }
  }
  std::size_t i = 0;
  while (i < tops.size()) {
    if (loop_above(tops[i])) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j + 1 < tops.size() && !loop_above(tops[j + 1])) ++j;
    bind_off(tops, i, j, dir);
    i = j + 1;
  }
}

void PieceEmitter::bind_off(const std::vector<int>& tops, std::size_t i, std::size_t j, int dir) {
  for (std::size_t k = i; k <= j; ++k) where_.erase(tops[k]);
  std::vector<int> run(tops.begin() + static_cast<std::ptrdiff_t>(i),
                       tops.begin() + static_cast<std::ptrdiff_t>(j) + 1);
  int holder = kNone;  // the live course edge that takes the chain's last loop
  int chain_dir = dir;
  if (j + 1 < tops.size()) {
    holder = tops[j + 1];
  } else if (i > 0) {
    holder = tops[i - 1];
    std::reverse(run.begin(), run.end());
    chain_dir = -dir;
  } else if (needed_later(needle(run.back())) && !needed_later(needle(run.front()))) {
    // The top of a branch: its chain ends where no later row needs the
    // needle, so its last loop never has to be dropped (a dropped last
    // loop lets the chain unravel, V053).
    std::reverse(run.begin(), run.end());
    chain_dir = -dir;
  }
  const auto move = [&](int from, int to) { move_loop(from, to); };
  // A run of one needle is moved as it is, unless it holds a stack (a
  // short row's stitch and the tuck of its turn): that is knit into one
  // loop first, so the holder takes one loop per run.
  if (run.size() > 1 || front_[needle(run[0])].size() > 1) {
    end_pass();
    cut_yarn_if_far(needle(run[0]), carrier_at_);
    stitch("knit", chain_dir, 'f', needle(run[0]), kTail);
    release_if_pending();
    for (std::size_t k = 0; k + 1 < run.size(); ++k) {
      move(needle(run[k]), needle(run[k + 1]));
      stitch("knit", chain_dir, 'f', needle(run[k + 1]), kTail);
    }
  }
  const int last = needle(run.back());
  if (holder == kNone) {
    // Both ends are needed later: the last loop waits beside the chain's
    // end, where the next row needing the needle comes latest (never,
    // best); that row moves it on again (drop_tail).
    int parked = last;
    if (needed_later(last)) {
      const int away = needle(run.back()) >= needle(run.front()) ? +1 : -1;
      parked = parking_needle(last, row_index_, away);
    }
    if (parked != last) move(last, parked);
    relabel(parked, kTail);
    return;
  }
  move(last, needle(holder));
  // The chain's loop now belongs with the holder's loop.
  for (int& t : front_[needle(holder)]) t = holder;
}

}  // namespace planner
