// A mesh file checked before OpenMesh reads it. OpenMesh's readers trust a
// file: an OFF or PLY header that claims a billion vertices makes them
// allocate and loop for that many, a coordinate of `nan` in an OBJ drops the
// vertex and shifts every later index, and a face corner naming a vertex
// the file lacks arrives as a silent bad index. The scan reads the bytes
// once, as the formats define them, and names each such fault with its line
// (or its triangle, in binary STL):
//
//   P003  a coordinate that is not a finite number (nan, inf, 1e999)
//   P004  a malformed element: a vertex without three numbers, a face
//         corner that is not an integer, a header that does not parse
//   P005  a face corner naming a vertex the file does not have (0 in OBJ,
//         which numbers from 1; past the last vertex; negative in OFF)
//   P006  a header claiming more elements than the file's size can hold,
//         or a file that ends before the elements its header claims
//   P010  a face of fewer than 3 corners
//
// Memory and time stay bounded by the file's real size: counts are checked
// against it before anything is allocated.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "knitout/diagnostic.hpp"
#include "planner/mesh/mesh.hpp"

namespace planner {

struct ScanResult {
  bool ok = false;  // nothing wrong found
  // The polygon soup, where the scan read it whole: ASCII OFF, which
  // OpenMesh's reader misreads (counts on the OFF line, comments between
  // the elements). Otherwise OpenMesh reads the file.
  std::optional<PolygonMesh> soup;
};

// Checks `bytes`, the whole content of a mesh file in format `ext` ("obj",
// "off", "ply" or "stl", lower case). Reports at most 10 messages of each
// code, then a count. Formats the scan does not look inside (binary OFF,
// 4-dimensional OFF, the body of PLY) are checked for their counts only.
ScanResult scan_mesh_bytes(std::string_view bytes, std::string_view ext, const std::string& source,
                           knitout::DiagnosticSink& sink);

}  // namespace planner
