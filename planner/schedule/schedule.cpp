// §7.3: random knitting orders, their refinement and the one kept
// (random_patch_order, improve_order, choose_order), the pieces
// (make_pieces) and the whole stage (schedule). Rows and patches are in
// rows.cpp, needles in needles.cpp, the simulation of one order in
// order_simulation.cpp.
#include "planner/schedule/schedule.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <numeric>
#include <random>

#include "simulators/cloth/parallel.hpp"

namespace planner {
namespace {

std::uint64_t mix(std::uint64_t seed, std::uint64_t trial) {
  // splitmix64 of the pair: independent streams per trial.
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + trial + 0x632BE59BD9B4E019ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// The patch graph: successors of each patch (sorted, no repeats).
std::vector<std::vector<int>> patch_successors(const Schedule& s) {
  std::vector<std::vector<int>> succ(s.patches.size());
  for (std::size_t r = 0; r < s.rows.size(); ++r) {
    const int a = s.rows[r].patch;
    for (int v : s.row_successors[r]) {
      const int b = s.rows[static_cast<std::size_t>(v)].patch;
      if (a != b) succ[static_cast<std::size_t>(a)].push_back(b);
    }
  }
  for (auto& list : succ) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  return succ;
}

}  // namespace

std::vector<int> random_patch_order(const Schedule& s, std::uint64_t seed, std::uint64_t trial) {
  const std::size_t np = s.patches.size();
  const std::vector<std::vector<int>> succ = patch_successors(s);
  std::vector<int> indeg(np, 0);
  for (const auto& list : succ) {
    for (int b : list) ++indeg[static_cast<std::size_t>(b)];
  }
  std::mt19937_64 rng(mix(seed, trial));
  std::vector<int> ready, order;
  for (std::size_t p = 0; p < np; ++p) {
    if (indeg[p] == 0) ready.push_back(static_cast<int>(p));
  }
  std::shuffle(ready.begin(), ready.end(), rng);
  // Two rules, mixed in a proportion drawn per trial so the trials spread
  // from one extreme to the other: depth first (the patch the last one just
  // unlocked is knit next, so a branch is finished before another starts and
  // its loops are held briefly) and lowest first (the ready patch lowest in
  // the row graph's topological order, so the branches beside a merge climb
  // together).
  std::bernoulli_distribution depth_first(std::uniform_real_distribution<double>(0, 1)(rng));
  while (!ready.empty()) {
    std::size_t i = ready.size() - 1;
    if (!depth_first(rng)) {
      i = 0;
      auto height = [&](int q) {
        const auto first = s.patches[static_cast<std::size_t>(q)].rows.front();
        return s.row_topo_index[static_cast<std::size_t>(first)];
      };
      for (std::size_t k = 1; k < ready.size(); ++k) {
        if (height(ready[k]) < height(ready[i])) i = k;
      }
    }
    const int p = ready[i];
    ready.erase(ready.begin() + static_cast<std::ptrdiff_t>(i));
    order.push_back(p);
    std::vector<int> unlocked;
    for (int b : succ[static_cast<std::size_t>(p)]) {
      if (--indeg[static_cast<std::size_t>(b)] == 0) unlocked.push_back(b);
    }
    std::shuffle(unlocked.begin(), unlocked.end(), rng);
    ready.insert(ready.end(), unlocked.begin(), unlocked.end());
  }
  if (order.size() != np) throw std::logic_error("random_patch_order: the patch graph has a cycle");
  return order;
}

int improve_order(const Schedule& s, std::vector<int>& order, int max_shift, int max_moves,
                  int max_aside) {
  const std::vector<std::vector<int>> succ = patch_successors(s);
  std::vector<std::vector<int>> pred(succ.size());
  for (std::size_t a = 0; a < succ.size(); ++a) {
    for (int b : succ[a]) pred[static_cast<std::size_t>(b)].push_back(static_cast<int>(a));
  }
  // `p` taken out of `order` and put back at the earliest place its
  // predecessors allow (`earliest`), or the latest its successors allow.
  const auto moved = [&](const std::vector<int>& from, int p, bool earliest) {
    std::vector<int> out;
    out.reserve(from.size());
    for (int q : from) {
      if (q != p) out.push_back(q);
    }
    std::vector<int> pos(succ.size());
    for (std::size_t i = 0; i < out.size(); ++i)
      pos[static_cast<std::size_t>(out[i])] = static_cast<int>(i);
    std::size_t at = earliest ? 0 : out.size();
    if (earliest) {
      for (int q : pred[static_cast<std::size_t>(p)])
        at = std::max(at, static_cast<std::size_t>(pos[static_cast<std::size_t>(q)]) + 1);
    } else {
      for (int q : succ[static_cast<std::size_t>(p)])
        at = std::min(at, static_cast<std::size_t>(pos[static_cast<std::size_t>(q)]));
    }
    out.insert(out.begin() + static_cast<std::ptrdiff_t>(at), p);
    return out;
  };
  std::vector<std::pair<int, int>> cuts = simulate_order(s, order, max_shift, nullptr, max_aside);
  int moves = 0;
  // Moves patch `p`; keeps the order when it leaves fewer cuts.
  const auto improves = [&](int p, bool earliest) {
    if (moves >= max_moves) return false;
    std::vector<int> candidate = moved(order, p, earliest);
    if (candidate == order) return false;
    ++moves;
    std::vector<std::pair<int, int>> fewer =
        simulate_order(s, candidate, max_shift, nullptr, max_aside);
    if (fewer.size() >= cuts.size()) return false;
    order = std::move(candidate);
    cuts = std::move(fewer);
    return true;
  };
  bool improved = true;
  while (improved && moves < max_moves && !cuts.empty()) {
    improved = false;
    // The loops of a cut's lower row were covered before its upper row
    // took them: knit the consumer as early as it can go, or the producer
    // as late.
    for (const auto& [lower, upper] : std::vector<std::pair<int, int>>(cuts)) {
      improved = improves(s.rows[static_cast<std::size_t>(upper)].patch, true) ||
                 improves(s.rows[static_cast<std::size_t>(lower)].patch, false);
      if (improved) break;
    }
    // No move of a cut's own patches helps: try every patch.
    for (std::size_t i = 0; !improved && i < order.size(); ++i) {
      const int p = order[i];
      improved = improves(p, true) || improves(p, false);
    }
  }
  return static_cast<int>(cuts.size());
}

namespace {

// §7.3: random order `t`, simulated with held loops kept where they were
// made and (when they may be) with them set aside.
TrialResult run_trial(const Schedule& s, const ScheduleParams& params, std::uint64_t t) {
  const auto order = random_patch_order(s, params.seed, t);
  const auto cuts = [&](int max_aside) {
    return static_cast<int>(
        simulate_order(s, order, params.max_patch_shift, nullptr, max_aside).size());
  };
  TrialResult result;
  result.trial = t;
  result.cuts_in_place = cuts(0);
  result.cuts_aside = params.max_aside > 0 ? cuts(params.max_aside) : result.cuts_in_place;
  result.cuts = std::min(result.cuts_in_place, result.cuts_aside);
  return result;
}

// Trials 0..N-1, in parallel, each into its own slot: params.trials of
// them or, with a time budget, rounds of one trial per thread until the
// budget is spent (at least one round).
std::vector<TrialResult> run_trials(const Schedule& s, const ScheduleParams& params) {
  const int threads = cloth::resolve_threads(params.threads);
  std::vector<TrialResult> results;
  const auto run = [&](int count) {
    const std::size_t first = results.size();
    results.resize(first + static_cast<std::size_t>(count));
    cloth::parallel_tasks(count, threads, [&](int i) {
      const std::size_t t = first + static_cast<std::size_t>(i);
      results[t] = run_trial(s, params, t);
    });
  };
  if (params.time_budget_s <= 0) {
    run(std::max(1, params.trials));
    return results;
  }
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed_s = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  do {
    run(threads);
  } while (elapsed_s() < params.time_budget_s);
  return results;
}

// One start of improve_order: a random order, refined with held loops in
// place or set aside.
struct Refinement {
  std::uint64_t trial = 0;
  bool aside = false;
  std::vector<int> order;
  int cuts = 0;
};

// Local search (improve_order) from the best random orders, in parallel;
// the result depends only on the ranking, not on the threads. The
// params.improve best orders with held loops in place are refined so, then
// (when loops may be set aside) the params.improve best with them set
// aside, in that order.
std::vector<Refinement> refine_best(const Schedule& s, const ScheduleParams& params,
                                    const std::vector<TrialResult>& results) {
  const std::size_t keep = static_cast<std::size_t>(std::max(0, params.improve));
  std::vector<Refinement> jobs;
  for (const bool set_aside : {false, true}) {
    if (set_aside && params.max_aside == 0) continue;
    std::vector<TrialResult> ranked = results;
    std::stable_sort(ranked.begin(), ranked.end(), [&](const TrialResult& a, const TrialResult& b) {
      return set_aside ? a.cuts_aside < b.cuts_aside : a.cuts_in_place < b.cuts_in_place;
    });
    for (std::size_t i = 0; i < std::min(keep, ranked.size()); ++i)
      jobs.push_back({ranked[i].trial, set_aside, {}, 0});
  }
  cloth::parallel_tasks(static_cast<int>(jobs.size()), params.threads, [&](int i) {
    Refinement& job = jobs[static_cast<std::size_t>(i)];
    job.order = random_patch_order(s, params.seed, job.trial);
    job.cuts = improve_order(s, job.order, params.max_patch_shift, params.improve_moves,
                             job.aside ? params.max_aside : 0);
  });
  return jobs;
}

// The kept order's cuts, patch shifts and held loops set aside; its patch
// shifts become the needles the emitter uses.
void keep_order(Schedule& s, const ScheduleParams& params, bool aside) {
  std::vector<int> shift;
  s.cut_rows = simulate_order(s, s.patch_order, params.max_patch_shift, &shift,
                              aside ? params.max_aside : 0, &s.aside_moves, &s.cut_causes);
  s.cuts = static_cast<int>(s.cut_rows.size());
  s.patch_shift = shift;
  for (CourseEdge& e : s.edges) {
    const int f = e.lower != kNone ? e.lower : e.upper;
    e.needle += shift[static_cast<std::size_t>(
        s.rows[static_cast<std::size_t>(s.face_row[static_cast<std::size_t>(f)])].patch)];
  }
  for (CourseEdge& e : s.edges) {
    if (e.lower == kNone || e.upper == kNone) continue;
    const std::pair<int, int> rows{s.face_row[static_cast<std::size_t>(e.lower)],
                                   s.face_row[static_cast<std::size_t>(e.upper)]};
    e.cut = std::find(s.cut_rows.begin(), s.cut_rows.end(), rows) != s.cut_rows.end();
  }
}

}  // namespace

void choose_order(Schedule& s, const ScheduleParams& params) {
  s.trials = run_trials(s, params);
  const auto best =
      std::min_element(s.trials.begin(), s.trials.end(),
                       [](const TrialResult& a, const TrialResult& b) { return a.cuts < b.cuts; });
  s.best_trial = best->trial;
  bool aside = best->cuts_aside < best->cuts_in_place;
  s.patch_order = random_patch_order(s, params.seed, best->trial);
  s.random_cuts = best->cuts;
  // The fewest cuts (ties: the earlier start). The first start of each
  // kind is the best random order of that kind, which the search never
  // makes worse; so where setting aside does not help the schedule is the
  // one without it.
  std::vector<Refinement> refined = refine_best(s, params, s.trials);
  if (!refined.empty()) {
    const auto kept =
        std::min_element(refined.begin(), refined.end(),
                         [](const Refinement& a, const Refinement& b) { return a.cuts < b.cuts; });
    s.patch_order = std::move(kept->order);
    s.best_trial = kept->trial;
    aside = kept->aside;
  }
  keep_order(s, params, aside);
}

void make_pieces(Schedule& s) {
  const std::size_t nr = s.rows.size();
  std::vector<int> parent(nr);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[static_cast<std::size_t>(x)] != x) {
      parent[static_cast<std::size_t>(x)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
      x = parent[static_cast<std::size_t>(x)];
    }
    return x;
  };
  for (const CourseEdge& e : s.edges) {
    if (e.lower == kNone || e.upper == kNone || e.cut) continue;
    const int a = find(s.face_row[static_cast<std::size_t>(e.lower)]);
    const int b = find(s.face_row[static_cast<std::size_t>(e.upper)]);
    if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }
  s.pieces.clear();
  std::map<int, std::size_t> piece_of_root;
  for (int p : s.patch_order) {
    for (int r : s.patches[static_cast<std::size_t>(p)].rows) {
      const int root = find(r);
      auto [it, added] = piece_of_root.emplace(root, s.pieces.size());
      if (added) s.pieces.emplace_back();
      s.pieces[it->second].rows.push_back(r);
    }
  }
}

Schedule schedule(const StitchMesh& mesh, const ScheduleParams& params) {
  Schedule s;
  build_rows(mesh, s);
  build_patches(s);
  assign_needles(mesh, s);
  if (!s.patches.empty()) choose_order(s, params);
  make_pieces(s);
  return s;
}

}  // namespace planner
