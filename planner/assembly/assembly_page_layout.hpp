// What goes on which page of the assembly guide (internal to
// planner/assembly/): the lines of the closing order on the cover page(s),
// and the pieces packed in shelves on the pages after them
// (docs/assembly.md, "What the pages show").
#pragma once

#include <string>
#include <vector>

#include "planner/assembly/assembly_model.hpp"

namespace planner::assembly {

constexpr double kPointsPerMm = 72.0 / 25.4;
constexpr double kCaption = 16;  // height of a piece's caption, points
constexpr double kLine = 10;     // line spacing of the closing order, points
constexpr double kTableTop = 162;
constexpr int kColumns = 2;
constexpr double kPiecesTitle = 20;  // the "Pieces" title above the pieces of a page

// Where a piece goes: its page, its top-left corner and scale.
struct Placement {
  int piece = 0;
  int page = 0;
  double x = 0, y = 0;  // top-left of the drawing area on the page
  double scale = 1;     // points per mm
  double w_mm = 0, h_mm = 0;
};

// The pages: the cover page with the closing order (continued on more
// pages when it is long), then the pieces, packed in shelves from below
// the last line of the order on, so that a short order shares its page
// with the first pieces.
struct PageLayout {
  std::string title;
  std::vector<std::string> lines;  // the closing order, one line per seam or part
  int table_pages = 1;             // the cover page and the order's continuation pages
  double pieces_top = 0;           // where the pieces start on the last of those pages
  std::vector<Placement> places;   // every piece, from the last table page on
  int piece_pages = 0;             // pages after the table pages
  int pages() const { return table_pages + piece_pages; }
};

PageLayout lay_out_pages(const Model& m, const std::string& title);

// The closing order's line for a seam or part: its name, sew or lace, the
// two pieces, where it comes from and the stitch sides along each stretch
// ("4.2  sew  piece 1 to piece 3  cut-arcs 3+5 part 2 of 3, 12 / 14 stitch
// sides: ease evenly").
std::string seam_line(const Model& m, const Seam& s);

// How many lines of the closing order fit on the cover page (first) or on a
// continuation page.
int lines_per_page(bool first);

// A piece's caption: its number, size and scale.
std::string caption(const Model& m, const Placement& pl);

}  // namespace planner::assembly
