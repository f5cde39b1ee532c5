#include "planner/schedule/schedule.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "knitout/parser.hpp"
#include "planner/schedule/knitout_emit.hpp"
#include "planner/schedule/schedule_stage.hpp"
#include "planner/schedule/schoolbus.hpp"
#include "tests/planner/bed_check.hpp"
#include "tests/planner/schedule_fixtures.hpp"

namespace planner {
namespace {

namespace fx = fixtures;

Schedule run(const StitchMesh& mesh, int trials = 20, std::uint64_t seed = 1, int threads = 2) {
  ScheduleParams params;
  params.trials = trials;
  params.seed = seed;
  params.threads = threads;
  return schedule(mesh, params);
}

// ---- grouping (§7.1) ----

TEST(ScheduleTest, RectangleIsOneRowPerCourseAndOnePatch) {
  const StitchMesh mesh = fx::rectangle(8, 5);
  const Schedule s = run(mesh);
  ASSERT_EQ(s.rows.size(), 5u);
  for (const Row& row : s.rows) {
    ASSERT_EQ(row.faces.size(), 8u);
    // Left to right: positions increase along the row.
    for (std::size_t i = 1; i < row.faces.size(); ++i) {
      const auto& a = mesh.faces[static_cast<std::size_t>(row.faces[i - 1])];
      const auto& b = mesh.faces[static_cast<std::size_t>(row.faces[i])];
      EXPECT_LT(mesh.positions[a.vertices[0]].x(), mesh.positions[b.vertices[0]].x());
    }
  }
  EXPECT_EQ(s.patches.size(), 1u);
  EXPECT_EQ(s.cuts, 0);
  EXPECT_EQ(s.pieces.size(), 1u);
}

TEST(ScheduleTest, ShortRowsOnBothSidesMergeIntoOnePatch) {
  const Schedule s = run(fx::short_rows(12, 3, true));
  ASSERT_EQ(s.rows.size(), 8u);
  // The direct edge from each full row to the next is redundant (Fig. 8d).
  std::size_t full = 0, reduced = 0;
  for (std::size_t r = 0; r < s.rows.size(); ++r) {
    full += s.row_successors[r].size();
    reduced += s.reduced_successors[r].size();
  }
  EXPECT_EQ(full, 10u);
  EXPECT_EQ(reduced, 7u);
  EXPECT_EQ(s.patches.size(), 1u);
  EXPECT_EQ(s.cuts, 0);
}

TEST(ScheduleTest, ShortRowsOnOneSideMergeIntoOnePatch) {
  const Schedule s = run(fx::short_rows(10, 2, false));
  EXPECT_EQ(s.patches.size(), 1u);
  EXPECT_EQ(s.cuts, 0);
}

TEST(ScheduleTest, YShapeSplitsIntoThreePatchesAndNeedsNoCut) {
  const Schedule s = run(fx::y_shape(12, 3, 4, 4));
  // Base (3 rows), left branch (4), right branch (4).
  ASSERT_EQ(s.patches.size(), 3u);
  std::multiset<std::size_t> sizes;
  for (const Patch& p : s.patches) sizes.insert(p.rows.size());
  EXPECT_EQ(sizes, (std::multiset<std::size_t>{3, 4, 4}));
  EXPECT_EQ(s.cuts, 0);
  EXPECT_EQ(s.pieces.size(), 1u);
}

TEST(ScheduleTest, CrossingBranchesNeedOneCutWhateverTheOrder) {
  // Each branch widens 30 needles over the other's base: further than a
  // patch may be moved (kMaxPatchShift) and the loops held for the other
  // set aside (kMaxAside) together, so every order needs a cut.
  const Schedule s = run(fx::crossing_branches(12, 3, 30), 30);
  ASSERT_EQ(s.patches.size(), 3u);
  ASSERT_EQ(s.trials.size(), 30u);
  for (const TrialResult& t : s.trials) EXPECT_GE(t.cuts, 1) << "trial " << t.trial;
  EXPECT_EQ(s.cuts, 1);
  ASSERT_EQ(s.cut_rows.size(), 1u);
  // The cut is between the base and the branch knit second.
  EXPECT_EQ(s.rows[static_cast<std::size_t>(s.cut_rows[0].first)].patch, s.patch_order[0]);
  EXPECT_EQ(s.rows[static_cast<std::size_t>(s.cut_rows[0].second)].patch, s.patch_order[2]);
  EXPECT_EQ(s.pieces.size(), 2u);
  // Why: a row of the branch knit first (patch_order[1]) covers a needle
  // where the base's loops wait for the other branch.
  ASSERT_EQ(s.cut_causes.size(), 1u);
  const CutCause& why = s.cut_causes[0];
  ASSERT_NE(why.covering, kNone);
  EXPECT_EQ(s.rows[static_cast<std::size_t>(why.covering)].patch, s.patch_order[1]);
  bool waiting = false;
  for (const CourseEdge& e : s.edges) {
    waiting = waiting || (e.lower != kNone && e.upper != kNone &&
                          s.face_row[static_cast<std::size_t>(e.lower)] == s.cut_rows[0].first &&
                          s.face_row[static_cast<std::size_t>(e.upper)] == s.cut_rows[0].second &&
                          e.needle == why.needle);
  }
  EXPECT_TRUE(waiting) << "no loop of the parted rows waits on needle " << why.needle;
  EXPECT_EQ(cut_cause_text(s, 0), "cut 1: rows " + std::to_string(s.cut_rows[0].first) + " and " +
                                      std::to_string(s.cut_rows[0].second) +
                                      " are parted because row " + std::to_string(why.covering) +
                                      " is knit before row " +
                                      std::to_string(s.cut_rows[0].second) +
                                      " over the needle where the loops from row " +
                                      std::to_string(s.cut_rows[0].first) + " wait for it");
}

TEST(ScheduleTest, BranchesCrossingBeyondTheShiftReachHaveTheHeldLoopsSetAside) {
  // The crossing 22 rows high: the branch knit first widens 22 needles over
  // the three loops held for the other. Moved by kMaxPatchShift it still
  // covers them; with them moved kMaxAside the other way it does not, so no
  // cut is needed (§7.3, docs/scheduling.md "Setting held loops aside").
  const StitchMesh mesh = fx::crossing_branches(12, 3, 22);
  const Schedule s = run(mesh, 30);
  ASSERT_EQ(s.patches.size(), 3u);
  EXPECT_EQ(s.cuts, 0);
  EXPECT_EQ(s.pieces.size(), 1u);
  ASSERT_EQ(s.aside_moves.size(), 3u);
  const auto patch_of = [&](int f) {
    return s.rows[static_cast<std::size_t>(s.face_row[static_cast<std::size_t>(f)])].patch;
  };
  std::set<int> edges;
  for (const AsideMove& m : s.aside_moves) {
    const CourseEdge& e = s.edges[static_cast<std::size_t>(m.edge)];
    edges.insert(m.edge);
    // The base's loops for the branch knit second, moved before the first
    // row of the branch knit first, at most kMaxAside from where they were
    // made and off every needle that branch knits.
    EXPECT_EQ(patch_of(e.lower), s.patch_order[0]);
    EXPECT_EQ(patch_of(e.upper), s.patch_order[2]);
    EXPECT_EQ(m.row, s.patches[static_cast<std::size_t>(s.patch_order[1])].rows.front());
    EXPECT_NE(m.to, e.needle);
    EXPECT_LE(std::abs(m.to - e.needle), kMaxAside);
    for (int r : s.patches[static_cast<std::size_t>(s.patch_order[1])].rows) {
      for (int f : s.rows[static_cast<std::size_t>(r)].faces) {
        for (int out : s.faces[static_cast<std::size_t>(f)].out)
          EXPECT_NE(s.edges[static_cast<std::size_t>(out)].needle, m.to);
      }
    }
  }
  EXPECT_EQ(edges.size(), 3u);
  // Kept where they were made, the loops are covered: a cut.
  ScheduleParams in_place;
  in_place.trials = 30;
  in_place.max_aside = 0;
  const Schedule cut = schedule(mesh, in_place);
  EXPECT_GE(cut.cuts, 1);
  EXPECT_TRUE(cut.aside_moves.empty());
}

TEST(ScheduleTest, BranchesCrossingWithinTheShiftReachAreMovedApartNotCut) {
  // The same crossing, 10 rows high: the branch knit second covers the
  // loops held for the other unless it is moved sideways; moving it by at
  // most kMaxPatchShift needles clears them, so no cut is needed (§7.3,
  // Fig. 9c by one transfer at the patch's start).
  const StitchMesh mesh = fx::crossing_branches(12, 3, 10);
  const Schedule s = run(mesh, 30);
  ASSERT_EQ(s.patches.size(), 3u);
  EXPECT_EQ(s.cuts, 0);
  EXPECT_EQ(s.pieces.size(), 1u);
  ASSERT_EQ(s.patch_shift.size(), 3u);
  int moved = 0;
  for (int shift : s.patch_shift) {
    EXPECT_LE(std::abs(shift), kMaxPatchShift);
    moved += shift != 0 ? 1 : 0;
  }
  EXPECT_EQ(moved, 1);
  // Without the move, the order kept would cover a held loop.
  Schedule unmoved = s;
  for (CourseEdge& e : unmoved.edges) {
    const int f = e.lower != kNone ? e.lower : e.upper;
    e.needle -= s.patch_shift[static_cast<std::size_t>(
        s.rows[static_cast<std::size_t>(s.face_row[static_cast<std::size_t>(f)])].patch)];
  }
  std::vector<int> shifts;
  EXPECT_EQ(simulate_order(unmoved, s.patch_order, kMaxPatchShift, &shifts).size(), 0u);
  EXPECT_EQ(shifts, s.patch_shift);
  EXPECT_EQ(simulate_order(unmoved, s.patch_order, 0, nullptr, 0).size(), 1u);
  // With moves switched off the scheduler cuts, as before.
  ScheduleParams fixed;
  fixed.trials = 30;
  fixed.max_patch_shift = 0;
  fixed.max_aside = 0;
  EXPECT_GE(schedule(mesh, fixed).cuts, 1);
  // The moved needles are the ones the emitter knits on: every piece passes
  // the bed checks ("crossing-branches" below and in schedule_vm_test).
}

// improve_order (§7.3's random orders, then a local search): never more
// cuts than the order it starts from, the count it returns is the order's,
// and the order is still one the patch graph allows; with held loops kept
// in place (these shapes need no cut once loops may be set aside) and set
// aside.
TEST(ScheduleTest, RefinedOrdersNeverCutMoreAndKeepThePatchGraphOrder) {
  int before = 0;
  int after = 0;
  for (const int max_aside : {0, kMaxAside}) {
    for (std::uint64_t seed = 0; seed < 40; ++seed) {
      SCOPED_TRACE("random shape " + std::to_string(seed));
      Schedule s;
      const StitchMesh mesh = fx::random_shape(seed);
      build_rows(mesh, s);
      build_patches(s);
      assign_needles(mesh, s);
      std::vector<std::set<int>> succ(s.patches.size());
      for (std::size_t r = 0; r < s.rows.size(); ++r) {
        for (int v : s.row_successors[r]) {
          const int a = s.rows[r].patch;
          const int b = s.rows[static_cast<std::size_t>(v)].patch;
          if (a != b) succ[static_cast<std::size_t>(a)].insert(b);
        }
      }
      for (std::uint64_t trial = 0; trial < 3; ++trial) {
        std::vector<int> order = random_patch_order(s, 5, trial);
        const int start =
            static_cast<int>(simulate_order(s, order, kMaxPatchShift, nullptr, max_aside).size());
        const int cuts = improve_order(s, order, kMaxPatchShift, 1000, max_aside);
        EXPECT_LE(cuts, start);
        EXPECT_EQ(cuts, static_cast<int>(
                            simulate_order(s, order, kMaxPatchShift, nullptr, max_aside).size()));
        std::vector<int> position(s.patches.size(), -1);
        for (std::size_t i = 0; i < order.size(); ++i) {
          ASSERT_EQ(position[static_cast<std::size_t>(order[i])], -1) << "patch twice";
          position[static_cast<std::size_t>(order[i])] = static_cast<int>(i);
        }
        ASSERT_EQ(order.size(), s.patches.size());
        for (std::size_t a = 0; a < succ.size(); ++a) {
          for (int b : succ[a]) EXPECT_LT(position[a], position[static_cast<std::size_t>(b)]);
        }
        if (max_aside == 0) {
          before += start;
          after += cuts;
        }
      }
    }
  }
  // Over all shapes the search removes cuts the random orders leave.
  EXPECT_LT(after, before);
}

TEST(ScheduleTest, WithoutRefinementTheBestRandomOrderIsKept) {
  const StitchMesh mesh = fx::crossing_branches(14, 3, 12);
  ScheduleParams params;
  params.trials = 20;
  params.improve = 0;
  const Schedule s = schedule(mesh, params);
  EXPECT_EQ(s.cuts, s.random_cuts);
  EXPECT_EQ(s.patch_order, random_patch_order(s, params.seed, s.best_trial));
}

TEST(ScheduleTest, SameSeedSameResultWhateverTheThreads) {
  const StitchMesh mesh = fx::crossing_branches(14, 3, 12);
  const Schedule a = run(mesh, 40, 7, 1);
  const Schedule b = run(mesh, 40, 7, 4);
  ASSERT_EQ(a.trials.size(), b.trials.size());
  for (std::size_t i = 0; i < a.trials.size(); ++i) {
    EXPECT_EQ(a.trials[i].trial, b.trials[i].trial);
    EXPECT_EQ(a.trials[i].cuts, b.trials[i].cuts);
  }
  EXPECT_EQ(a.patch_order, b.patch_order);
  EXPECT_EQ(a.best_trial, b.best_trial);
  EXPECT_EQ(a.cuts, b.cuts);
  EXPECT_EQ(a.random_cuts, b.random_cuts);
}

TEST(ScheduleTest, TimeBudgetRunsAtLeastOneTrial) {
  ScheduleParams params;
  params.time_budget_s = 0.05;
  params.threads = 2;
  const Schedule s = schedule(fx::y_shape(10, 2, 3, 3), params);
  ASSERT_FALSE(s.trials.empty());
  for (std::size_t i = 0; i < s.trials.size(); ++i) EXPECT_EQ(s.trials[i].trial, i);
}

// ---- needle assignment (§7.2) ----

TEST(ScheduleTest, RectangleNeedsNoTransfers) {
  const Schedule s = run(fx::rectangle(6, 4));
  for (const CourseEdge& e : s.edges) {
    if (e.lower == kNone || e.upper == kNone) continue;
    // The face above works on the needle where the loop already is.
    const int work =
        s.edges[static_cast<std::size_t>(s.faces[static_cast<std::size_t>(e.upper)].out[0])].needle;
    EXPECT_EQ(e.needle, work);
  }
}

TEST(ScheduleTest, ShortRowFacesAreAligned) {
  const StitchMesh mesh = fx::short_rows(12, 2, true);
  const Schedule s = run(mesh);
  int triangles = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (mesh.faces[f].type != FaceType::ShortRow) continue;
    ++triangles;
    const int below = s.edges[static_cast<std::size_t>(s.faces[f].in[0])].needle;
    const int above = s.edges[static_cast<std::size_t>(s.faces[f].out[0])].needle;
    EXPECT_EQ(below, above) << "face " << f;
  }
  EXPECT_EQ(triangles, 4);
}

TEST(ScheduleTest, BranchesAgreeWithTheBaseAlongTheirBoundary) {
  const Schedule s = run(fx::y_shape(12, 2, 4, 2));
  for (const CourseEdge& e : s.edges) {
    if (e.lower == kNone || e.upper == kNone) continue;
    const int work =
        s.edges[static_cast<std::size_t>(s.faces[static_cast<std::size_t>(e.upper)].out[0])].needle;
    EXPECT_EQ(e.needle, work);
  }
}

// ---- bad input ----

TEST(ScheduleTest, RejectsFaceWithoutCourseIn) {
  StitchMesh mesh = fx::rectangle(2, 1);
  mesh.faces[1].roles = {EdgeRole::Wale, EdgeRole::Wale, EdgeRole::CourseOut, EdgeRole::Wale};
  try {
    run(mesh);
    FAIL() << "expected ScheduleError";
  } catch (const ScheduleError& e) {
    EXPECT_STREQ(e.what(), "face 1: no course-in side");
  }
}

TEST(ScheduleTest, AcceptsTheSameFaceWithItsRoles) {
  StitchMesh mesh = fx::rectangle(2, 1);
  EXPECT_NO_THROW(run(mesh));
}

TEST(ScheduleTest, FacesWhoseRowsRunOppositeWaysMeetAtASeam) {
  // Face 1 turned upside down: its wale side towards face 0 is its right
  // side too, so the two cannot share a row; the side stays open.
  StitchMesh mesh = fx::rectangle(2, 1);
  mesh.faces[1].roles = {EdgeRole::CourseOut, EdgeRole::Wale, EdgeRole::CourseIn, EdgeRole::Wale};
  const Schedule s = run(mesh);
  EXPECT_EQ(s.wale_seams, (std::vector<std::pair<int, int>>{{0, 1}}));
  EXPECT_EQ(s.rows.size(), 2u);
  EXPECT_TRUE(run(fx::rectangle(2, 1)).wale_seams.empty());
}

TEST(ScheduleTest, RejectsVertexOutOfRange) {
  StitchMesh mesh = fx::rectangle(2, 1);
  mesh.faces[0].vertices[2] = 999;
  try {
    run(mesh);
    FAIL() << "expected ScheduleError";
  } catch (const ScheduleError& e) {
    EXPECT_STREQ(e.what(), "face 0: vertex 999 out of range");
  }
}

// ---- schoolbus ----

struct Replay {
  std::map<int, int> front;  // needle -> loops
  std::vector<std::string> errors;
};

Replay replay(std::map<int, int> front, const std::vector<Transfer>& plan) {
  Replay r;
  std::map<int, int> back;
  for (const Transfer& t : plan) {
    if (std::abs(t.racking) > 8) r.errors.push_back("racking");
    if (t.front != t.back + t.racking) r.errors.push_back("misaligned");
    int& f = front[t.front];
    int& b = back[t.back];
    if (t.to_back) {
      if (f == 0) r.errors.push_back("empty front");
      if (b != 0) r.errors.push_back("back needle taken");
      b += f;
      f = 0;
    } else {
      if (b == 0) r.errors.push_back("empty back");
      f += b;
      b = 0;
    }
  }
  for (auto& [n, c] : back) {
    if (c != 0) r.errors.push_back("left on back");
  }
  std::erase_if(front, [](const auto& p) { return p.second == 0; });
  r.front = front;
  return r;
}

TEST(SchoolbusTest, MovesEveryLoopToItsNeedleWithinTheRackingLimit) {
  // Shifts of every size up to 12, both ways, and a decrease onto a loop that stays.
  std::vector<LoopMove> moves = {{0, 0}, {1, 0}, {10, 13}, {11, 14}, {30, 18}, {40, 52}, {60, 59}};
  std::map<int, int> start, want;
  for (const LoopMove& m : moves) {
    start[m.from] += 1;
    want[m.to] += 1;
  }
  const auto plan = schoolbus(moves, [&](int n) { return n == 0; });
  const Replay r = replay(start, plan);
  EXPECT_TRUE(r.errors.empty()) << r.errors.front();
  EXPECT_EQ(r.front, want);
  // Each loop that moves at most 8 is transferred exactly twice.
  const auto count = std::count_if(plan.begin(), plan.end(), [](const Transfer& t) {
    return t.front == 1 || t.back == 1 || t.front == 0;
  });
  EXPECT_EQ(count, 2);
}

TEST(SchoolbusTest, NothingToDoMeansNoTransfers) {
  EXPECT_TRUE(schoolbus({{3, 3}, {4, 4}}, [](int) { return false; }).empty());
}

TEST(SchoolbusTest, StopsShortOfAnIntermediateNeedleThatHoldsALoop) {
  // 12 needles to the right would stop at +8, where a loop that stays sits:
  // the rider gets off at +7 instead and goes on from there.
  const auto plan = schoolbus({{0, 12}}, [](int n) { return n == 8; });
  const Replay r = replay({{0, 1}, {8, 1}}, plan);
  EXPECT_TRUE(r.errors.empty());
  EXPECT_EQ(r.front, (std::map<int, int>{{8, 1}, {12, 1}}));
  EXPECT_TRUE(std::any_of(plan.begin(), plan.end(),
                          [](const Transfer& t) { return !t.to_back && t.front == 7; }));
}

TEST(SchoolbusTest, ARiderWithNoStopWithinReachIsANoTransferRoute) {
  // 20 to the right with every needle from +1 to +19 holding a loop that
  // stays: no stop within the racking limit of 8. The planner says so with
  // its own error (the schedule stage reports it as S911), not a crash.
  EXPECT_THROW(schoolbus({{0, 20}}, [](int n) { return n >= 1 && n <= 19; }), NoTransferRoute);
}

TEST(SchoolbusTest, ARiderThatStopsEarlyWaitsForTheNextRound) {
  // 12 to the right with +8 ... +5 held: the rider gets off at +4, 8 short
  // of its needle. It must not ride on from there at racking +8 in the same
  // round (its loop is on the front bed then): it boards again next round.
  auto held = [](int n) { return n >= 15 && n <= 18; };
  const auto plan = schoolbus({{10, 22}}, held);
  const Replay r = replay({{10, 1}, {15, 1}, {16, 1}, {17, 1}, {18, 1}}, plan);
  EXPECT_TRUE(r.errors.empty()) << r.errors.front();
  EXPECT_EQ(r.front, (std::map<int, int>{{15, 1}, {16, 1}, {17, 1}, {18, 1}, {22, 1}}));
}

TEST(SchoolbusTest, ARiderWithAFreeWayGetsThereInOneRound) {
  const auto plan = schoolbus({{10, 18}}, [](int n) { return n >= 15 && n <= 17; });
  EXPECT_EQ(plan.size(), 2u);
  const Replay r = replay({{10, 1}, {15, 1}, {16, 1}, {17, 1}}, plan);
  EXPECT_TRUE(r.errors.empty()) << r.errors.front();
  EXPECT_EQ(r.front, (std::map<int, int>{{15, 1}, {16, 1}, {17, 1}, {18, 1}}));
}

TEST(SchoolbusTest, ARiderWhoseReachIsTakenThisRoundWaitsOnItsNeedle) {
  // 20 -> 0 with 13..19 held: its only free stop within reach, 12, is taken
  // by the rider 6 -> 30, which gets off there first. The first rider waits
  // on its needle for a round (it used to stop the schedule) and then both
  // pass each other.
  auto held = [](int n) { return n >= 13 && n <= 19; };
  const auto plan = schoolbus({{20, 0}, {6, 30}}, held);
  std::map<int, int> start = {{20, 1}, {6, 1}};
  for (int n = 13; n <= 19; ++n) start[n] = 1;
  std::map<int, int> want = {{0, 1}, {30, 1}};
  for (int n = 13; n <= 19; ++n) want[n] = 1;
  const Replay r = replay(start, plan);
  EXPECT_TRUE(r.errors.empty()) << r.errors.front();
  EXPECT_EQ(r.front, want);
  // In the first round only the rider from 6 boards.
  ASSERT_FALSE(plan.empty());
  EXPECT_EQ(plan.front().front, 6);
  EXPECT_TRUE(plan.front().to_back);
}

TEST(SchoolbusTest, ARiderWithEveryStopTakenBoardsOffsetAndGetsThereInOneRound) {
  // 0 -> 12 with 1..8 held: no stop on the way. It boards at racking -4
  // onto b4 and gets off at 12 at racking +8.
  const auto plan = schoolbus({{0, 12}}, [](int n) { return n >= 1 && n <= 8; });
  std::map<int, int> start = {{0, 1}};
  for (int n = 1; n <= 8; ++n) start[n] = 1;
  std::map<int, int> want = {{12, 1}};
  for (int n = 1; n <= 8; ++n) want[n] = 1;
  const Replay r = replay(start, plan);
  EXPECT_TRUE(r.errors.empty()) << r.errors.front();
  EXPECT_EQ(r.front, want);
  EXPECT_EQ(plan.size(), 2u);
}

TEST(SchoolbusTest, AFarRiderPassesLoopsThatArriveBeforeIt) {
  // 54 -> 63 past a loop that stays on 55 and seven riders 64..70 -> 56..62
  // (each 8 to the left): every stop of the far rider is someone's
  // destination, and once they arrive its way is shut for good. It boards
  // offset and lands in the first round.
  std::vector<LoopMove> moves = {{54, 63}};
  std::map<int, int> start = {{54, 1}, {55, 1}};
  std::map<int, int> want = {{63, 1}, {55, 1}};
  for (int k = 0; k < 7; ++k) {
    moves.push_back({64 + k, 56 + k});
    start[64 + k] = 1;
    want[56 + k] = 1;
  }
  const auto plan = schoolbus(moves, [](int n) { return n == 55; });
  const Replay r = replay(start, plan);
  EXPECT_TRUE(r.errors.empty()) << r.errors.front();
  EXPECT_EQ(r.front, want);
}

// A block shifted past a loop that stays (fertility at 99 mm, one row: 51
// loops 15..65 to 69..107 past loops on 66, 76 and 96). Riders chose their
// stops back first: the one ahead of the block found its stops taken by
// those behind and waited, the wait spread back through the block, the
// riders that waited fell behind riders going less far, whose arrived loops
// then shut their way for more than the racking limit ("no free needle
// within reach"). Front first, every shift of such a block goes through.
TEST(SchoolbusTest, ABlockPassesALoopThatStaysJustAheadOfIt) {
  std::vector<LoopMove> moves;
  std::map<int, int> start = {{23, 1}};
  std::map<int, int> want = {{23, 1}};
  for (int n = 0; n < 20; ++n) {
    moves.push_back({n, n + 24});
    start[n] = 1;
    want[n + 24] = 1;
  }
  const auto plan = schoolbus(moves, [](int n) { return n == 23; });
  const Replay r = replay(start, plan);
  EXPECT_TRUE(r.errors.empty()) << r.errors.front();
  EXPECT_EQ(r.front, want);
}

TEST(SchoolbusTest, EveryShiftOfABlockPastALoopThatStaysGoesThrough) {
  for (int size = 4; size <= 40; ++size) {
    for (int shift = 9; shift <= 60; ++shift) {
      for (int gap = 0; gap <= 3; ++gap) {
        for (const int sign : {+1, -1}) {
          const int held = sign * (size + gap);
          std::vector<LoopMove> moves;
          std::map<int, int> start = {{held, 1}};
          std::map<int, int> want = {{held, 1}};
          for (int n = 0; n < size; ++n) {
            moves.push_back({sign * n, sign * (n + shift)});
            start[sign * n] = 1;
            want[sign * (n + shift)] += 1;
          }
          if (want[held] != 1) continue;  // a destination on the held loop is a decrease
          std::vector<Transfer> plan;
          ASSERT_NO_THROW(plan = schoolbus(moves, [&](int n) { return n == held; }))
              << size << " loops shifted by " << sign * shift << " past f" << held;
          const Replay r = replay(start, plan);
          ASSERT_TRUE(r.errors.empty()) << r.errors.front();
          ASSERT_EQ(r.front, want) << size << " loops shifted by " << sign * shift;
        }
      }
    }
  }
}

TEST(SchoolbusTest, RefusesWhenNoIntermediateNeedleIsFree) {
  // Beyond twice the racking limit with every stop held.
  EXPECT_THROW(schoolbus({{0, 20}}, [](int n) { return n >= 1 && n <= 8; }), std::logic_error);
}

// ---- knitout (§7.4-7.5) ----

struct Case {
  const char* name;
  StitchMesh mesh;
};

std::vector<Case> cases() {
  return {{"rectangle", fx::rectangle(10, 6)},
          {"trapezoid", fx::trapezoid(16, 10)},
          {"widening", fx::widening(6, 10)},
          {"short-rows-one-side", fx::short_rows(12, 3, false)},
          {"short-rows-both-sides", fx::short_rows(14, 3, true)},
          {"y-shape", fx::y_shape(14, 3, 5, 4)},
          {"crossing-branches", fx::crossing_branches(12, 3, 10)},
          {"crossing-branches-aside", fx::crossing_branches(12, 3, 22)},
          {"crossing-branches-cut", fx::crossing_branches(12, 3, 30)}};
}

int subdivided_faces(const StitchMesh& mesh, const Schedule& s, const Piece& piece) {
  int n = 0;
  for (int r : piece.rows) {
    for (int f : s.rows[static_cast<std::size_t>(r)].faces) {
      n += mesh.faces[static_cast<std::size_t>(f)].vertices.size() == 3 ? 1 : 2;
    }
  }
  return n;
}

TEST(KnitoutEmitTest, EveryPieceOfEveryFixtureIsValidKnitout) {
  for (StitchPattern pattern : {StitchPattern::Plain, StitchPattern::Seed}) {
    for (const Case& c : cases()) {
      SCOPED_TRACE(std::string(c.name) + " " + std::string(stitch_pattern_name(pattern)));
      const Schedule s = run(c.mesh);
      EmitParams params;
      params.pattern = pattern;
      for (std::size_t p = 0; p < s.pieces.size(); ++p) {
        EmittedPiece piece;
        ASSERT_NO_THROW(piece = emit_piece(c.mesh, s, p, params));
        knitout::DiagnosticSink sink;
        const knitout::Program program = knitout::parse_string(piece.knitout, c.name, sink);
        ASSERT_EQ(sink.error_count(), 0u) << knitout::format(sink.diagnostics().front());
        EXPECT_EQ(sink.warning_count(), 0u);
        const testing::BedCheck check = testing::check_bed(program);
        EXPECT_TRUE(check.errors.empty()) << check.errors.front();
        EXPECT_EQ(check.transfers, piece.stats.transfers);
        EXPECT_EQ(check.knits, piece.stats.knits);
        EXPECT_EQ(piece.stats.lines,
                  static_cast<int>(std::count(piece.knitout.begin(), piece.knitout.end(), '\n')));
      }
    }
  }
}

TEST(KnitoutEmitTest, YarnVisitsOneLoopPerSubdividedFaceInTracedOrder) {
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.name);
    const Schedule s = run(c.mesh);
    for (std::size_t p = 0; p < s.pieces.size(); ++p) {
      const EmittedPiece piece = emit_piece(c.mesh, s, p, EmitParams{});
      EXPECT_EQ(static_cast<int>(piece.trace.size()), subdivided_faces(c.mesh, s, s.pieces[p]));
      // Each (face, half) once; rows in the piece's order; within a row the
      // first half away from the start and the second half back (§7.4).
      std::set<std::pair<int, int>> seen;
      std::size_t k = 0;
      for (int r : s.pieces[p].rows) {
        const auto& faces = s.rows[static_cast<std::size_t>(r)].faces;
        ASSERT_LT(k, piece.trace.size());
        const bool rightward = piece.trace[k].face == faces.front();
        std::vector<int> first(faces.begin(), faces.end());
        if (!rightward) std::reverse(first.begin(), first.end());
        for (int f : first) {
          ASSERT_LT(k, piece.trace.size());
          EXPECT_EQ(piece.trace[k].face, f);
          EXPECT_EQ(piece.trace[k].part, 0);
          ++k;
        }
        for (auto it = first.rbegin(); it != first.rend(); ++it) {
          if (c.mesh.faces[static_cast<std::size_t>(*it)].vertices.size() == 3) continue;
          ASSERT_LT(k, piece.trace.size());
          EXPECT_EQ(piece.trace[k].face, *it);
          EXPECT_EQ(piece.trace[k].part, 1);
          ++k;
        }
      }
      for (std::size_t i = 1; i < piece.trace.size(); ++i) {
        EXPECT_LT(piece.trace[i - 1].line, piece.trace[i].line);
        EXPECT_TRUE(seen.insert({piece.trace[i].face, piece.trace[i].part}).second);
      }
    }
  }
}

TEST(KnitoutEmitTest, RandomShapesGiveValidKnitout) {
  // 150 fixed-seed random shapes (shaping, short rows, branches), both
  // patterns: every piece passes the bed checker and has one knit per
  // subdivided face. Every other shape is scheduled without moving patches
  // sideways or setting held loops aside (with them none of these shapes
  // needs a cut), so cut pieces are knit too.
  int pieces = 0, cut = 0, branched = 0, moved = 0;
  for (std::uint32_t seed = 1; seed <= 150; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const StitchMesh mesh = fx::random_shape(seed);
    ScheduleParams schedule_params;
    schedule_params.trials = 10;
    schedule_params.seed = seed;
    schedule_params.threads = 1;
    schedule_params.max_patch_shift = seed % 2 == 0 ? 0 : kMaxPatchShift;
    schedule_params.max_aside = seed % 2 == 0 ? 0 : kMaxAside;
    Schedule s;
    ASSERT_NO_THROW(s = schedule(mesh, schedule_params));
    cut += s.cuts > 0 ? 1 : 0;
    moved += std::any_of(s.patch_shift.begin(), s.patch_shift.end(),
                         [](int shift) { return shift != 0; })
                 ? 1
                 : 0;
    branched += s.patches.size() > 1 ? 1 : 0;
    for (StitchPattern pattern : {StitchPattern::Plain, StitchPattern::Seed}) {
      EmitParams params;
      params.pattern = pattern;
      for (std::size_t p = 0; p < s.pieces.size(); ++p) {
        EmittedPiece piece;
        ASSERT_NO_THROW(piece = emit_piece(mesh, s, p, params)) << "piece " << p;
        knitout::DiagnosticSink sink;
        const auto check = testing::check_bed(knitout::parse_string(piece.knitout, "r", sink));
        ASSERT_FALSE(sink.has_errors());
        ASSERT_TRUE(check.errors.empty()) << "piece " << p << ": " << check.errors.front();
        EXPECT_EQ(static_cast<int>(piece.trace.size()), subdivided_faces(mesh, s, s.pieces[p]));
        ++pieces;
      }
    }
  }
  // The cases exercise branching and cuts, not only plain sheets.
  EXPECT_GT(branched, 100);
  EXPECT_GT(cut, 0);
  EXPECT_GT(moved, 0);
  EXPECT_GT(pieces, 300);
}

TEST(KnitoutEmitTest, AFanOfDecreasesNeverStacksMoreThanFourLoops) {
  // Bind-off tails joining the loops a decrease then stacks (anchor's V037):
  // every needle holds at most four loops, in both patterns, and every
  // subdivided face is still knit once.
  const StitchMesh mesh = fx::decrease_fan(2);
  const Schedule s = run(mesh);
  ASSERT_EQ(s.pieces.size(), 1u);
  for (StitchPattern pattern : {StitchPattern::Plain, StitchPattern::Seed}) {
    SCOPED_TRACE(std::string(stitch_pattern_name(pattern)));
    EmitParams params;
    params.pattern = pattern;
    EmittedPiece piece;
    ASSERT_NO_THROW(piece = emit_piece(mesh, s, 0, params));
    knitout::DiagnosticSink sink;
    const auto check = testing::check_bed(knitout::parse_string(piece.knitout, "fan", sink));
    ASSERT_FALSE(sink.has_errors());
    EXPECT_TRUE(check.errors.empty()) << check.errors.front() << "\n" << piece.knitout;
    EXPECT_EQ(static_cast<int>(piece.trace.size()), subdivided_faces(mesh, s, s.pieces[0]));
  }
}

TEST(KnitoutEmitTest, ADecreaseOfTwoStacksKnitsTheFullerOneFirst) {
  // 3 + 2 loops would meet on the decrease's needle: the stack of three is
  // knit into one loop before the transfers, so the needle takes three.
  const StitchMesh mesh = fx::stacked_decrease(2);
  const Schedule s = run(mesh);
  ASSERT_EQ(s.pieces.size(), 1u);
  EmittedPiece piece;
  ASSERT_NO_THROW(piece = emit_piece(mesh, s, 0, EmitParams{}));
  knitout::DiagnosticSink sink;
  const auto check = testing::check_bed(knitout::parse_string(piece.knitout, "stacks", sink));
  ASSERT_FALSE(sink.has_errors());
  EXPECT_TRUE(check.errors.empty()) << check.errors.front();
  EXPECT_EQ(static_cast<int>(piece.trace.size()), subdivided_faces(mesh, s, s.pieces[0]));
}

TEST(KnitoutEmitTest, CarrierComesInWithTheHookAndLeavesWithIt) {
  const StitchMesh mesh = fx::rectangle(6, 3);
  const Schedule s = run(mesh);
  const EmittedPiece piece = emit_piece(mesh, s, 0, EmitParams{});
  const std::string& k = piece.knitout;
  EXPECT_EQ(k.rfind(";!knitout-2\n", 0), 0u);
  EXPECT_NE(k.find(";;Carriers: 1 2 3 4 5 6 7 8 9 10\n"), std::string::npos);
  const auto in = k.find("inhook 3\n");
  const auto first_stitch = k.find(" 3\n", in + 9);
  const auto release = k.find("releasehook 3\n");
  const auto out = k.find("outhook 3\n");
  ASSERT_NE(in, std::string::npos);
  ASSERT_NE(release, std::string::npos);
  ASSERT_NE(out, std::string::npos);
  EXPECT_LT(in, first_stitch);
  EXPECT_LT(first_stitch, release);
  EXPECT_LT(release, out);
}

TEST(KnitoutEmitTest, BindOffChainsEveryTopLoop) {
  // A rectangle ends with one loop on the bed (the chain's last), and the
  // cast-on tucks every needle of the first row.
  const StitchMesh mesh = fx::rectangle(7, 3);
  const Schedule s = run(mesh);
  const EmittedPiece piece = emit_piece(mesh, s, 0, EmitParams{});
  knitout::DiagnosticSink sink;
  const auto check = testing::check_bed(knitout::parse_string(piece.knitout, "r", sink));
  EXPECT_TRUE(check.errors.empty());
  EXPECT_EQ(check.loops_left, 1);
  EXPECT_EQ(piece.stats.bind_off_tails, 1);
  EXPECT_EQ(check.tucks, 7);
}

TEST(KnitoutEmitTest, SeedKnitsPurlsOnTheBackBed) {
  const StitchMesh mesh = fx::rectangle(6, 4);
  const Schedule s = run(mesh);
  EmitParams params;
  const EmittedPiece plain = emit_piece(mesh, s, 0, params);
  params.pattern = StitchPattern::Seed;
  const EmittedPiece seed = emit_piece(mesh, s, 0, params);
  EXPECT_EQ(plain.knitout.find("knit + b"), std::string::npos);
  EXPECT_NE(seed.knitout.find("knit + b"), std::string::npos);
  int back = 0;
  for (const TraceStep& t : seed.trace) back += t.bed == 'b' ? 1 : 0;
  EXPECT_EQ(back, static_cast<int>(seed.trace.size()) / 2);
  EXPECT_GT(seed.stats.transfers, plain.stats.transfers);
  EXPECT_GT(seed.stats.knit_time_s, plain.stats.knit_time_s);
}

}  // namespace
}  // namespace planner
