// A DAT raster as a picture: the colour-index raster drawn as KnitPaint
// shows it (first row at the bottom), each pixel a `scale` x `scale` block,
// coloured with the file's own palette. Written as an 8-bit palette PNG
// with libpng.
#pragma once

#include <iosfwd>
#include <string>

#include "backends/dat/format.hpp"

namespace dat {

inline constexpr int kMaxPngSide = 32768;  // pixels; larger pictures are refused

// Why a width x height raster cannot be drawn at `scale` (scale out of
// 1..64, picture larger than kMaxPngSide); empty when it can.
std::string png_size_problem(int width, int height, int scale);

// Writes the PNG to `out`. Returns an empty string on success, else what
// went wrong (scale out of 1..64, picture larger than kMaxPngSide, libpng
// failure).
std::string write_png(std::ostream& out, const Raster& raster, int scale);

// Writes the PNG to `path` through knitout::write_file_atomically.
std::string write_png_file(const std::string& path, const Raster& raster, int scale);

}  // namespace dat
