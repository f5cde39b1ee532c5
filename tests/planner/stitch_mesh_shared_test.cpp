// Stitch meshing of the cut meshes of every shared test mesh: each mesh is
// scaled to 100 mm along its longest side, cut (§4) and remeshed (§6) at the
// default gauge with the default options. Every stitch mesh must be valid
// (only the four face types, one disc with the cut mesh's boundary) and have
// the stitch sizes of Limits: stitches of the machine's size, as many as the
// area holds. The cuts are made once per test run (shared_cuts.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "planner/pipeline.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "planner/stitch_mesh/stitch_mesher.hpp"
#include "tests/planner/shared_cuts.hpp"
#include "tests/planner/stitch_discs.hpp"
#include "tests/test_support.hpp"

namespace planner {
namespace {

// The stitch sizes: mean course and wale lengths within 5% of the target,
// 90% of each within 15%, stitches within 10% of area / (course x wale).
struct Limits {
  double mean = 0.05;         // |mean / target - 1| at most
  double within = 0.90;       // fraction of edges within 15%, at least
  double wale_mean = 0.05;    // as `mean`, for wale edges
  double wale_within = 0.90;  // as `within`, for wale edges
  double stitches = 0.10;     // |stitches / (area / (course x wale)) - 1| at most
};

// Where the stitch mesher's wale sides run long on the default cut
// (docs/cutting.md, "Known limits"): about half of them lean, the rest
// belong to tall rows where the field proxy's few long cuts meet the rows
// (`armadillo`, `gargoyle`; bench/wale_sides.py splits them), or round a
// pit or peak of the row time that the drain fits leave (`anchor`). Each
// mesh is held to a little over what it reaches today, so that it can only
// get better.
const std::map<std::string, Limits>& known_fans() {
  static const std::map<std::string, Limits> fans = {
      {"anchor", {0.05, 0.90, 0.15, 0.78, 0.10}},     // wale mean 1.12, 80% within
      {"armadillo", {0.05, 0.90, 0.05, 0.86, 0.10}},  // 86.9% of wale sides within
      {"gargoyle", {0.05, 0.90, 0.08, 0.84, 0.10}},   // wale mean 1.08, 87% within
  };
  return fans;
}

struct Meshed {
  LabelledDisc disc;
  StitchMeshResult result;
};

// One read of each cut per process (a test runs its mesh's cases in one).
const LabelledDisc& shared_disc(const std::filesystem::path& shared, const std::string& name) {
  static std::map<std::string, LabelledDisc> discs;
  auto it = discs.find(name);
  if (it == discs.end()) {
    const std::optional<Cut> cut = shared_cuts::read_shared_cut(shared, name);
    LabelledDisc disc;
    if (cut) {
      disc = labelled_disc(cut->mesh);
      disc.surface = cut->surface;  // as the stage lays the stitches on the garment
    }
    it = discs.emplace(name, std::move(disc)).first;
  }
  return it->second;
}

// Valid faces only, one disc, the cut mesh's boundary.
void expect_valid(const Meshed& m) {
  for (const std::string& p : m.result.problems) ADD_FAILURE() << p;
  EXPECT_TRUE(check(m.result.mesh).empty());
  const StitchMeshFigures f = measure(m.result.mesh);
  EXPECT_EQ(f.boundary_loops, 1);
  EXPECT_EQ(f.euler_characteristic, 1);
  // The sheet's edge is the cut mesh's boundary, moved onto the garment's
  // surface where the cut records it (Q's edges are chords of the garment;
  // a move of up to a wale is made).
  const double edge_tolerance = m.disc.surface.faces.empty() ? 1e-6 : m.result.mesh.wale_mm;
  EXPECT_LT(stitch_discs::farthest_boundary_vertex(m.disc, m.result.mesh), edge_tolerance);
}

void expect_sizes(const Meshed& m, const Limits& limits) {
  const StitchMeshFigures f = measure(m.result.mesh);
  const StitchMeshParams p;
  EXPECT_NEAR(f.course.mean_mm / p.course_mm, 1.0, limits.mean);
  EXPECT_NEAR(f.wale.mean_mm / p.wale_mm, 1.0, limits.wale_mean);
  EXPECT_GE(f.course.within_15_percent, limits.within);
  EXPECT_GE(f.wale.within_15_percent, limits.wale_within);
  const double expected = disc_area_mm2(m.disc) / (p.course_mm * p.wale_mm);
  EXPECT_NEAR(f.faces / expected, 1.0, limits.stitches);
  // Stitches that span a gap of the surface (the fans, docs/stitch-mesh.md) stay rare.
  const OffSurface off = off_surface_faces(m.result.mesh, m.disc, p.wale_mm);
  EXPECT_LE(static_cast<double>(off.faces.size()), 0.02 * f.faces) << off.max_offset_mm;
  std::cout << "off the surface: " << off.faces.size() << " stitches, up to " << off.max_offset_mm
            << " mm\n";
  std::cout << "figures: course mean " << f.course.mean_mm / p.course_mm << ", within 15% "
            << f.course.within_15_percent << "; wale mean " << f.wale.mean_mm / p.wale_mm
            << ", within 15% " << f.wale.within_15_percent << "; stitches / estimate "
            << f.faces / expected << "\n";
}

// The cut mesh of the shared mesh named by the parameter.
class SharedDiscTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    WEARKNIT_REQUIRE_SHARED(shared);
    disc_ = &shared_disc(shared, GetParam());
    ASSERT_FALSE(disc_->faces.empty());
    ASSERT_TRUE(check_disc(*disc_).empty()) << GetParam() << ": the cut is not a disc";
  }
  const LabelledDisc& disc() const { return *disc_; }

 private:
  const LabelledDisc* disc_ = nullptr;
};

class StitchMeshSharedTest : public SharedDiscTest {};

// With the default options (rules of thumb on; the rows along the better of
// the cut's two directions, as the stage makes them).
TEST_P(StitchMeshSharedTest, IsAValidDiscOfTheStitchSizes) {
  Meshed m;
  DirectedStitchMesh directed =
      make_directed_stitch_mesh(disc(), StitchMeshParams{}, KnitDirection::Best);
  m.disc = directed.turned ? turned(disc()) : disc();
  m.result = std::move(directed.result);
  std::cout << "rows along the cut's " << (directed.turned ? "wale" : "course") << " sides; scores "
            << directed.score_as_cut << " as cut, " << directed.score_turned << " turned\n";
  EXPECT_GE(directed.turned ? directed.score_turned : directed.score_as_cut,
            std::max(directed.score_as_cut, directed.score_turned));
  expect_valid(m);
  const auto fan = known_fans().find(GetParam());
  expect_sizes(m, fan == known_fans().end() ? Limits{} : fan->second);
}

INSTANTIATE_TEST_SUITE_P(Meshes, StitchMeshSharedTest,
                         ::testing::ValuesIn(shared_cuts::mesh_names()), shared_cuts::test_name);

// Other gauges: stitches much coarser than the default (a chunky machine on a
// small object: a row can be as tall as a feature of the cut), flat ones
// (course four times the wale) and tall ones. The stitch mesh must stay
// valid; Limits holds for the default gauge only. At these sizes rows
// begin and end at tips of the cut, and strips need the handling that
// docs/stitch-mesh.md, "Other gauges", lists (each size made one of them
// fail on some mesh without it).
class StitchMeshSharedGaugeTest : public SharedDiscTest {};

TEST_P(StitchMeshSharedGaugeTest, CoarseFlatAndTallStitchesGiveAValidDisc) {
  Meshed m;
  m.disc = disc();
  for (const auto& [course, wale] : std::vector<std::pair<double, double>>{
           {5, 5}, {8, 2}, {8, 8}, {12, 12}, {6, 12}, {10, 20}}) {
    SCOPED_TRACE(std::to_string(course) + " x " + std::to_string(wale) + " mm");
    StitchMeshParams params;
    params.course_mm = course;
    params.wale_mm = wale;
    m.result = make_stitch_mesh(m.disc, params);
    expect_valid(m);
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, StitchMeshSharedGaugeTest,
                         ::testing::ValuesIn(shared_cuts::mesh_names()), shared_cuts::test_name);

// A cut mesh meshed with the defaults and with `other`, both valid.
std::pair<Meshed, Meshed> defaults_and(const LabelledDisc& disc, const StitchMeshParams& other) {
  std::pair<Meshed, Meshed> both;
  both.first.disc = disc;
  both.first.result = make_stitch_mesh(disc, StitchMeshParams{});
  both.second.disc = disc;
  both.second.result = make_stitch_mesh(disc, other);
  expect_valid(both.first);
  expect_valid(both.second);
  return both;
}

// Saddles of the row time held on a level (docs/stitch-mesh.md, step 2):
// on the remeshed proxy's cuts of these two meshes, whose rows go round
// saddles, left where the fit put them they leave a fan of wale sides
// across the surface and the wale mean misses its Limits; held, the fan is
// gone.
class StitchMeshSharedSaddleTest : public ::testing::TestWithParam<std::string> {};

TEST_P(StitchMeshSharedSaddleTest, SaddlesHeldOnALevelLeaveNoFan) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const std::optional<Cut> cut = shared_cuts::remeshed_cut(shared, GetParam());
  ASSERT_TRUE(cut) << GetParam();
  LabelledDisc disc = labelled_disc(cut->mesh);
  disc.surface = cut->surface;
  StitchMeshParams off;
  off.saddle_wales = 0;
  const auto [held, left] = defaults_and(disc, off);
  EXPECT_EQ(left.result.stats.saddles_pinned, 0);
  EXPECT_GT(held.result.stats.saddles_pinned, 0);
  const double wale = StitchMeshParams{}.wale_mm;
  const double left_mean = measure(left.result.mesh).wale.mean_mm / wale;
  const double held_mean = measure(held.result.mesh).wale.mean_mm / wale;
  std::cout << "wale mean / target: " << left_mean << " left, " << held_mean << " held\n";
  EXPECT_GT(left_mean, 1.05);
  EXPECT_NEAR(held_mean, 1.0, 0.05);
  EXPECT_LT(off_surface_faces(held.result.mesh, held.disc, wale).faces.size(),
            off_surface_faces(left.result.mesh, left.disc, wale).faces.size());
}

INSTANTIATE_TEST_SUITE_P(Meshes, StitchMeshSharedSaddleTest,
                         ::testing::Values("teddy-quad", "half-torus"), shared_cuts::test_name);

// The rules of thumb (the default) leave fewer unstable configurations than
// sizes alone, and the stitch mesh stays valid either way.
class StitchMeshSharedRulesTest : public SharedDiscTest {};

TEST_P(StitchMeshSharedRulesTest, RulesOfThumbLeaveFewerUnstableShapings) {
  StitchMeshParams no_rules;
  no_rules.stability_cost = 0;
  const auto [with_rules, sizes_only] = defaults_and(disc(), no_rules);
  const StabilityCounts before = count_stability_rules(sizes_only.result.mesh);
  const StabilityCounts after = count_stability_rules(with_rules.result.mesh);
  const int total_before = before.edge_shaping + before.stacked_shaping + before.opposed_shaping;
  const int total_after = after.edge_shaping + after.stacked_shaping + after.opposed_shaping;
  EXPECT_LE(total_after, total_before);
  if (total_before > 10) {
    EXPECT_LT(total_after, total_before * 2 / 3);
  }
}

INSTANTIATE_TEST_SUITE_P(Meshes, StitchMeshSharedRulesTest,
                         ::testing::Values("disc-quad", "torus-qd", "bunny-qd"),
                         shared_cuts::test_name);

}  // namespace
}  // namespace planner
