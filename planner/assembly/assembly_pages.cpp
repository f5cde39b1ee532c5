#include "planner/assembly/assembly_pages.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "planner/common/index.hpp"
#include "planner/schedule/piece_layout.hpp"

namespace planner::assembly {

namespace {

// Joins segments that meet end to start into polylines.
std::vector<std::vector<P2>> chain(std::vector<std::array<P2, 2>> segments) {
  std::vector<std::vector<P2>> out;
  auto same = [](P2 a, P2 b) { return std::abs(a.x - b.x) < 1e-6 && std::abs(a.y - b.y) < 1e-6; };
  std::vector<bool> used(segments.size(), false);
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (used[i]) continue;
    used[i] = true;
    std::vector<P2> line{segments[i][0], segments[i][1]};
    for (bool grew = true; grew;) {
      grew = false;
      for (std::size_t j = 0; j < segments.size(); ++j) {
        if (used[j]) continue;
        auto s = segments[j];
        if (same(s[1], line.front()) || same(s[0], line.front())) {
          if (same(s[0], line.front())) std::swap(s[0], s[1]);
          line.insert(line.begin(), s[0]);
        } else if (same(s[0], line.back()) || same(s[1], line.back())) {
          if (same(s[1], line.back())) std::swap(s[0], s[1]);
          line.push_back(s[1]);
        } else {
          continue;
        }
        used[j] = true;
        grew = true;
      }
    }
    out.push_back(std::move(line));
  }
  return out;
}

void draw_legend(Canvas& c, P2 at) {
  c.text({at.x, at.y}, "Legend", 11, kText, Anchor::Start, true, "legend");
  double y = at.y + 16;
  c.polyline({{at.x, y - 3}, {at.x + 40, y - 3}}, kSewColour, 2.2, false, "legend-sew");
  c.text({at.x + 48, y}, "sew: closed with a sewing needle, before dressing", 9, kText,
         Anchor::Start, false, "legend");
  y += 14;
  c.polyline({{at.x, y - 3}, {at.x + 40, y - 3}}, kLaceColour, 2.2, true, "legend-lace");
  c.text({at.x + 48, y}, "lace: laced shut after the garment is on the wearer", 9, kText,
         Anchor::Start, false, "legend");
  y += 14;
  c.polyline({{at.x, y - 3}, {at.x + 40, y - 3}}, kEdgeColour, 0.6, false, "legend-edge");
  c.text({at.x + 48, y}, "edge of the fabric that stays open (not a seam)", 9, kText, Anchor::Start,
         false, "legend");
  y += 16;
  c.circle({at.x + 20, y - 4}, 6, kWhite, kSewColour, 1.2);
  c.text({at.x + 20, y - 1}, "7", 7, kSewColour, Anchor::Middle, true, "legend");
  c.text({at.x + 48, y}, "seam number: the two stretches with the same number are joined", 9, kText,
         Anchor::Start, false, "legend");
  y += 14;
  c.text({at.x, y},
         "Pieces are drawn as they come off the machine: left to right = needles, bottom to top = "
         "rows, in the stitch size of the gauge.",
         9, kText, Anchor::Start, false, "legend");
}

// A seam number on a page: its circle, and the point of the seam it names.
struct Label {
  P2 centre;
  P2 anchor;
  double radius = 0;
  const Seam* seam = nullptr;
};

// Page coordinates of a point (needle, row height) of the piece at `pl`.
struct ToPage {
  P2 operator()(std::array<double, 2> q) const {
    return P2{pl.x + q[0] * course_mm * pl.scale, top + height - q[1] * wale_mm * pl.scale};
  }
  const Placement& pl;
  double course_mm;
  double wale_mm;
  double top;     // of the drawing, below the caption
  double height;  // of the drawing
};

// The cover page(s): title, legend, steps, the closing order.
void draw_cover(Canvas& c, const Model& m, const PageLayout& layout) {
  c.text({kMargin, kMargin + 14}, layout.title, 16, kText, Anchor::Start, true, "title");
  std::ostringstream summary;
  summary << m.layouts.size() << " piece" << (m.layouts.size() == 1 ? "" : "s") << ", "
          << m.seams.size() << " seam" << (m.seams.size() == 1 ? "" : "s") << ": ";
  if (m.sewn > 0)
    summary << "sew 1" << (m.sewn > 1 ? "-" + std::to_string(m.sewn) : "") << " first";
  else
    summary << "nothing to sew";
  const int laced = static_cast<int>(m.seams.size()) - m.sewn;
  if (laced > 0) {
    summary << ", then put the garment on the wearer and lace " << m.sewn + 1;
    if (laced > 1) summary << "-" << m.seams.size();
  }
  summary << ".";
  c.text({kMargin, kMargin + 34}, summary.str(), 10, kText, Anchor::Start, false, "summary");
  draw_legend(c, {kMargin, kMargin + 60});
  c.text({kMargin, kTableTop - 14}, "Order to close the seams", 11, kText, Anchor::Start, true,
         "order-title");
  std::size_t next = 0;
  for (int page = 0; page < layout.table_pages; ++page) {
    if (page > 0) {
      c.next_page();
      c.text({kMargin, kMargin + 14}, "Order to close the seams (continued)", 11, kText,
             Anchor::Start, true, "order-title");
    }
    const double top = page == 0 ? kTableTop : kMargin + 30;
    const int per_column = lines_per_page(page == 0) / kColumns;
    for (int col = 0; col < kColumns && next < layout.lines.size(); ++col) {
      for (int row = 0; row < per_column && next < layout.lines.size(); ++row, ++next) {
        const std::string& line = layout.lines[next];
        const bool lace = line.find(". lace") != std::string::npos;
        c.text({kMargin + col * (kPageW - 2 * kMargin) / kColumns, top + row * kLine}, line, 8,
               line.rfind("--", 0) == 0 ? kLaceColour : (lace ? kLaceColour : kText), Anchor::Start,
               false, "order");
      }
    }
  }
}

// A piece's edges that stay open, and its seam sides by (seam, side of the
// seam), as segments in page coordinates.
struct PieceLines {
  std::vector<std::array<P2, 2>> edges;
  std::map<std::pair<int, int>, std::vector<std::array<P2, 2>>> seam_segments;
};

PieceLines piece_lines(const Model& m, const Placement& pl, const ToPage& to_page) {
  const PieceLayout& layout = m.layouts[at(pl.piece)];
  PieceLines out;
  std::vector<std::array<P2, 2>>& edges = out.edges;
  auto& seam_segments = out.seam_segments;
  for (const FaceLayout& f : layout.faces) {
    const StitchFace& face = m.mesh.faces[at(f.face)];
    const FaceSideRoles roles = face_side_roles(face);
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      const SideRef side{f.face, static_cast<int>(i)};
      const auto seam = m.seam_of_side.find(side);
      const SideRef other = other_side(m, side);
      const bool open = other.face == kNone || m.piece_of_face[at(other.face)] != pl.piece;
      if (seam == m.seam_of_side.end() && !open) continue;
      const auto seg = side_in_layout(face, f, static_cast<int>(i));
      const std::array<P2, 2> s{to_page(seg[0]), to_page(seg[1])};
      if (seam == m.seam_of_side.end()) {
        edges.push_back(s);
      } else {
        const Seam& sm = m.seams[at(seam->second)];
        const int which =
            std::find(sm.sides[0].begin(), sm.sides[0].end(), side) != sm.sides[0].end() ? 0 : 1;
        seam_segments[{seam->second, which}].push_back(s);
      }
    }
    // The point of a short-row triangle has no side; in the layout it
    // is a gap between the triangle's bottom and top. Close it in the
    // style of the seam on either side of it, so the seam reads as one line.
    const auto corners = face_corners(f);
    auto close = [&](P2 a, P2 b, int in_side, int out_side) {
      for (int side : {in_side, out_side}) {
        const auto seam = m.seam_of_side.find({f.face, side});
        if (seam == m.seam_of_side.end()) continue;
        const Seam& sm = m.seams[at(seam->second)];
        const SideRef ref{f.face, side};
        const int which =
            std::find(sm.sides[0].begin(), sm.sides[0].end(), ref) != sm.sides[0].end() ? 0 : 1;
        seam_segments[{seam->second, which}].push_back({a, b});
        return;
      }
      edges.push_back({a, b});
    };
    if (roles.left_wale == kNone && !roles.in.empty() && !roles.out.empty())
      close(to_page(corners[3]), to_page(corners[0]), roles.in.front(), roles.out.front());
    if (roles.right_wale == kNone && !roles.in.empty() && !roles.out.empty())
      close(to_page(corners[1]), to_page(corners[2]), roles.in.back(), roles.out.back());
  }
  return out;
}

// Where the number of seam `sm` goes on its side `which` (drawn on piece
// pl.piece), clear of the numbers already `placed` on the page.
Label place_label(const Model& m, const Placement& pl, const Seam& sm, int which,
                  const ToPage& to_page, const std::vector<Label>& placed) {
  // The number sits on the middle side of the stretch, or, where
  // another number is already there, on a side near it or moved off
  // the line (with a leader) until it is clear.
  std::vector<SideRef> here;
  for (const SideRef& side : sm.sides[at(which)]) {
    if (m.piece_of_face[at(side.face)] == pl.piece) here.push_back(side);
  }
  const SideRef mid = sm.label_at[at(which)];
  const auto middle = std::find(here.begin(), here.end(), mid);
  const std::ptrdiff_t centre = middle == here.end() ? 0 : middle - here.begin();
  std::vector<std::pair<std::ptrdiff_t, SideRef>> by_distance;
  for (std::size_t k = 0; k < here.size(); ++k)
    by_distance.push_back({std::abs(static_cast<std::ptrdiff_t>(k) - centre), here[k]});
  std::stable_sort(by_distance.begin(), by_distance.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  for (std::size_t k = 0; k < here.size(); ++k) here[k] = by_distance[k].second;
  const std::string number = std::to_string(sm.number);
  const double r = number.size() > 2 ? 8.5 : 6.5;
  Label best;
  bool found = false;
  const std::size_t anchors = std::min<std::size_t>(here.size(), 8);
  for (int push = 0; push < 4 && !found; ++push) {
    for (std::size_t k = 0; k < anchors && !found; ++k) {
      const SideRef side = here[k];
      const FaceLayout& f = m.layouts[at(pl.piece)].faces[at(m.layout_index[at(side.face)])];
      const auto seg = side_in_layout(m.mesh.faces[at(side.face)], f, side.side);
      const P2 a = to_page(seg[0]);
      const P2 b = to_page(seg[1]);
      const P2 on{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
      const double len = std::max(std::hypot(b.x - a.x, b.y - a.y), 1e-9);
      const P2 normal{-(b.y - a.y) / len, (b.x - a.x) / len};
      for (int sign : {1, -1}) {
        const double d = push * 2.2 * r * sign;
        const P2 at_p{on.x + normal.x * d, on.y + normal.y * d};
        const bool clear = std::all_of(placed.begin(), placed.end(), [&](const Label& o) {
          return std::hypot(o.centre.x - at_p.x, o.centre.y - at_p.y) >= o.radius + r + 0.5;
        });
        if (!found && (clear || (push == 0 && k == 0 && sign == 1))) {
          best = {at_p, on, r, &sm};
          found = clear;
        }
        if (push == 0) break;
      }
    }
  }
  return best;
}

// A piece: its caption, its stitches, its open edges, its seams and their
// numbers (added to the page's `placed`).
void draw_piece(Canvas& c, const Model& m, const Placement& pl, std::vector<Label>& placed) {
  const PieceLayout& layout = m.layouts[at(pl.piece)];
  const double top = pl.y + kCaption;
  const ToPage to_page{pl, m.mesh.course_mm, m.mesh.wale_mm, top, pl.h_mm * pl.scale};
  c.text({pl.x, pl.y + 10}, caption(m, pl), 9, kText, Anchor::Start, true, "piece-caption");
  std::vector<std::vector<P2>> polys;
  polys.reserve(layout.faces.size());
  for (const FaceLayout& f : layout.faces) {
    std::vector<P2> poly;
    for (const auto& q : face_corners(f)) poly.push_back(to_page(q));
    polys.push_back(std::move(poly));
  }
  c.fill_polygons(polys, kFabric);
  // Open edges, then the seams over them.
  const PieceLines lines = piece_lines(m, pl, to_page);
  for (const auto& e : lines.edges) c.polyline({e[0], e[1]}, kEdgeColour, 0.6, false, "edge");
  std::vector<Label> labels;
  for (const auto& [key, segs] : lines.seam_segments) {
    const Seam& sm = m.seams[at(key.first)];
    const Rgb colour = sm.lace ? kLaceColour : kSewColour;
    for (const auto& line : chain(segs))
      c.polyline(line, colour, 2.0, sm.lace, sm.lace ? "seam-lace" : "seam-sew");
    if (sm.piece[at(key.second)] != pl.piece) continue;
    const Label best = place_label(m, pl, sm, key.second, to_page, placed);
    placed.push_back(best);
    labels.push_back(best);
  }
  for (const Label& l : labels) {
    const Seam& sm = *l.seam;
    const Rgb colour = sm.lace ? kLaceColour : kSewColour;
    if (std::hypot(l.centre.x - l.anchor.x, l.centre.y - l.anchor.y) > 0.5)
      c.polyline({l.anchor, l.centre}, colour, 0.6, false, "leader");
    c.circle(l.centre, l.radius, kWhite, colour, 1.2);
    c.text({l.centre.x, l.centre.y + 2.6}, std::to_string(sm.number), 7, colour, Anchor::Middle,
           true, sm.lace ? "seam-label lace" : "seam-label sew");
  }
}

}  // namespace

void draw_pages(Canvas& c, const Model& m, const PageLayout& layout) {
  draw_cover(c, m, layout);
  for (int page = 0; page < layout.piece_pages; ++page) {
    c.next_page();
    std::vector<Label> placed;  // seam numbers on this page
    c.text({kMargin, kMargin + 10},
           "Pieces (page " + std::to_string(page + 1) + " of " +
               std::to_string(layout.piece_pages) + ")",
           11, kText, Anchor::Start, true, "page-title");
    for (const Placement& pl : layout.places) {
      if (pl.page == layout.table_pages + page) draw_piece(c, m, pl, placed);
    }
  }
}

}  // namespace planner::assembly
