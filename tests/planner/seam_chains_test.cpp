// Cut-arcs chained into seams (planner/cut/seam_chains.hpp) on hand-made
// arc graphs.
#include "planner/cut/seam_chains.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace planner {
namespace {

constexpr int kSew = 0;
constexpr int kLace = 1;

std::vector<std::vector<int>> arcs_of(const std::vector<SeamChain>& seams) {
  std::vector<std::vector<int>> out;
  for (const SeamChain& s : seams) out.push_back(s.arcs);
  return out;
}

TEST(SeamChainsTest, ASingleArcIsOneOpenSeam) {
  const auto seams = chain_arcs({{4, 7, kSew}});
  ASSERT_EQ(seams.size(), 1u);
  EXPECT_EQ(seams[0].arcs, std::vector<int>{0});
  EXPECT_EQ(seams[0].reversed, std::vector<bool>{false});
  EXPECT_FALSE(seams[0].closed);
  EXPECT_EQ(seams[0].label, kSew);
}

TEST(SeamChainsTest, SameLabelArcsMeetingAtADegreeTwoVertexAreOneSeam) {
  // 1 -a0- 2 -a1- 3 -a2- 4, arc 1 stored backwards (3 to 2).
  const auto seams = chain_arcs({{1, 2, kSew}, {3, 2, kSew}, {3, 4, kSew}});
  ASSERT_EQ(seams.size(), 1u);
  EXPECT_EQ(seams[0].arcs, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(seams[0].reversed, (std::vector<bool>{false, true, false}));
  EXPECT_FALSE(seams[0].closed);
}

TEST(SeamChainsTest, AnOpenSeamStartsAtItsEndWithTheSmallerArc) {
  // 1 -a2- 2 -a1- 3 -a0- 4: walked from arc 0 at vertex 4.
  const auto seams = chain_arcs({{3, 4, kLace}, {2, 3, kLace}, {1, 2, kLace}});
  ASSERT_EQ(seams.size(), 1u);
  EXPECT_EQ(seams[0].arcs, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(seams[0].reversed, (std::vector<bool>{true, true, true}));
}

TEST(SeamChainsTest, ALabelChangeSplits) {
  const auto seams = chain_arcs({{1, 2, kSew}, {2, 3, kLace}, {3, 4, kLace}});
  EXPECT_EQ(arcs_of(seams), (std::vector<std::vector<int>>{{0}, {1, 2}}));
  EXPECT_EQ(seams[0].label, kSew);
  EXPECT_EQ(seams[1].label, kLace);
}

TEST(SeamChainsTest, ABranchNodeOfDegreeThreeSplits) {
  // Three same-label arcs meet at vertex 0; arc 3 continues arc 2 through 5.
  const auto seams = chain_arcs({{0, 1, kSew}, {0, 2, kSew}, {0, 5, kSew}, {5, 6, kSew}});
  EXPECT_EQ(arcs_of(seams), (std::vector<std::vector<int>>{{0}, {1}, {2, 3}}));
  EXPECT_EQ(seam_of_arc(seams, 4), (std::vector<int>{0, 1, 2, 2}));
}

TEST(SeamChainsTest, ADegreeTwoVertexOfAClosedArcJoinsNothingElse) {
  // Arc 0 is a loop at vertex 3 (which it ends at twice); arc 1 also ends there.
  const auto seams = chain_arcs({{3, 3, kSew}, {3, 8, kSew}});
  EXPECT_EQ(arcs_of(seams), (std::vector<std::vector<int>>{{0}, {1}}));
  EXPECT_TRUE(seams[0].closed);
  EXPECT_FALSE(seams[1].closed);
}

TEST(SeamChainsTest, ALoopOfArcsIsOneClosedSeam) {
  // 1 -a0- 2 -a1- 3 -a2- 1, every vertex of degree 2; and a separate closed arc.
  const auto seams = chain_arcs({{1, 2, kLace}, {2, 3, kLace}, {1, 3, kLace}, {9, 9, kLace}});
  ASSERT_EQ(seams.size(), 2u);
  EXPECT_EQ(seams[0].arcs, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(seams[0].reversed, (std::vector<bool>{false, false, true}));
  EXPECT_TRUE(seams[0].closed);
  EXPECT_EQ(seams[1].arcs, std::vector<int>{3});
  EXPECT_TRUE(seams[1].closed);
}

TEST(SeamChainsTest, ALoopWithALabelChangeIsTwoOpenSeams) {
  const auto seams = chain_arcs({{1, 2, kLace}, {2, 3, kSew}, {3, 1, kLace}});
  // Sewn seams first; the two laced arcs join at vertex 1 only.
  EXPECT_EQ(arcs_of(seams), (std::vector<std::vector<int>>{{1}, {0, 2}}));
  EXPECT_EQ(seams[1].reversed, (std::vector<bool>{true, true}));
  EXPECT_FALSE(seams[1].closed);
}

TEST(SeamChainsTest, EveryArcIsInExactlyOneSeam) {
  // A cut graph with branch nodes, loops, label changes.
  const std::vector<ArcEnds> arcs{{0, 1, kSew},  {1, 2, kSew}, {2, 0, kLace}, {2, 3, kLace},
                                  {3, 4, kLace}, {4, 4, kSew}, {5, 6, kSew},  {6, 5, kSew}};
  const auto seams = chain_arcs(arcs);
  std::vector<int> seen(arcs.size(), 0);
  for (const SeamChain& s : seams) {
    ASSERT_EQ(s.arcs.size(), s.reversed.size());
    for (const int a : s.arcs) ++seen[static_cast<std::size_t>(a)];
  }
  EXPECT_EQ(seen, std::vector<int>(arcs.size(), 1));
  // 0 and 1 join at vertex 1 (the lace arc 2 ends at vertex 0 beside 0);
  // vertex 2 is a branch node; 3 and 4 join at vertex 3, but 4 and the
  // loop 5 do not (vertex 4 has three ends); 6 and 7 close a loop.
  EXPECT_EQ(arcs_of(seams), (std::vector<std::vector<int>>{{0, 1}, {5}, {6, 7}, {2}, {3, 4}}));
}

}  // namespace
}  // namespace planner
