#include "backends/dat/format.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>

namespace dat {

namespace {

void put_u16(std::vector<std::uint8_t>& bytes, std::size_t offset, unsigned value) {
  bytes[offset] = static_cast<std::uint8_t>(value & 0xFF);
  bytes[offset + 1] = static_cast<std::uint8_t>((value >> 8) & 0xFF);
}

unsigned get_u16(std::span<const std::uint8_t> bytes, std::size_t offset) {
  return static_cast<unsigned>(bytes[offset]) | (static_cast<unsigned>(bytes[offset + 1]) << 8);
}

}  // namespace

void encode_row(std::span<const std::uint8_t> row, std::vector<std::uint8_t>& out) {
  if (row.empty()) return;
  // The run counter counts pixels equal to `colour` seen so far in the run;
  // a pair is emitted when the colour changes, when the counter reaches 255,
  // and at the row's last pixel. After 255 the counter restarts at 0 (not at
  // 1), which is what makes the reference emit (colour, 0) pairs.
  std::uint8_t colour = row[0];
  int length = 0;
  const std::size_t width = row.size();
  for (std::size_t x = 0; x < width; ++x) {
    const std::uint8_t next = row[x];
    if (next == colour) ++length;
    if (next != colour || length == kMaxRunLength || x + 1 == width) {
      out.push_back(colour);
      out.push_back(static_cast<std::uint8_t>(length));
      colour = next;
      length = length == kMaxRunLength ? 0 : 1;
    }
  }
}

std::vector<std::uint8_t> file_prefix(int width, int height) {
  std::vector<std::uint8_t> bytes(kDataOffset, 0);
  put_u16(bytes, 0, 0);
  put_u16(bytes, 2, 0);
  put_u16(bytes, 4, static_cast<unsigned>(width - 1));
  put_u16(bytes, 6, static_cast<unsigned>(height - 1));
  put_u16(bytes, 8, kHeaderMagic);
  put_u16(bytes, 16, kHeaderMagic);
  std::copy(kPalette.begin(), kPalette.end(), bytes.begin() + kPaletteOffset);
  return bytes;
}

std::vector<std::uint8_t> encode(const Raster& raster) {
  std::vector<std::uint8_t> bytes = file_prefix(raster.width, raster.height);
  std::copy(raster.palette.begin(), raster.palette.end(), bytes.begin() + kPaletteOffset);
  const auto width = static_cast<std::size_t>(raster.width);
  for (int y = 0; y < raster.height; ++y) {
    encode_row(std::span(raster.pixels).subspan(static_cast<std::size_t>(y) * width, width), bytes);
  }
  return bytes;
}

std::optional<RunRows> scan_runs(std::span<const std::uint8_t> bytes, std::string_view source,
                                 knitout::DiagnosticSink& sink) {
  auto fail = [&](std::string_view code, std::string message) {
    sink.error(source, 0, 0, code, std::move(message));
    return std::nullopt;
  };
  if (bytes.size() < kDataOffset) {
    return fail("D040", "truncated DAT: " + std::to_string(bytes.size()) +
                            " bytes, but header and palette alone take " +
                            std::to_string(kDataOffset));
  }
  const unsigned x_min = get_u16(bytes, 0);
  const unsigned y_min = get_u16(bytes, 2);
  const unsigned x_max = get_u16(bytes, 4);
  const unsigned y_max = get_u16(bytes, 6);
  if (x_max < x_min || y_max < y_min) {
    return fail("D041", "bad DAT header: x " + std::to_string(x_min) + ".." +
                            std::to_string(x_max) + ", y " + std::to_string(y_min) + ".." +
                            std::to_string(y_max) + " is an empty raster");
  }
  RunRows rows;
  rows.width = static_cast<int>(x_max - x_min + 1);
  rows.height = static_cast<int>(y_max - y_min + 1);
  const std::span<const std::uint8_t> data = bytes.subspan(kDataOffset);
  if (data.size() % 2 != 0) {
    return fail("D043", "truncated DAT: run-length data has an odd number of bytes (" +
                            std::to_string(data.size()) + "), the last pair is cut");
  }
  const std::uint64_t pixels =
      static_cast<std::uint64_t>(rows.width) * static_cast<std::uint64_t>(rows.height);
  if (pixels > kMaxRasterPixels) {
    return fail("D047", "DAT raster too large: the header declares " + std::to_string(rows.width) +
                            " x " + std::to_string(rows.height) + " pixels, more than the " +
                            std::to_string(kMaxRasterPixels) +
                            " this reader takes (no machine bed needs them)");
  }
  // Each pair covers at most 255 pixels: a raster the data cannot fill is
  // rejected before anything is allocated for it.
  const std::size_t pairs = data.size() / 2;
  const std::uint64_t coverable = static_cast<std::uint64_t>(pairs) * kMaxRunLength;
  if (pixels > coverable) {
    return fail("D043", "truncated DAT: " + std::to_string(pairs) +
                            " run-length pairs cannot fill a " + std::to_string(rows.width) +
                            " x " + std::to_string(rows.height) + " raster");
  }
  rows.row_offsets.reserve(static_cast<std::size_t>(rows.height) + 1);
  rows.row_offsets.push_back(kDataOffset);
  std::uint64_t at = 0;  // next pixel
  const auto width = static_cast<std::uint64_t>(rows.width);
  std::size_t pair = 0;
  for (; pair < pairs && at < pixels; ++pair) {
    const std::uint8_t colour = data[2 * pair];
    const std::size_t length = data[2 * pair + 1];
    const std::uint64_t row_end = (at / width + 1) * width;
    if (at + length > row_end) {
      return fail("D044", "corrupt DAT: the run at byte " + std::to_string(kDataOffset + 2 * pair) +
                              " (" + std::to_string(length) + " pixels of colour " +
                              std::to_string(colour) + ") crosses the end of row " +
                              std::to_string(at / width));
    }
    at += length;
    if (at == row_end) {
      // Zero-length pairs are part of the format (see encode_row): those
      // right after a row end it.
      while (pair + 1 < pairs && data[2 * (pair + 1) + 1] == 0) ++pair;
      rows.row_offsets.push_back(kDataOffset + 2 * (pair + 1));
    }
  }
  if (at < pixels) {
    return fail("D043", "truncated DAT: the data ends in row " + std::to_string(at / width) +
                            " of " + std::to_string(rows.height) + " (" +
                            std::to_string(pixels - at) + " pixels missing)");
  }
  if (pair < pairs) {
    sink.warning(source, 0, 0, "D045",
                 "DAT has " + std::to_string(data.size() - 2 * pair) +
                     " bytes after the last row (from byte " +
                     std::to_string(kDataOffset + 2 * pair) + "); they are ignored");
  }
  return rows;
}

Raster decode(std::span<const std::uint8_t> bytes, std::string_view source,
              knitout::DiagnosticSink& sink) {
  const std::optional<RunRows> rows = scan_runs(bytes, source, sink);
  if (!rows) return Raster{};
  Raster raster;
  raster.width = rows->width;
  raster.height = rows->height;
  std::copy(bytes.begin() + kPaletteOffset, bytes.begin() + kPaletteOffset + kPaletteBytes,
            raster.palette.begin());
  raster.pixels.reserve(static_cast<std::size_t>(raster.width) *
                        static_cast<std::size_t>(raster.height));
  for (int y = 0; y < raster.height; ++y) {
    const auto row = static_cast<std::size_t>(y);
    for (std::size_t at = rows->row_offsets[row]; at < rows->row_offsets[row + 1]; at += 2)
      raster.pixels.insert(raster.pixels.end(), bytes[at + 1], bytes[at]);
  }
  return raster;
}

std::optional<std::pair<int, int>> declared_size(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 8) return std::nullopt;
  const unsigned x_min = get_u16(bytes, 0);
  const unsigned y_min = get_u16(bytes, 2);
  const unsigned x_max = get_u16(bytes, 4);
  const unsigned y_max = get_u16(bytes, 6);
  if (x_max < x_min || y_max < y_min) return std::nullopt;
  return std::pair(static_cast<int>(x_max - x_min + 1), static_cast<int>(y_max - y_min + 1));
}

std::vector<std::uint8_t> read_bytes(const std::string& path, knitout::DiagnosticSink& sink,
                                     bool& ok) {
  ok = false;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    sink.error(path, 0, 0, "D049", std::string("cannot open file: ") + std::strerror(errno));
    return {};
  }
  std::vector<std::uint8_t> bytes;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  in.clear();
  in.seekg(0);
  in.clear();
  if (size > 0) {
    // One read into a buffer of the file's size: no growth, no copy.
    bytes.resize(static_cast<std::size_t>(size));
    in.read(reinterpret_cast<char*>(bytes.data()), size);
    if (in.gcount() != size) {
      sink.error(path, 0, 0, "D049", "cannot read file (it changed while being read)");
      return {};
    }
  } else {
    // Not a regular file (a pipe, a device): read to its end.
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  if (in.bad()) {
    sink.error(path, 0, 0, "D049", "cannot read file");
    return {};
  }
  ok = true;
  return bytes;
}

}  // namespace dat
