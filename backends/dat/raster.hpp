// Carriage passes -> DAT raster, the second half of the DAT backend.
//
// Layout (docs/dat.md): 55 columns left of the design for the left option
// lines, one column per needle slot, 55 columns right; rows bottom-up: 5
// blank, 3 fixed courses, one row per pass, 3 fixed end courses, 1 blank,
// the width line with the position code, 5 blank. Each pass row holds its
// ops' colours, stop marks (13) beside its first and last slot, and option
// lines L1-L20 / R1-R20 (direction, carriers, racking, stitch, speed,
// gripper, hook, presser, pause, pass type).
//
// Errors the reference raises only while drawing are raised here too, at the
// line of the instruction that opened the offending pass: racking beyond
// +-8 (D021), a split-via-sliders pass whose return racking cannot be drawn
// (D027), Position Keep outside the bed (D028), and a raster too big for the
// DAT header (D030).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <utility>
#include <vector>

#include "backends/dat/format.hpp"
#include "backends/dat/passes.hpp"
#include "knitout/diagnostic.hpp"

namespace dat {

// Geometry of the layout.
inline constexpr int kLeftSpace = 55;  // 10 + 2 * 20 option columns + 5
inline constexpr int kRightSpace = 55;
inline constexpr int kTopSpace = 8;
inline constexpr int kBottomSpace = 5;
inline constexpr int kFixedCourses = 3;  // at the bottom and at the top of the passes
inline constexpr int kPositionColumn = kLeftSpace - 7;
inline constexpr std::uint8_t kStopMark = 13;

// The whole DAT file for `passes`; nullopt after an error.
std::optional<std::vector<std::uint8_t>> write_dat(const PassList& passes,
                                                   knitout::DiagnosticSink& sink);

// The raster (with the swg091n2 palette) for `passes`; nullopt after an error.
std::optional<Raster> rasterize(const PassList& passes, knitout::DiagnosticSink& sink);

// The position code written at column 48: where KnitPaint places the design
// on the bed (Center: centred on `;;Width:`, Keep: the first slot, Left: 1,
// Right: 0 = left to KnitPaint).
std::int64_t position_code(const PassList& passes, std::int64_t min_slot, std::int64_t max_slot);

// The colours (front, back) of a split-via-sliders pass's splits, which
// also encode the return from the sliders; nullopt when the pass was never
// returned or its return racking is not 1, 2 or 4 needles away.
std::optional<std::pair<std::uint8_t, std::uint8_t>> split_via_sliders_colours(const Pass& pass);

}  // namespace dat
