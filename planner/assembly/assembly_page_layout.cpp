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

// One line of the closing order.
std::string seam_line(const Model& m, const Seam& s) {
  std::ostringstream out;
  out << s.number << ". " << (s.lace ? "lace" : "sew") << "  piece " << s.piece[0] + 1
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
      out << "cut-arc " << s.arc;
      if (s.parts > 1) out << " part " << s.part << " of " << s.parts;
      if (!s.labelled) out << " (no wearability label)";
      break;
  }
  out << ", " << s.sides[0].size() << " / " << s.sides[1].size() << " stitch sides";
  return out.str();
}

std::vector<std::string> order_lines(const Model& m) {
  std::vector<std::string> lines;
  for (const Seam& s : m.seams) {
    if (s.number == m.sewn + 1) lines.push_back("-- put the garment on the wearer, then --");
    lines.push_back(seam_line(m, s));
  }
  for (const ArcInfo& a : m.arcs) {
    if (a.seams == 0) {
      std::ostringstream out;
      out << "cut-arc " << a.id << " (" << (a.lace ? "lace" : "sew")
          << "): no stitch side lies on it (shorter than a stitch); nothing to join";
      lines.push_back(out.str());
    }
  }
  return lines;
}

// Pieces packed in shelves, from page `first_page` on; returns the
// placements and sets *pages to the number of piece pages.
std::vector<Placement> place_pieces(const Model& m, int first_page, int* pages) {
  std::vector<Placement> out;
  const double area_w = kPageW - 2 * kMargin;
  const double area_h = kPageH - 2 * kMargin - 20;
  double x = kMargin;
  double y = kMargin + 20;
  double shelf = 0;
  int page = first_page;
  bool any = false;
  for (std::size_t p = 0; p < m.layouts.size(); ++p) {
    Placement pl;
    pl.piece = static_cast<int>(p);
    pl.w_mm = std::max(1, m.layouts[p].needles + 1) * m.mesh.course_mm;
    pl.h_mm = std::max(1, m.layouts[p].levels) * m.mesh.wale_mm;
    const double fit = std::min(area_w / pl.w_mm, (area_h - kCaption) / pl.h_mm);
    // Twice the true size when it fits (room for the seam numbers), small
    // pieces enlarged to stay readable, large ones scaled down to the page.
    const double readable = 90.0 / std::max(pl.w_mm, pl.h_mm);
    pl.scale = std::min(fit, std::max(2 * kPointsPerMm, readable));
    // Room for the caption too (about 5 points per character at 9 points).
    const double w = std::max(pl.w_mm * pl.scale, 5.0 * static_cast<double>(caption(m, pl).size()));
    const double h = pl.h_mm * pl.scale + kCaption;
    if (any && x + w > kMargin + area_w) {
      x = kMargin;
      y += shelf + kGap;
      shelf = 0;
    }
    if (any && y + h > kMargin + 20 + area_h) {
      ++page;
      x = kMargin;
      y = kMargin + 20;
      shelf = 0;
    }
    pl.page = page;
    pl.x = x;
    pl.y = y;
    out.push_back(pl);
    x += w + kGap;
    shelf = std::max(shelf, h);
    any = true;
  }
  *pages = any ? page - first_page + 1 : 0;
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

PageLayout lay_out_pages(const Model& m, const std::string& title) {
  PageLayout out;
  out.title = title;
  out.lines = order_lines(m);
  for (std::size_t room = static_cast<std::size_t>(lines_per_page(true)); room < out.lines.size();
       room += static_cast<std::size_t>(lines_per_page(false)))
    ++out.table_pages;
  out.places = place_pieces(m, out.table_pages, &out.piece_pages);
  return out;
}

}  // namespace planner::assembly
