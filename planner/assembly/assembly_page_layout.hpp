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
constexpr double kLine = 11;     // line spacing of the closing order, points
constexpr double kTableTop = 200;
constexpr int kColumns = 2;

// Where a piece goes: its page, its top-left corner and scale.
struct Placement {
  int piece = 0;
  int page = 0;
  double x = 0, y = 0;  // top-left of the drawing area on the page
  double scale = 1;     // points per mm
  double w_mm = 0, h_mm = 0;
};

struct PageLayout {
  std::string title;
  std::vector<std::string> lines;  // the closing order, one line per seam
  int table_pages = 1;             // the cover page and the order's continuation pages
  std::vector<Placement> places;   // every piece, on the pages after those
  int piece_pages = 0;
  int pages() const { return table_pages + piece_pages; }
};

PageLayout lay_out_pages(const Model& m, const std::string& title);

// How many lines of the closing order fit on the cover page (first) or on a
// continuation page.
int lines_per_page(bool first);

// A piece's caption: its number, size and scale.
std::string caption(const Model& m, const Placement& pl);

}  // namespace planner::assembly
