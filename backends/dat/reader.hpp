// Reading a DAT back: from the decoded raster (format.hpp) to its passes.
//
// `read_layout` interprets a raster laid out as raster.hpp describes: the
// needle slots, the position code, and per pass row its direction mark,
// option lines and op colours. `compare_passes` checks a layout against the
// passes it was written from (`wearknit dat --verify`).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "backends/dat/format.hpp"
#include "backends/dat/passes.hpp"
#include "knitout/diagnostic.hpp"

namespace dat {

struct DecodedPass {
  int row = 0;                                              // raster row (0 = bottom)
  knitout::Direction direction = knitout::Direction::None;  // direction mark 6 / 7 / 1
  std::array<std::uint8_t, 21> left{};                      // option values L1..L20
  std::array<std::uint8_t, 21> right{};                     // option values R1..R20
  double racking = 0;                                       // from L2, L3, L4
  // (column - first slot column, colour) of every op pixel, left to right.
  std::vector<std::pair<int, std::uint8_t>> ops;

  int carriers() const { return right[3]; }
  int stitch() const { return right[6]; }
  int speed() const { return left[5] == 0 ? 0 : left[5] - 10; }
};

struct DatLayout {
  int width = 0;
  int height = 0;
  int slots = 0;              // needle slots of the design
  std::int64_t position = 0;  // position code (row height-7 + 100 * row height-6, column 48)
  std::vector<DecodedPass> passes;
};

// Interprets `raster`. A raster too small for the layout, or a pass row
// without option lines, is error D046 (the raster itself may still be valid
// DAT, written by another program).
std::optional<DatLayout> read_layout(const Raster& raster, std::string_view source,
                                     knitout::DiagnosticSink& sink);

// How R3 notes carriers: "-" for none, "3", "1 10", "1 5|10 5" where the
// notation cannot tell carrier 1 from 10 in the lead.
std::string carrier_code_text(int code);

// The R3 code of a pass's carriers (255 = none on knit-tuck passes, 0 = none
// on others; one carrier: its number; two: their digits, see docs/dat.md).
std::int64_t carrier_code(const Pass& pass);

// Human-readable colour-index names: "knit-front", "xfer-to-back", ...;
// "colour N" for others.
std::string colour_name(std::uint8_t colour);

// Differences between the passes `list` and the passes of a layout read
// back from the DAT written for it; empty when they agree.
std::vector<std::string> compare_passes(const PassList& list, const DatLayout& layout);

}  // namespace dat
