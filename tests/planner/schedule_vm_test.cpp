// The needle-bed VM judges the scheduler's knitout: every piece of every
// synthetic shape, plain and seed, validates with zero errors, and the VM's
// knit graph has one knitted loop per subdivided face, made by the yarn in
// the traced order (§7.4); the VM warns about nothing (no dropped chain, no long float).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "knitout/parser.hpp"
#include "planner/schedule/knitout_emit.hpp"
#include "simulators/bed/knit_graph.hpp"
#include "simulators/bed/validate.hpp"
#include "tests/planner/knitted_lines.hpp"
#include "tests/planner/schedule_fixtures.hpp"

namespace planner {
namespace {

namespace fx = fixtures;

TEST(ScheduleVmTest, EveryPieceValidatesAndKnitsItsFacesInTracedOrder) {
  std::vector<std::pair<std::string, StitchMesh> > shapes = {
      {"rectangle", fx::rectangle(10, 6)},
      {"trapezoid", fx::trapezoid(16, 10)},
      {"widening", fx::widening(6, 10)},
      {"short-rows-one-side", fx::short_rows(12, 3, false)},
      {"short-rows-both-sides", fx::short_rows(14, 3, true)},
      {"y-shape", fx::y_shape(14, 3, 5, 4)},
      {"crossing-branches", fx::crossing_branches(12, 3, 10)},
      {"crossing-branches-aside", fx::crossing_branches(12, 3, 22)},
      {"crossing-branches-aside-wide", fx::crossing_branches(16, 5, 18)},
      {"crossing-branches-cut", fx::crossing_branches(12, 3, 30)},
      {"ledge", fx::ledge(40, 10, 3, 3)}};
  for (std::uint32_t seed = 1; seed <= 40; ++seed) {
    shapes.emplace_back("random-" + std::to_string(seed), fx::random_shape(seed));
  }
  for (const auto& [name, mesh] : shapes) {
    ScheduleParams params;
    params.trials = 10;
    params.threads = 1;
    const Schedule s = schedule(mesh, params);
    // The "-aside" shapes are knit with held loops set aside (§7.3).
    if (name.find("-aside") != std::string::npos) {
      EXPECT_FALSE(s.aside_moves.empty()) << name;
    }
    for (StitchPattern pattern : {StitchPattern::Plain, StitchPattern::Seed}) {
      EmitParams emit;
      emit.pattern = pattern;
      for (std::size_t p = 0; p < s.pieces.size(); ++p) {
        SCOPED_TRACE(name + " " + std::string(stitch_pattern_name(pattern)) + " piece " +
                     std::to_string(p + 1));
        const EmittedPiece piece = emit_piece(mesh, s, p, emit);
        knitout::DiagnosticSink sink;
        const knitout::Program program = knitout::parse_string(piece.knitout, name, sink);
        bed::KnitGraph graph;
        bed::MachineOptions options;
        options.observer = &graph;
        bed::validate(program, bed::default_profile(), sink, name, options);
        ASSERT_EQ(sink.error_count(), 0u) << knitout::format(sink.sorted().front());
        // The VM warns about nothing: no bind-off chain is ever let go
        // (V053: a dropped loop that holds stitches lets the fabric
        // unravel), no float is longer than the machine warns about (V054).
        for (const knitout::Diagnostic& d : sink.diagnostics()) {
          ADD_FAILURE() << knitout::format(d);
        }
        // The knitted loops at the trace's lines, in the yarn's order.
        const std::vector<std::uint32_t> made = testing::knitted_trace_lines(graph, piece.trace);
        ASSERT_EQ(made.size(), piece.trace.size());
        for (std::size_t i = 0; i < made.size(); ++i) {
          EXPECT_EQ(made[i], static_cast<std::uint32_t>(piece.trace[i].line));
        }
      }
    }
  }
}

TEST(ScheduleVmTest, ACastOnAtTheFarEndOfARowIsMadeWhereTheYarnGetsThere) {
  // The wide row starts on the left, where the yarn waits after the rows
  // below; its 10 faces without a loop below are 40 needles away. Cast on
  // before the row, they would float the yarn 40 needles out and back
  // (V054, the machine warns above 24); cast on when pass A reaches them,
  // nothing floats. Seed puts their tucks on the back bed, where pass A
  // purls, so no transfer moves an empty needle (V051).
  const StitchMesh mesh = fx::ledge(40, 10, 3, 3);
  ScheduleParams params;
  params.trials = 4;
  params.threads = 1;
  const Schedule s = schedule(mesh, params);
  ASSERT_EQ(s.pieces.size(), 1u);
  for (StitchPattern pattern : {StitchPattern::Plain, StitchPattern::Seed}) {
    SCOPED_TRACE(std::string(stitch_pattern_name(pattern)));
    EmitParams emit;
    emit.pattern = pattern;
    const EmittedPiece piece = emit_piece(mesh, s, 0, emit);
    knitout::DiagnosticSink sink;
    const knitout::Program program = knitout::parse_string(piece.knitout, "ledge", sink);
    bed::validate(program, bed::default_profile(), sink, "ledge", {});
    EXPECT_EQ(sink.error_count(), 0u);
    EXPECT_EQ(sink.warning_count(), 0u)
        << (sink.diagnostics().empty() ? "" : knitout::format(sink.sorted().front()));
    // The yarn comes in once: it is not cut to reach the far faces either.
    EXPECT_EQ(piece.stats.yarn_ins, 1);
  }
}

}  // namespace
}  // namespace planner
