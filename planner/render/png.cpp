#include "planner/render/png.hpp"

#include <ostream>
#include <stdexcept>

#include "knitout/output_file.hpp"

namespace planner::render {

namespace {

cairo_status_t write_to_stream(void* closure, const unsigned char* data, unsigned int length) {
  auto* out = static_cast<std::ostream*>(closure);
  out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
  return *out ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

}  // namespace

void write_png(cairo_surface_t* surface, std::ostream& out) {
  cairo_surface_flush(surface);
  if (cairo_surface_write_to_png_stream(surface, write_to_stream, &out) != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error("cairo could not encode the PNG");
}

std::string write_png_file(cairo_surface_t* surface, const std::string& path) {
  return knitout::write_file_atomically(path, [&](std::ostream& out) { write_png(surface, out); });
}

}  // namespace planner::render
