// Stitch size of the machine and yarn (§6.1, §8.1): the target course and
// wale edge lengths of the stitch mesh, from the gauge and a measured swatch
// or given directly.
#pragma once

#include <string>
#include <string_view>

namespace planner {

struct StitchGauge {
  double needles_per_inch = 15.0;  // machine gauge (the SWG091N2 is 15 gauge)
  // §8.1: a 40 x 40 seed-stitch swatch measured 4.2 cm x 11.5 cm.
  double course_mm = 42.0 / 40.0;              // loop width: swatch width / stitches
  double wale_mm = 115.0 / 40.0;               // row height: swatch height / rows
  std::string source = "swatch 40x40:42x115";  // how the size was found, for reports
};

// Parses `STITCHESxROWS:WIDTHxHEIGHT_MM` (e.g. "40x40:42x115") into course_mm =
// WIDTH / STITCHES and wale_mm = HEIGHT / ROWS. Returns an empty string, or
// what is wrong with the text (gauge left unchanged then).
std::string parse_swatch(std::string_view text, StitchGauge& gauge);

// Parses `COURSExWALE` in millimetres (e.g. "1.05x2.875").
std::string parse_stitch_mm(std::string_view text, StitchGauge& gauge);

// Checks needles_per_inch, course_mm and wale_mm are positive and finite.
std::string check_gauge(const StitchGauge& gauge);

}  // namespace planner
