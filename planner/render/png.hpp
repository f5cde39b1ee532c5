// PNG files of the planner's pictures, from Cairo image surfaces.
#pragma once

#include <cairo.h>

#include <iosfwd>
#include <string>

namespace planner::render {

// Writes `surface` to `out` as PNG; throws std::runtime_error when Cairo
// cannot encode it or `out` fails.
void write_png(cairo_surface_t* surface, std::ostream& out);

// Writes `surface` as the PNG file `path`, atomically
// (knitout::write_file_atomically: nothing half-written is left). Returns ""
// or the failure, naming the path.
std::string write_png_file(cairo_surface_t* surface, const std::string& path);

}  // namespace planner::render
