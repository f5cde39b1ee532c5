// The linking test (planner/wearability/linking.hpp): linking numbers of
// polylines, the cycles that span a surface's first homology, and garments
// on a torus and a sphere whose curves do or do not wind around the wearer.
#include "planner/wearability/linking.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cover_shapes.hpp"
#include "planner/wearability/wearability.hpp"

namespace {

using planner::Loop;
using planner::Vec3;
using wearknit::test::sphere_mesh;
using wearknit::test::torus_cover;
using wearknit::test::torus_mesh;

const Vec3 kView(0.3, 0.5, 0.81);

// `n` points of a curve t ↦ f(2πk/n).
template <typename F>
Loop sampled(int n, F f) {
  Loop loop;
  for (int k = 0; k < n; ++k) loop.push_back(f(2 * std::numbers::pi * k / n));
  return loop;
}

Loop circle_xy(double radius, const Vec3& centre) {
  return sampled(
      64, [&](double t) { return Vec3(centre + radius * Vec3(std::cos(t), std::sin(t), 0)); });
}

Loop circle_xz(double radius, const Vec3& centre) {
  return sampled(
      64, [&](double t) { return Vec3(centre + radius * Vec3(std::cos(t), 0, std::sin(t))); });
}

TEST(LinkingTest, TwoRingsOfAChainLinkOnceAndApartNotAtAll) {
  const Loop a = circle_xy(1.0, Vec3::Zero());
  const Loop through = circle_xz(1.0, Vec3(1, 0, 0));
  const auto linked = planner::linking_number(a, through, kView);
  ASSERT_TRUE(linked.has_value());
  EXPECT_EQ(std::abs(*linked), 1);
  // Symmetric, and reversing one curve flips the sign.
  EXPECT_EQ(planner::linking_number(through, a, kView), linked);
  const Loop reversed(through.rbegin(), through.rend());
  EXPECT_EQ(planner::linking_number(a, reversed, kView), -*linked);
  // Any generic view gives the same number.
  EXPECT_EQ(planner::linking_number(a, through, Vec3(-0.7, 0.2, 0.3)), linked);
  EXPECT_EQ(planner::linking_number(a, circle_xz(1.0, Vec3(3, 0, 0)), kView), 0);
  // Passing beside the ring, not through it.
  EXPECT_EQ(planner::linking_number(a, circle_xz(0.4, Vec3(1.6, 0, 0)), kView), 0);
}

TEST(LinkingTest, ACurveWindingTwiceAroundARingLinksItTwice) {
  // Once along the unit circle and twice around it, 0.3 away.
  const Loop twice = sampled(200, [](double t) {
    const double rho = 1 + 0.3 * std::cos(2 * t);
    return Vec3(rho * std::cos(t), rho * std::sin(t), 0.3 * std::sin(2 * t));
  });
  const auto linked = planner::linking_number(circle_xy(1.0, Vec3::Zero()), twice, kView);
  ASSERT_TRUE(linked.has_value());
  EXPECT_EQ(std::abs(*linked), 2);
}

TEST(LinkingTest, ACrossingThroughAVertexIsDegenerate) {
  // Seen along z, the square's corner (1, 0) lies on the ring's segment.
  const Loop square = {Vec3(1, 0, 1), Vec3(2, 1, 1), Vec3(3, 0, 1), Vec3(2, -1, 1)};
  const Loop segment_through = {Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(0, 0, 0)};
  EXPECT_FALSE(planner::linking_number(square, segment_through, Vec3(0, 0, 1)).has_value());
}

int cycles_of(const planner::CoverMesh& mesh) {
  return static_cast<int>(
      planner::homology_cycles(static_cast<int>(mesh.positions.size()), mesh.faces, 100).size());
}

TEST(LinkingTest, CyclesSpanTheFirstHomology) {
  // 2g on a closed surface, 2g + b - 1 with b boundary loops.
  EXPECT_EQ(cycles_of(torus_mesh(1.0, 0.4, 12, 8)), 2);
  EXPECT_EQ(cycles_of(sphere_mesh(1.0, 12, 8)), 0);
  EXPECT_EQ(cycles_of(sphere_mesh(1.0, 12, 8, 2.0)), 0);  // an open cap: a disc
  // The torus cut along its outer equator: an annulus.
  const planner::CoverMesh cover = torus_cover(1.0, 0.4, 12, 8, 1);
  const auto band = planner::open_cuts(cover, {false, true});
  EXPECT_EQ(
      planner::homology_cycles(static_cast<int>(band.positions.size()), band.faces, 100).size(),
      1u);
  const auto disc = planner::open_cuts(cover, {true, true});
  EXPECT_EQ(
      planner::homology_cycles(static_cast<int>(disc.positions.size()), disc.faces, 100).size(),
      0u);
  // Each cycle is a closed walk along edges of the mesh.
  const planner::CoverMesh torus = torus_mesh(1.0, 0.4, 12, 8);
  for (const auto& cycle :
       planner::homology_cycles(static_cast<int>(torus.positions.size()), torus.faces, 100)) {
    ASSERT_GE(cycle.size(), 3u);
    for (std::size_t i = 0; i < cycle.size(); ++i) {
      const int a = cycle[i], b = cycle[(i + 1) % cycle.size()];
      bool edge = false;
      for (const auto& face : torus.faces)
        for (std::size_t k = 0; k < face.size(); ++k)
          edge = edge || (face[k] == a && face[(k + 1) % face.size()] == b) ||
                 (face[k] == b && face[(k + 1) % face.size()] == a);
      EXPECT_TRUE(edge) << a << "-" << b;
    }
  }
  // A triangle soup has no cycles until its corners are welded: the test
  // welds the wearer's.
  EXPECT_EQ(planner::homology_cycles(6, {{0, 1, 2}, {3, 4, 5}}, 100).size(), 0u);
}

cloth::SignedDistanceField field_of(const planner::CoverMesh& mesh) {
  cloth::SdfParams sdf;
  sdf.resolution = 48;
  return cloth::SignedDistanceField(mesh.positions, mesh.faces, sdf);
}

TEST(LinkingTest, BandsAroundATorusAreLinkedAndItsDiscIsNot) {
  const cloth::SignedDistanceField wearer = field_of(torus_mesh(1.0, 0.4, 48, 16));
  const planner::LinkingTest test(wearer);
  EXPECT_EQ(test.wearer_loops(), 2);
  const planner::CoverMesh cover =
      planner::dressed(torus_cover(1.0, 0.4, 48, 16, 2), wearer, cloth::ClothParams{});
  // Every arc open: a disc.
  EXPECT_FALSE(test.linked(planner::open_cuts(cover, {true, true, true})));
  // The meridian sewn: a band around the torus's hole, open along its
  // outer equator. Its curves run around the hole beside the tube, never
  // around the tube: a rubber band around a ring slips off over its side.
  EXPECT_FALSE(test.linked(planner::open_cuts(cover, {false, true, true})));
  // Half the equator sewn: a band around the tube.
  const auto tube = test.linked(planner::open_cuts(cover, {true, false, true}));
  ASSERT_TRUE(tube);
  EXPECT_EQ(std::abs(tube->linking_number), 1);
  // Sewn shut: linked both ways.
  EXPECT_TRUE(test.linked(planner::open_cuts(cover, {false, false, false})));
}

TEST(LinkingTest, ACoarseGarmentWhoseChordsDipIntoTheWearerIsFollowedOutside) {
  // Six faces around the tube: dressed, every vertex is outside the torus,
  // but the middles of the edges around the tube are inside it.
  const cloth::SignedDistanceField wearer = field_of(torus_mesh(1.0, 0.4, 48, 16));
  const planner::LinkingTest test(wearer);
  const planner::CoverMesh cover =
      planner::dressed(torus_cover(1.0, 0.4, 12, 6, 2), wearer, cloth::ClothParams{});
  int inside = 0;
  for (const auto& face : cover.faces) {
    for (std::size_t k = 0; k < face.size(); ++k) {
      const Vec3 middle =
          0.5 * (cover.positions[static_cast<std::size_t>(face[k])] +
                 cover.positions[static_cast<std::size_t>(face[(k + 1) % face.size()])]);
      inside += wearer.value(middle) < 0;
    }
  }
  EXPECT_GT(inside, 0);
  EXPECT_TRUE(test.linked(planner::open_cuts(cover, {true, false, true})));
  EXPECT_FALSE(test.linked(planner::open_cuts(cover, {true, true, true})));
}

TEST(LinkingTest, NothingIsLinkedWithABall) {
  // A ball has no curve to wind around: even the closed shell, which can
  // never come off, is left to the simulation.
  const planner::CoverMesh ball = sphere_mesh(1.0, 24, 12);
  const cloth::SignedDistanceField wearer = field_of(ball);
  const planner::LinkingTest test(wearer);
  EXPECT_EQ(test.wearer_loops(), 0);
  EXPECT_FALSE(test.linked(planner::open_cuts(
      planner::dressed(sphere_mesh(1.0, 24, 12), wearer, cloth::ClothParams{}), {})));
}

// A short open tube about the z axis, a napkin ring: radius 0.5, z from
// -0.15 to 0.15, no caps. (A long open tube winds almost once around the
// points on its axis, so the distance field counts them inside it, as the
// simulation does.)
planner::CoverMesh open_tube() {
  planner::CoverMesh tube;
  const int around = 32, along = 3;
  for (int j = 0; j <= along; ++j) {
    for (int i = 0; i < around; ++i) {
      const double t = 2 * std::numbers::pi * i / around;
      tube.positions.push_back({0.5 * std::cos(t), 0.5 * std::sin(t), -0.15 + 0.3 * j / along});
    }
  }
  for (int j = 0; j < along; ++j) {
    for (int i = 0; i < around; ++i) {
      const int a = j * around + i, b = j * around + (i + 1) % around;
      tube.faces.push_back({a, b, b + around, a + around});
    }
  }
  return tube;
}

// A band of cloth along the closed polyline `path`, `width` wide across
// `side`: one quad per segment, its one cycle along `path`.
cloth::PolygonMesh band_along(const Loop& path, const Vec3& side, double width) {
  cloth::PolygonMesh band;
  const int n = static_cast<int>(path.size());
  for (const Vec3& p : path) {
    band.positions.push_back(p - 0.5 * width * side);
    band.positions.push_back(p + 0.5 * width * side);
  }
  for (int k = 0; k < n; ++k) {
    const int a = 2 * k, b = 2 * ((k + 1) % n);
    band.faces.push_back({a, b, b + 1, a + 1});
  }
  return band;
}

TEST(LinkingTest, ARingThreadedThroughAnOpenTubeIsLinkedAndOneAroundItIsNot) {
  // A wearer with a boundary: its curve runs around the tube. A ring through
  // the tube and back outside it cannot come off (it would cross the wall);
  // a ring around the tube slides off over its rim.
  const planner::CoverMesh tube = open_tube();
  const cloth::SignedDistanceField wearer = field_of(tube);
  const planner::LinkingTest test(wearer);
  EXPECT_EQ(test.wearer_loops(), 1);
  Loop threaded;
  auto line = [&](const Vec3& from, const Vec3& to, int steps) {
    for (int k = 0; k < steps; ++k) threaded.push_back(from + (to - from) * (double(k) / steps));
  };
  line(Vec3(0, 0, -0.6), Vec3(0, 0, 0.6), 24);
  line(Vec3(0, 0, 0.6), Vec3(1.0, 0, 0.6), 20);
  line(Vec3(1.0, 0, 0.6), Vec3(1.0, 0, -0.6), 24);
  line(Vec3(1.0, 0, -0.6), Vec3(0, 0, -0.6), 20);
  EXPECT_TRUE(test.linked(band_along(threaded, Vec3::UnitY(), 0.05)));
  const Loop around =
      sampled(48, [](double t) { return Vec3(0.8 * std::cos(t), 0.8 * std::sin(t), 0); });
  EXPECT_FALSE(test.linked(band_along(around, Vec3::UnitZ(), 0.05)));
}

TEST(LinkingTest, AGarmentCurveInsideTheWearerIsNotTrusted) {
  // The torus's own surface, not dressed: its curves touch the wearer, so no
  // linking number is taken from them.
  const planner::CoverMesh torus = torus_mesh(1.0, 0.4, 48, 16);
  const cloth::SignedDistanceField wearer = field_of(torus);
  const planner::LinkingTest test(wearer);
  planner::CoverMesh shrunk = torus;
  for (auto& p : shrunk.positions) {
    const Vec3 centre = Vec3(p.x(), p.y(), 0).normalized();
    p = centre + 0.5 * (p - centre);
  }
  EXPECT_FALSE(test.linked(planner::open_cuts(shrunk, {})));
}

TEST(LinkingTest, TheEliminationLacesLinkedArcsWithoutSimulating) {
  // A torus cover over its torus: an equator arc sewn closes a band around
  // the tube, and the linking test fails such a test at once (simulated, its
  // four trials run until they stall). The meridian's test is simulated.
  const planner::CoverMesh wearer_mesh = torus_mesh(1.0, 0.4, 48, 16);
  const cloth::SignedDistanceField wearer = field_of(wearer_mesh);
  const planner::CoverMesh cover = torus_cover(1.0, 0.4, 24, 12, 3);
  planner::WearabilityParams params;
  params.threads = 2;
  params.seed = 3;
  const auto fast = planner::eliminate(cover, wearer, params);
  ASSERT_TRUE(fast.wearable());
  EXPECT_FALSE(fast.arcs[0].test.linked);
  EXPECT_FALSE(fast.arcs[0].test.trials.empty());
  for (std::size_t a = 1; a < fast.arcs.size(); ++a) {
    EXPECT_EQ(fast.arcs[a].label, planner::Label::Lace);
    EXPECT_TRUE(fast.arcs[a].test.linked);
    EXPECT_TRUE(fast.arcs[a].test.trials.empty());
  }
  EXPECT_GE(fast.linked, 3);
  // Simulated instead, the equator arcs are laced all the same.
  params.linking = false;
  const auto slow = planner::eliminate(cover, wearer, params);
  EXPECT_EQ(slow.linked, 0);
  for (std::size_t a = 1; a < slow.arcs.size(); ++a) {
    EXPECT_EQ(slow.arcs[a].label, planner::Label::Lace);
    EXPECT_FALSE(slow.arcs[a].test.trials.empty());
  }
  EXPECT_GT(slow.steps, fast.steps);
}

}  // namespace
