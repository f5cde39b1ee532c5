// The Shima Seiki DAT file as the swg091n2 profile writes it (docs/dat.md).
//
// A DAT holds a raster of colour indices (one byte per pixel, row 0 at the
// bottom) plus a palette. Bytes 0x000-0x1FF are a header of little-endian
// u16 values (x-min, y-min, x-max, y-max, and 1000 at offsets 8 and 16),
// 0x200-0x4FF the palette (256 red, 256 green, 256 blue bytes), 0x500-0x5FF
// zero, and from 0x600 on (colour, run length) byte pairs row after row.
//
// This header holds the format's constants, the raster type and the
// byte-level encoder and decoder. Pass formation is in passes.hpp, the layout
// of passes as rows in raster.hpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "knitout/diagnostic.hpp"

namespace dat {

inline constexpr std::size_t kHeaderBytes = 0x200;
inline constexpr std::size_t kPaletteOffset = 0x200;
inline constexpr std::size_t kPaletteBytes = 768;
inline constexpr std::size_t kDataOffset = 0x600;
inline constexpr std::uint16_t kHeaderMagic = 1000;  // at offsets 8 and 16
inline constexpr int kMaxRunLength = 255;
inline constexpr int kMaxDimension = 0xFFFF;  // x-max / y-max are u16
// The largest raster read or written, in pixels (one byte each): 4096 columns
// by 65536 rows, far beyond any machine's bed. The header alone can declare
// 2^32 pixels; a file declaring more than this is refused (D047) before
// anything is allocated for it (docs/dat.md).
inline constexpr std::uint64_t kMaxRasterPixels = std::uint64_t{1} << 28;

// The palette of the swg091n2 profile, R[256] G[256] B[256] (palette.cpp).
extern const std::array<std::uint8_t, kPaletteBytes> kPalette;

// A raster of colour indices; pixel (x, y) is pixels[y * width + x], y = 0 is
// the bottom row (the first one in the file).
struct Raster {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;
  std::array<std::uint8_t, kPaletteBytes> palette{};

  std::uint8_t at(int x, int y) const {
    return pixels[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(x)];
  }
};

// Appends the run-length pairs of one row to `out`, exactly as the reference
// encoder does: runs are cut at 255 pixels and, after a cut, the counter
// restarts at 0, so a run of exactly 255*k pixels followed by another colour
// yields an extra (colour, 0) pair. (Like the reference, a last pixel whose
// colour differs from its left neighbour is not encoded; rows written by
// this backend always end in blank columns.)
void encode_row(std::span<const std::uint8_t> row, std::vector<std::uint8_t>& out);

// The 0x600 bytes before the pixel data: header for a width x height raster
// and the swg091n2 palette. Width and height must be in 1..65536.
std::vector<std::uint8_t> file_prefix(int width, int height);

// Whole-file encoding of a raster (header, its palette, rows).
std::vector<std::uint8_t> encode(const Raster& raster);

// Where each raster row's run-length pairs lie in DAT bytes.
struct RunRows {
  int width = 0;
  int height = 0;
  // Row y's (colour, length) pairs are bytes[row_offsets[y], row_offsets[y + 1]);
  // row_offsets[0] is kDataOffset. A zero-length pair right after a full row
  // (see encode_row) stays with that row; row_offsets.back() < bytes.size()
  // when other bytes follow the last row.
  std::vector<std::size_t> row_offsets;
};

// Checks DAT bytes as `decode` does and finds its rows, without drawing
// them: the one reader of the run-length data (`decode` draws the rows it
// finds; devices cut a job into them). Diagnostics and nullopt as for
// `decode`; bytes after the last row are warning D045.
std::optional<RunRows> scan_runs(std::span<const std::uint8_t> bytes, std::string_view source,
                                 knitout::DiagnosticSink& sink);

// Decodes DAT bytes. Problems (too short, bad dimensions, a raster larger
// than kMaxRasterPixels, run-length data that is truncated, odd, or crosses
// a row end) are error diagnostics D040-D047
// against `source` with the byte offset in the message; the result is then
// empty (width 0). Never reads out of bounds, whatever the bytes.
Raster decode(std::span<const std::uint8_t> bytes, std::string_view source,
              knitout::DiagnosticSink& sink);

// The raster size the header declares (width, height), without checking the
// run-length data; nullopt when the bytes are shorter than the header or
// its sizes are reversed. Lets a caller refuse an output it cannot make
// before the raster is decoded.
std::optional<std::pair<int, int>> declared_size(std::span<const std::uint8_t> bytes);

// Reads a whole file into a buffer of its size; a file that cannot be read
// is error D049.
std::vector<std::uint8_t> read_bytes(const std::string& path, knitout::DiagnosticSink& sink,
                                     bool& ok);

}  // namespace dat
