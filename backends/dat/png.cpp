#include "backends/dat/png.hpp"

#include <png.h>

#include <ostream>
#include <stdexcept>
#include <vector>

#include "knitout/output_file.hpp"

namespace dat {

namespace {

void write_to_stream(png_structp png, png_bytep data, png_size_t length) {
  auto* out = static_cast<std::ostream*>(png_get_io_ptr(png));
  out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
}

void flush_stream(png_structp png) {
  static_cast<std::ostream*>(png_get_io_ptr(png))->flush();
}

// libpng reports errors through longjmp by default; turn them into an
// exception at the call site's setjmp instead.
struct PngWriter {
  png_structp png = nullptr;
  png_infop info = nullptr;
  ~PngWriter() { png_destroy_write_struct(&png, info != nullptr ? &info : nullptr); }
};

}  // namespace

std::string png_size_problem(int width, int height, int scale) {
  if (scale < 1 || scale > 64) return "PNG scale must be 1..64, not " + std::to_string(scale);
  if (width <= 0 || height <= 0) return "empty raster";
  const long long png_width = static_cast<long long>(width) * scale;
  const long long png_height = static_cast<long long>(height) * scale;
  if (png_width > kMaxPngSide || png_height > kMaxPngSide) {
    return "a " + std::to_string(png_width) + " x " + std::to_string(png_height) +
           " picture is too large (at most " + std::to_string(kMaxPngSide) + " pixels a side)" +
           (scale > 1 ? "; use a smaller --scale" : "");
  }
  return {};
}

std::string write_png(std::ostream& out, const Raster& raster, int scale) {
  if (std::string problem = png_size_problem(raster.width, raster.height, scale);
      !problem.empty()) {
    return problem;
  }
  const long long png_width = static_cast<long long>(raster.width) * scale;
  const long long png_height = static_cast<long long>(raster.height) * scale;
  PngWriter writer;
  writer.png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (writer.png == nullptr) return "libpng: cannot create writer";
  writer.info = png_create_info_struct(writer.png);
  if (writer.info == nullptr) return "libpng: cannot create info";

  std::vector<png_color> palette(256);
  for (std::size_t i = 0; i < 256; ++i) {
    palette[i].red = raster.palette[i];
    palette[i].green = raster.palette[256 + i];
    palette[i].blue = raster.palette[512 + i];
  }
  std::vector<png_byte> line(static_cast<std::size_t>(png_width));
  // Nothing below allocates C++ objects whose destructors a longjmp could skip
  // (the vectors above live outside the jump).
  if (setjmp(png_jmpbuf(writer.png))) return "libpng: failed to write the picture";
  png_set_write_fn(writer.png, &out, write_to_stream, flush_stream);
  png_set_IHDR(writer.png, writer.info, static_cast<png_uint_32>(png_width),
               static_cast<png_uint_32>(png_height), 8, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_set_PLTE(writer.png, writer.info, palette.data(), 256);
  png_write_info(writer.png, writer.info);
  // KnitPaint draws the first row at the bottom: write rows top-down from
  // the last one.
  for (int y = raster.height - 1; y >= 0; --y) {
    for (int x = 0; x < raster.width; ++x) {
      const png_byte colour = raster.at(x, y);
      for (int k = 0; k < scale; ++k) line[static_cast<std::size_t>(x * scale + k)] = colour;
    }
    for (int k = 0; k < scale; ++k) png_write_row(writer.png, line.data());
  }
  png_write_end(writer.png, nullptr);
  return out ? std::string() : "cannot write the picture";
}

std::string write_png_file(const std::string& path, const Raster& raster, int scale) {
  std::string problem;
  const std::string failure = knitout::write_file_atomically(path, [&](std::ostream& out) {
    problem = write_png(out, raster, scale);
    if (!problem.empty()) throw std::runtime_error(problem);
  });
  if (!problem.empty()) return problem;
  return failure;
}

}  // namespace dat
