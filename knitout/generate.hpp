// Knitout programs the project builds itself: used by `wearknit demo`, the
// benchmarks and the tests, so none of them needs a data file.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>

namespace knitout {

enum class SheetPattern : std::uint8_t { Plain, Seed };

struct SheetParams {
  int width_needles = 20;  // needles f0 .. f(width-1)
  int rows = 10;           // knitted rows after the cast-on
  std::string carrier = "3";
  SheetPattern pattern = SheetPattern::Plain;
};

// Writes a flat sheet for the default swg091n2 machine: inhook, an
// alternating-tuck cast-on, `rows` rows of plain (or seed: knit/purl
// checkerboard, with the transfers it needs) knitting, outhook and a
// drop of every loop. Lines: about rows * width (plain).
void write_sheet(std::ostream& out, const SheetParams& params);
std::string sheet_text(const SheetParams& params);

}  // namespace knitout
