// Colours of the planner's pictures: red, green and blue from 0 to 1, as
// Cairo takes them.
#pragma once

#include <cairo.h>

namespace planner::render {

struct Rgb {
  double r = 0;
  double g = 0;
  double b = 0;
};

// Every channel of `c` times `factor` (shading).
inline Rgb scaled(Rgb c, double factor) {
  return {c.r * factor, c.g * factor, c.b * factor};
}

// Cairo's source colour, opaque or with `alpha` (0 transparent .. 1 opaque).
inline void set_source(cairo_t* cr, Rgb c) {
  cairo_set_source_rgb(cr, c.r, c.g, c.b);
}
inline void set_source(cairo_t* cr, Rgb c, double alpha) {
  cairo_set_source_rgba(cr, c.r, c.g, c.b, alpha);
}

}  // namespace planner::render
