// The assembly guide's pages (internal to planner/assembly/): the cover
// page(s) with the title, the legend and the order to close the seams, then
// the pieces laid flat with their seams numbered (docs/assembly.md).
#pragma once

#include "planner/assembly/assembly_canvas.hpp"
#include "planner/assembly/assembly_model.hpp"
#include "planner/assembly/assembly_page_layout.hpp"

namespace planner::assembly {

// Draws every page of `layout` onto `c`, calling c.next_page() between pages.
void draw_pages(Canvas& c, const Model& m, const PageLayout& layout);

}  // namespace planner::assembly
