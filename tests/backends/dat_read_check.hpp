// The properties the DAT reader fuzzer checks on every input, shared with the
// replay test (dat_fuzz_replay_test.cpp): reading bytes as `wearknit dat-info
// --passes` does (decode, read_layout, the passes' carriers and colours)
// never crashes or reads out of bounds; a decode with errors gives an empty
// raster and one without a raster of width x height pixels; every error has
// a code and a message; the passes of a layout lie inside the raster, their
// operations inside the needle slots, left to right. Returns "" or what went
// wrong.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "backends/dat/format.hpp"
#include "backends/dat/reader.hpp"

namespace dat {

inline std::string check_read(std::span<const std::uint8_t> bytes) {
  knitout::DiagnosticSink sink;
  const Raster raster = decode(bytes, "fuzz.dat", sink);
  for (const knitout::Diagnostic& d : sink.diagnostics()) {
    if (d.code.empty() || d.message.empty()) return "a diagnostic without a code or a message";
  }
  if (sink.has_errors()) {
    if (raster.width != 0 || !raster.pixels.empty()) return "a raster despite errors";
    return "";
  }
  if (raster.width < 1 || raster.height < 1) return "an empty raster without an error";
  if (raster.pixels.size() !=
      static_cast<std::size_t>(raster.width) * static_cast<std::size_t>(raster.height)) {
    return "the raster's pixels are not width x height";
  }
  knitout::DiagnosticSink layout_sink;
  const auto layout = read_layout(raster, "fuzz.dat", layout_sink);
  if (!layout) {
    if (!layout_sink.has_errors()) return "no layout and no error";
    return "";
  }
  if (layout->slots < 1 || layout->slots > raster.width) return "needle slots outside the raster";
  for (const DecodedPass& pass : layout->passes) {
    if (pass.row < 0 || pass.row >= raster.height) return "a pass row outside the raster";
    if (carrier_code_text(pass.carriers()).empty()) return "carriers without a text";
    int column = -1;
    for (const auto& [slot, colour] : pass.ops) {
      if (slot <= column || slot >= layout->slots) return "operations out of order or outside";
      column = slot;
      if (colour_name(colour).empty()) return "a colour without a name";
    }
  }
  return "";
}

}  // namespace dat
