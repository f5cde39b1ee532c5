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

// A short stroke across the end of a seam's stretch, at `end`, coming from `from`.
void end_tick(Canvas& c, P2 end, P2 from, Rgb colour) {
  const double len = std::max(std::hypot(end.x - from.x, end.y - from.y), 1e-9);
  const P2 normal{-(end.y - from.y) / len, (end.x - from.x) / len};
  constexpr double kHalf = 4.5;
  c.polyline({{end.x - normal.x * kHalf, end.y - normal.y * kHalf},
              {end.x + normal.x * kHalf, end.y + normal.y * kHalf}},
             colour, 1.4, false, "seam-end");
}

// The legend, in two columns of three lines from `at`, and a line below.
void draw_legend(Canvas& c, P2 at) {
  constexpr double kRow = 16;
  const double col = (kPageW - 2 * kMargin) / 2;
  auto line = [&](int row, Rgb colour, double width, bool dashed, const char* cls,
                  const std::string& what) {
    const double y = at.y + row * kRow;
    c.polyline({{at.x, y - 3}, {at.x + 40, y - 3}}, colour, width, dashed, cls);
    c.text({at.x + 48, y}, what, 9, kText, Anchor::Start, false, "legend");
  };
  line(0, kSewColour, 2.2, false, "legend-sew",
       "sew: closed with a sewing needle, before dressing");
  line(1, kLaceColour, 2.2, true, "legend-lace",
       "lace: laced shut after the garment is on the wearer");
  line(2, kEdgeColour, 0.6, false, "legend-edge",
       "edge of the fabric that stays open (not a seam)");
  const double x = at.x + col;
  double y = at.y;
  c.circle({x + 20, y - 4}, 6.5, kWhite, kSewColour, 1.2);
  c.text({x + 20, y - 1.4}, "7", 7, kSewColour, Anchor::Middle, true, "legend");
  c.text({x + 48, y}, "seam 7: join the two stretches numbered 7, lowest number first", 9, kText,
         Anchor::Start, false, "legend");
  y += kRow;
  c.polyline({{x, y - 3}, {x + 40, y - 3}}, kSewColour, 2.0, false, "legend-sew-end");
  end_tick(c, {x, y - 3}, {x + 40, y - 3}, kSewColour);
  end_tick(c, {x + 40, y - 3}, {x, y - 3}, kSewColour);
  c.text({x + 48, y}, "the ends of a stretch: join end to end, easing evenly between", 9, kText,
         Anchor::Start, false, "legend");
  y += kRow;
  c.circle({x + 20, y - 4}, 8.5, kWhite, kSewColour, 1.2);
  c.text({x + 20, y - 1.4}, "7.2", 7, kSewColour, Anchor::Middle, true, "legend");
  c.text({x + 48, y}, "part 2 of seam 7, where the seam passes to another piece", 9, kText,
         Anchor::Start, false, "legend");
  c.text({at.x, at.y + 3 * kRow + 2},
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
          << m.numbered << " seam" << (m.numbered == 1 ? "" : "s") << ": ";
  if (m.sewn > 0)
    summary << "sew 1" << (m.sewn > 1 ? "-" + std::to_string(m.sewn) : "") << " first";
  else
    summary << "nothing to sew";
  const int laced = m.numbered - m.sewn;
  if (laced > 0) {
    summary << ", then put the garment on the wearer and lace " << m.sewn + 1;
    if (laced > 1) summary << "-" << m.numbered;
  }
  summary << ".";
  c.text({kMargin, kMargin + 32}, summary.str(), 10, kText, Anchor::Start, false, "summary");
  draw_legend(c, {kMargin, kMargin + 54});
  c.text({kMargin, kTableTop - 13}, "Order to close the seams", 11, kText, Anchor::Start, true,
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
        const bool lace = line.find("  lace  ") != std::string::npos;
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

// The radius of the circle around a seam's name on the pieces.
double label_radius(const Seam& sm) {
  const std::size_t n = sm.name().size();
  return n > 2 ? 6.5 + 2.0 * static_cast<double>(n - 2) : 6.5;
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
  const double r = label_radius(sm);
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

// Marks both ends of stretch `which` of seam `sm` where they lie on piece
// pl.piece, so that the two stretches are matched end to end and not only
// by their numbers: the end of its first side away from the second side,
// and the end of its last side away from the one before (a stretch's sides
// are in order along it).
void mark_stretch_ends(Canvas& c, const Model& m, const Placement& pl, const Seam& sm, int which,
                       const ToPage& to_page) {
  const std::vector<SideRef>& list = sm.sides[at(which)];
  if (list.empty()) return;
  const Rgb colour = sm.lace ? kLaceColour : kSewColour;
  // Tick at end `outer` (0: the side's first vertex, 1: its second) of `side`.
  auto tick = [&](const SideRef& side, int outer) {
    if (m.piece_of_face[at(side.face)] != pl.piece) return;
    const FaceLayout& f = m.layouts[at(pl.piece)].faces[at(m.layout_index[at(side.face)])];
    const auto seg = side_in_layout(m.mesh.faces[at(side.face)], f, side.side);
    end_tick(c, to_page(seg[at(outer)]), to_page(seg[at(1 - outer)]), colour);
  };
  // The end of `side` that `neighbour` does not share.
  auto away_from = [&](const SideRef& side, const SideRef& neighbour) {
    const auto v = side_vertices(m, side);
    const auto w = side_vertices(m, neighbour);
    return v[0] == w[0] || v[0] == w[1] ? 1 : 0;
  };
  if (list.size() == 1) {
    tick(list.front(), 0);
    tick(list.front(), 1);
    return;
  }
  tick(list.front(), away_from(list.front(), list[1]));
  tick(list.back(), away_from(list.back(), list[list.size() - 2]));
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
    mark_stretch_ends(c, m, pl, sm, key.second, to_page);
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
    const std::string name = sm.name();
    c.text({l.centre.x, l.centre.y + 2.6}, name, name.size() > 3 ? 6.5 : 7, colour, Anchor::Middle,
           true, sm.lace ? "seam-label lace" : "seam-label sew");
  }
}

}  // namespace

void draw_pages(Canvas& c, const Model& m, const PageLayout& layout) {
  draw_cover(c, m, layout);
  // The pieces: below the closing order on its last page when they fit
  // there, then on pages of their own.
  for (int page = layout.table_pages - 1; page < layout.pages(); ++page) {
    if (page >= layout.table_pages) c.next_page();
    const bool first = page == layout.table_pages - 1;
    const bool any = std::any_of(layout.places.begin(), layout.places.end(),
                                 [&](const Placement& pl) { return pl.page == page; });
    if (!any) continue;
    const double top = first ? layout.pieces_top : kMargin;
    c.text({kMargin, top + 10}, first ? "Pieces" : "Pieces (continued)", 11, kText, Anchor::Start,
           true, "page-title");
    std::vector<Label> placed;  // seam numbers on this page
    for (const Placement& pl : layout.places) {
      if (pl.page == page) draw_piece(c, m, pl, placed);
    }
  }
}

}  // namespace planner::assembly
