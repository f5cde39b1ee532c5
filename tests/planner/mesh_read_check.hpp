// The properties the mesh reader fuzzer checks on every input, shared with
// the replay test (mesh_fuzz_replay_test.cpp). The first byte picks the
// format (its value mod 4: OBJ, OFF, PLY, STL), the rest is the file.
// Reading it as `wearknit cut` does (read_polygon_soup, then check_mesh)
// never crashes, reads out of bounds or allocates beyond the input's size;
// every diagnostic has a mesh code (P001-P015) and a message; a soup that
// check_mesh accepts has only finite coordinates and faces of at least 3
// distinct corners that all name one of its vertices. Returns "" or what
// went wrong.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <sstream>
#include <string>
#include <string_view>

#include "planner/mesh/mesh_io.hpp"

namespace planner::mesh_fuzz {

inline std::string check_read(std::span<const std::uint8_t> data) {
  if (data.empty()) return "";
  static constexpr std::string_view kFormats[] = {"obj", "off", "ply", "stl"};
  const std::string_view ext = kFormats[data[0] % 4];
  const std::string bytes(reinterpret_cast<const char*>(data.data()) + 1, data.size() - 1);
  knitout::DiagnosticSink sink;
  std::istringstream in(bytes);
  const std::string source = "fuzz." + std::string(ext);
  auto mesh = read_polygon_soup(in, ext, source, sink);
  bool accepted = false;
  if (mesh) {
    // Content-bounded: OpenMesh makes at most one vertex and one face per
    // few bytes (binary STL: 3 corners per 50 bytes).
    if (mesh->positions.size() > bytes.size() + 3 || mesh->faces.size() > bytes.size() + 1) {
      return "more elements than the input has bytes";
    }
    accepted = check_mesh(*mesh, source, sink);
  }
  for (const knitout::Diagnostic& d : sink.diagnostics()) {
    if (d.message.empty()) return "a diagnostic without a message";
    if (d.code.size() != 4 || d.code.substr(0, 2) != "P0" || d.code > "P015") {
      return "a diagnostic with the code '" + d.code + "'";
    }
  }
  if (!mesh && !sink.has_errors()) return "no mesh and no error";
  if (!accepted) return "";
  const int nv = static_cast<int>(mesh->positions.size());
  for (const Vec3& p : mesh->positions) {
    if (!p.allFinite()) return "an accepted mesh with a coordinate that is not finite";
  }
  for (const auto& face : mesh->faces) {
    if (face.size() < 3) return "an accepted face of fewer than 3 corners";
    for (int v : face) {
      if (v < 0 || v >= nv) return "an accepted face corner that names no vertex";
    }
  }
  return "";
}

}  // namespace planner::mesh_fuzz
