#include "planner/assembly/assembly_page_layout.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>

#include "planner/assembly/assembly_canvas.hpp"
#include "planner/common/index.hpp"

namespace planner::assembly {

namespace {

constexpr double kGap = 18;  // between pieces, points

std::vector<std::string> order_lines(const Model& m) {
  std::vector<std::string> lines;
  for (const Seam& s : m.seams) {
    if (s.number == m.sewn + 1 && s.part == 1)
      lines.push_back("-- put the garment on the wearer, then --");
    lines.push_back(seam_line(m, s));
  }
  for (const SeamChain& chain : m.chains) {
    if (m.arcs[at(chain.arcs.front())].seams > 0) continue;
    std::ostringstream out;
    out << (chain.arcs.size() > 1 ? "cut-arcs " : "cut-arc ");
    for (std::size_t k = 0; k < chain.arcs.size(); ++k) out << (k ? "+" : "") << chain.arcs[k];
    out << " (" << (m.arcs[at(chain.arcs.front())].lace ? "lace" : "sew")
        << "): no stitch side lies on " << (chain.arcs.size() > 1 ? "them" : "it")
        << " (shorter than a stitch); nothing to join";
    lines.push_back(out.str());
  }
  return lines;
}

// The scale of a piece on a page of its own: twice the true size when it
// fits (room for the seam numbers), small pieces enlarged to stay readable,
// large ones scaled down to the page.
double page_scale(const Placement& pl) {
  const double area_w = kPageW - 2 * kMargin;
  const double area_h = kPageH - 2 * kMargin - kPiecesTitle;
  const double fit = std::min(area_w / pl.w_mm, (area_h - kCaption) / pl.h_mm);
  const double readable = 90.0 / std::max(pl.w_mm, pl.h_mm);
  return std::min(fit, std::max(2 * kPointsPerMm, readable));
}

// A piece may be drawn smaller than on a page of its own, down to this
// share of that scale, to share the page with the end of the closing order;
// down to the second share where the guide would otherwise have more pages
// than pieces.
constexpr double kShrinkOnTablePage = 0.6;
constexpr double kShrinkToSavePage = 0.4;

// Pieces packed in shelves from `top` on page `first_page` on; returns the
// placements and sets *pages to the number of pages after `first_page`.
std::vector<Placement> place_pieces(const Model& m, int first_page, double top, int* pages,
                                    double shrink) {
  std::vector<Placement> out;
  const double right = kPageW - kMargin;
  const double bottom = kPageH - kMargin;
  int page = first_page;
  double x = kMargin;
  double y = top + kPiecesTitle;
  double shelf = 0;
  bool any = false;  // a piece placed yet
  for (std::size_t p = 0; p < m.layouts.size(); ++p) {
    Placement pl;
    pl.piece = static_cast<int>(p);
    pl.w_mm = std::max(1, m.layouts[p].needles + 1) * m.mesh.course_mm;
    pl.h_mm = std::max(1, m.layouts[p].levels) * m.mesh.wale_mm;
    pl.scale = page_scale(pl);
    // Room for the caption too (about 5 points per character at 9 points).
    auto width = [&] {
      return std::max(pl.w_mm * pl.scale, 5.0 * static_cast<double>(caption(m, pl).size()));
    };
    auto height = [&] { return pl.h_mm * pl.scale + kCaption; };
    if (any && x + width() > right) {
      x = kMargin;
      y += shelf + kGap;
      shelf = 0;
    }
    if (y + height() > bottom && !any && page == first_page) {
      const double fits = std::min((bottom - y - kCaption) / pl.h_mm, (right - x) / pl.w_mm);
      if (fits >= shrink * pl.scale) pl.scale = fits;
    }
    if (y + height() > bottom) {
      ++page;
      x = kMargin;
      y = kMargin + kPiecesTitle;
      shelf = 0;
      pl.scale = page_scale(pl);
    }
    pl.page = page;
    pl.x = x;
    pl.y = y;
    out.push_back(pl);
    x += width() + kGap;
    shelf = std::max(shelf, height());
    any = true;
  }
  *pages = page - first_page;
  return out;
}

}  // namespace

int lines_per_page(bool first) {
  const double top = first ? kTableTop : kMargin + 30;
  return static_cast<int>((kPageH - kMargin - top) / kLine) * kColumns;
}

std::string caption(const Model& m, const Placement& pl) {
  const PieceLayout& layout = m.layouts[at(pl.piece)];
  std::ostringstream out;
  out << "piece " << pl.piece + 1 << ": " << layout.needles << " needles x " << layout.levels
      << " rows, " << layout.faces.size() << " stitches";
  if (std::abs(pl.scale - kPointsPerMm) > 1e-9) {
    out.precision(2);
    out << std::fixed << " (x" << pl.scale / kPointsPerMm << ")";
  } else {
    out << " (true size)";
  }
  return out.str();
}

std::string seam_line(const Model& m, const Seam& s) {
  std::ostringstream out;
  out << s.name() << "  " << (s.lace ? "lace" : "sew") << "  piece " << s.piece[0] + 1
      << " to piece " << s.piece[1] + 1 << "  ";
  switch (s.kind) {
    case SeamKind::ScheduleCut: {
      const int lower = s.label_at[0].face;
      const int upper = s.label_at[1].face;
      out << "scheduling cut " << s.arc + 1 << " (rows "
          << m.layouts[at(m.piece_of_face[at(lower)])].faces[at(m.layout_index[at(lower)])].level +
                 1
          << " / "
          << m.layouts[at(m.piece_of_face[at(upper)])].faces[at(m.layout_index[at(upper)])].level +
                 1
          << ")";
      break;
    }
    case SeamKind::WaleSeam:
      out << "wale seam (rows knit in opposite directions)";
      break;
    case SeamKind::CutArc:
      out << (s.arcs.size() > 1 ? "cut-arcs " : "cut-arc ");
      for (std::size_t k = 0; k < s.arcs.size(); ++k) out << (k ? "+" : "") << s.arcs[k];
      if (s.parts > 1) out << " part " << s.part << " of " << s.parts;
      if (!s.labelled) out << " (no wearability label)";
      break;
  }
  // The two sides of a cut are stitch-meshed independently, so their
  // stitch counts may differ: the longer stretch is eased in evenly.
  const std::size_t a = s.sides[0].size(), b = s.sides[1].size();
  out << ", " << a << " / " << b << " stitch sides";
  if (a != b) out << ": ease evenly";
  return out.str();
}

PageLayout lay_out_pages(const Model& m, const std::string& title) {
  PageLayout out;
  out.title = title;
  out.lines = order_lines(m);
  std::size_t before_last = 0;  // lines on the pages before the last table page
  for (std::size_t room = static_cast<std::size_t>(lines_per_page(true)); room < out.lines.size();
       room += static_cast<std::size_t>(lines_per_page(false))) {
    before_last = room;
    ++out.table_pages;
  }
  // The pieces start below the first column of the last table page.
  const std::size_t on_last = out.lines.size() - before_last;
  const int per_column = lines_per_page(out.table_pages == 1) / kColumns;
  const double top = out.table_pages == 1 ? kTableTop : kMargin + 30;
  out.pieces_top =
      top +
      static_cast<double>(std::min<std::size_t>(on_last, static_cast<std::size_t>(per_column))) *
          kLine +
      6;
  out.places =
      place_pieces(m, out.table_pages - 1, out.pieces_top, &out.piece_pages, kShrinkOnTablePage);
  // No more pages to read than pieces to lay out, where a smaller first
  // piece on the table page makes that so.
  if (out.pages() > static_cast<int>(m.layouts.size())) {
    int pages = 0;
    std::vector<Placement> smaller =
        place_pieces(m, out.table_pages - 1, out.pieces_top, &pages, kShrinkToSavePage);
    if (out.table_pages + pages < out.pages()) {
      out.places = std::move(smaller);
      out.piece_pages = pages;
    }
  }
  return out;
}

}  // namespace planner::assembly
