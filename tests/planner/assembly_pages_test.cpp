// The assembly guide's page layout (planner/assembly/assembly_page_layout.hpp):
// where the closing order leaves room, the first piece shares its page,
// shrunk no further than the layout allows.
#include <gtest/gtest.h>

#include <cstddef>
#include <optional>
#include <string>

#include "planner/assembly/assembly_model.hpp"
#include "planner/assembly/assembly_page_layout.hpp"

namespace planner::assembly {
namespace {

// `pieces` tall pieces (60 needles by 150 rows at the default gauge: 64 by
// 431 mm) and `lines` lines in the closing order (cut-arcs with no seam,
// one line each).
Model model(int pieces, int lines) {
  Model m;
  m.mesh.course_mm = 1.05;
  m.mesh.wale_mm = 2.875;
  for (int p = 0; p < pieces; ++p) {
    PieceLayout layout;
    layout.needles = 60;
    layout.levels = 150;
    m.layouts.push_back(layout);
  }
  for (int a = 0; a < lines; ++a) {
    ArcInfo arc;
    arc.id = a;
    arc.seam = a;
    m.arcs.push_back(arc);
    SeamChain chain;
    chain.arcs = {a};
    chain.reversed = {false};
    m.chains.push_back(chain);
  }
  return m;
}

// The scale of the piece on a page of its own: where the closing order
// leaves no room on the cover page.
double own_page_scale() {
  const int full = lines_per_page(true) / kColumns;
  const PageLayout layout = lay_out_pages(model(1, full), "own page");
  EXPECT_EQ(layout.places.front().page, 1);
  return layout.places.front().scale;
}

TEST(AssemblyPagesTest, AOnePieceGuideHasOnePageWhereThePieceFitsAtFourTenthsItsScale) {
  const double own = own_page_scale();
  std::optional<int> saved;  // a line count where the piece shares the cover at < 0.6 of its scale
  for (int lines = 0; lines <= lines_per_page(true) / kColumns; ++lines) {
    SCOPED_TRACE(std::to_string(lines) + " lines");
    const PageLayout layout = lay_out_pages(model(1, lines), "one piece");
    ASSERT_EQ(layout.places.size(), 1U);
    const Placement& pl = layout.places.front();
    if (pl.page == 0) {
      EXPECT_EQ(layout.pages(), 1);
      // Never shrunk below four tenths of its own page's scale.
      EXPECT_GE(pl.scale, 0.4 * own - 1e-9);
      if (pl.scale < 0.6 * own) saved = lines;
    } else {
      // On a page of its own only where it would be shrunk further.
      EXPECT_EQ(layout.pages(), 2);
      EXPECT_NEAR(pl.scale, own, 1e-9);
      const PageLayout fewer = lay_out_pages(model(1, lines - 1), "one piece");
      EXPECT_TRUE(fewer.places.front().page == 1 || fewer.places.front().scale < 0.45 * own)
          << "the cover had room at " << lines - 1 << " lines but not at " << lines;
    }
  }
  // The rule acted somewhere: without it, those guides had two pages for one piece.
  ASSERT_TRUE(saved.has_value());
  // And a long closing order still sends the piece to a page of its own.
  EXPECT_EQ(lay_out_pages(model(1, lines_per_page(true) / kColumns), "one piece").pages(), 2);
}

TEST(AssemblyPagesTest, PiecesAreNotShrunkBelowSixTenthsWhenTheyHavePagesEnough) {
  const double own = own_page_scale();
  for (int lines = 0; lines <= lines_per_page(true) / kColumns; ++lines) {
    SCOPED_TRACE(std::to_string(lines) + " lines");
    const PageLayout layout = lay_out_pages(model(2, lines), "two pieces");
    ASSERT_EQ(layout.places.size(), 2U);
    EXPECT_LE(layout.pages(), 3);
    for (const Placement& pl : layout.places) {
      if (pl.page == 0) {
        EXPECT_GE(pl.scale, 0.6 * own - 1e-9);
      }
    }
  }
}

}  // namespace
}  // namespace planner::assembly
