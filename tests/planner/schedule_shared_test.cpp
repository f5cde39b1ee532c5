// The scheduler on the stitch meshes of every shared mesh: each mesh of
// ../shared/meshes is scaled to 100 mm along its longest side, cut (§4, once
// per test run: shared_cuts.hpp) and stitch-meshed (§6) with the defaults,
// written and read back as `wearknit stitch-mesh` and `wearknit schedule` do
// (write_cut and read_cut, write_smobj and parse_smobj), scheduled
// (§7.1-7.3), and every piece (plain) is run through the needle-bed VM (zero
// errors; the knit graph has one knitted loop per subdivided face, made in
// the traced order, §7.4) and the DAT backend.
//
// A mesh whose stitch mesh is not produced is a failure. A mesh whose
// stitch mesh the scheduler cannot knit yet is listed in
// kScheduleFailures with what goes wrong; they are skipped with that
// reason (docs/scheduling.md, "Open problems").
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "backends/dat/passes.hpp"
#include "backends/dat/raster.hpp"
#include "knitout/parser.hpp"
#include "planner/pipeline.hpp"
#include "planner/schedule/knitout_emit.hpp"
#include "planner/schedule/schedule.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "planner/stitch_mesh/stitch_mesher.hpp"
#include "simulators/bed/knit_graph.hpp"
#include "simulators/bed/validate.hpp"
#include "tests/planner/knitted_lines.hpp"
#include "tests/planner/shared_cuts.hpp"
#include "tests/test_support.hpp"

namespace planner {
namespace {

namespace fs = std::filesystem;

// Stitch meshes that the scheduler does not knit correctly yet, with the
// failure they show.
const std::map<std::string, std::string> kScheduleFailures = {};

// Subdivided faces (§7.4, Fig. 11): two per stitch, one per short-row
// triangle (knit in the row's first pass only).
std::size_t subdivided_faces(const StitchMesh& mesh, const Schedule& s, const Piece& piece) {
  std::size_t n = 0;
  for (int r : piece.rows) {
    for (int f : s.rows[static_cast<std::size_t>(r)].faces) {
      const StitchFace& face = mesh.faces[static_cast<std::size_t>(f)];
      n += face.type == FaceType::ShortRow || face.vertices.size() == 3 ? 1 : 2;
    }
  }
  return n;
}

// The stitch mesh of a shared mesh: its cut (shared_cuts.hpp) stitch-meshed
// with the defaults, written and read back, as `wearknit stitch-mesh` and
// `wearknit schedule` do. Skips (known failures) and fails through gtest;
// `mesh` is set on success.
// The stitch mesh of `cut`, the cut of shared mesh `name`, as above.
void stitch_cut(const std::optional<Cut>& cut, const std::string& name,
                std::optional<StitchMesh>& mesh) {
  ASSERT_TRUE(cut) << name;
  const LabelledDisc disc = labelled_disc(cut->mesh);
  ASSERT_TRUE(check_disc(disc).empty()) << name << ": the cut is not a disc";
  const StitchMeshResult stitched =
      make_directed_stitch_mesh(disc, StitchMeshParams{}, KnitDirection::Best).result;
  if (!stitched.problems.empty()) {
    FAIL() << name << ": the stitch-mesh stage reports " << stitched.problems.size()
           << " problem(s), first: " << stitched.problems.front();
  }
  std::ostringstream written;
  write_smobj(written, stitched.mesh);
  std::istringstream text(written.str());
  knitout::DiagnosticSink read_sink;
  mesh = parse_smobj(text, name + ".smobj", read_sink);
  ASSERT_TRUE(mesh) << knitout::format(read_sink.diagnostics().front());
}

void stitch_shared(const fs::path& shared, const std::string& name,
                   std::optional<StitchMesh>& mesh) {
  if (const auto known = kScheduleFailures.find(name); known != kScheduleFailures.end()) {
    GTEST_SKIP() << name << ": known scheduler failure, not yet fixed: " << known->second;
  }
  stitch_cut(shared_cuts::read_shared_cut(shared, name), name, mesh);
}

class ScheduleSharedTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ScheduleSharedTest, EveryPieceValidatesConvertsAndKnitsItsFacesInTracedOrder) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const std::string name = GetParam();
  std::optional<StitchMesh> mesh;
  stitch_shared(shared, name, mesh);
  if (::testing::Test::IsSkipped() || ::testing::Test::HasFatalFailure() || !mesh) return;

  ScheduleParams params;
  params.trials = 4;
  params.threads = 1;
  Schedule s;
  try {
    s = schedule(*mesh, params);
  } catch (const ScheduleError& e) {
    FAIL() << name << ": the schedule fails: " << e.what();
  }
  std::size_t stitches = 0;
  for (const Piece& piece : s.pieces) {
    for (int r : piece.rows) stitches += s.rows[static_cast<std::size_t>(r)].faces.size();
  }
  EXPECT_EQ(stitches, mesh->faces.size()) << "every stitch is in exactly one piece";
  RecordProperty("pieces", static_cast<int>(s.pieces.size()));
  RecordProperty("cuts", s.cuts);

  int drops = 0;
  for (std::size_t p = 0; p < s.pieces.size(); ++p) {
    SCOPED_TRACE(name + " piece " + std::to_string(p + 1) + " of " +
                 std::to_string(s.pieces.size()));
    const EmittedPiece piece = emit_piece(*mesh, s, p, EmitParams{});
    const std::string source = name + "-" + std::to_string(p + 1) + ".k";
    knitout::DiagnosticSink sink;
    const knitout::Program program = knitout::parse_string(piece.knitout, source, sink);
    bed::KnitGraph graph;
    bed::MachineOptions options;
    options.observer = &graph;
    bed::validate(program, bed::default_profile(), sink, source, options);
    ASSERT_EQ(sink.error_count(), 0u) << knitout::format(sink.sorted().front());
    // The VM warns about nothing. In particular no bind-off chain is let go
    // (V053: a dropped loop that holds stitches), so nothing can unravel:
    // every chain's last loop waits on a free needle, joins a live loop, or
    // is knit through; and no float is longer than the machine warns about
    // (V054: the yarn goes out and in again rather than float far, and a
    // cast-on is made where the yarn is; docs/scheduling.md).
    for (const knitout::Diagnostic& d : sink.diagnostics()) {
      if (d.code == "V053") ++drops;
      ADD_FAILURE() << knitout::format(d);
    }
    // One knitted loop per subdivided face, made where the trace says, in
    // the yarn's order.
    ASSERT_EQ(piece.trace.size(), subdivided_faces(*mesh, s, s.pieces[p]));
    const std::vector<std::uint32_t> made = testing::knitted_trace_lines(graph, piece.trace);
    ASSERT_EQ(made.size(), piece.trace.size());
    for (std::size_t i = 0; i < made.size(); ++i) {
      ASSERT_EQ(made[i], static_cast<std::uint32_t>(piece.trace[i].line)) << "loop " << i;
    }
    // The Shima Seiki DAT backend takes it.
    knitout::DiagnosticSink dat_sink;
    const auto passes = dat::form_passes(program, source, dat_sink);
    ASSERT_TRUE(passes) << knitout::format(dat_sink.sorted().front());
    const auto dat = dat::write_dat(*passes, dat_sink);
    ASSERT_TRUE(dat) << knitout::format(dat_sink.sorted().front());
    EXPECT_FALSE(dat->empty());
  }
  RecordProperty("v053_drops", drops);
}

// The paper knits Fertility without extra cuts from scheduling
// (§8). With the default options (100 random orders, the best 8 of each
// kind refined by improve_order, patches moved up to 8 needles, held loops
// set aside up to 8) the cut of fertility.obj on §4.1's remeshed proxy
// (the paper's kind of cut) and its stitch mesh need none
// (the random orders alone 1; without setting loops aside 1 and 7, with
// moves of up to 4 needles 3 and 13), and so does `wearknit cut --scale`
// from the command line, whose scale differs in the last bit and whose
// remesh differs with it (docs/scheduling.md).
TEST(ScheduleSharedFertilityTest, RefinedOrdersNeedFewSchedulingCutsOnFertility) {
  WEARKNIT_REQUIRE_SHARED(shared);
  std::optional<StitchMesh> mesh;
  stitch_cut(shared_cuts::remeshed_cut(shared, "fertility"), "fertility", mesh);
  if (::testing::Test::IsSkipped() || ::testing::Test::HasFatalFailure() || !mesh) return;
  const Schedule s = schedule(*mesh, ScheduleParams{});
  RecordProperty("cuts", s.cuts);
  RecordProperty("random_cuts", s.random_cuts);
  RecordProperty("loops_set_aside", static_cast<int>(s.aside_moves.size()));
  EXPECT_EQ(s.cuts, 0) << "the best of " << s.trials.size() << " random orders had "
                       << s.random_cuts << " cuts";
  EXPECT_LE(s.cuts * 3, s.random_cuts) << "the refinement removes most of the random orders' cuts";
}

INSTANTIATE_TEST_SUITE_P(Meshes, ScheduleSharedTest, ::testing::ValuesIn(shared_cuts::mesh_names()),
                         shared_cuts::test_name);

}  // namespace
}  // namespace planner
