// Reading garment meshes (OBJ, OFF, PLY, STL through OpenMesh), checking
// that they are surfaces the planner can cut, and writing OBJ.
//
// Every problem a user can fix is a diagnostic naming the element: vertices
// and faces are numbered from 1 in file order, as OBJ numbers them.
// Codes (docs/diagnostics.md): P001 cannot read, P002 no faces, P003 bad
// coordinate, P004 malformed element, P005 corner naming no vertex, P006
// header claiming more than the file holds (P003-P006 from the scan before
// reading, mesh_scan.hpp, with lines), P010 degenerate face, P011 non-manifold edge, P012
// inconsistent orientation, P013 non-manifold vertex, P014 several
// components, P015 unreferenced vertex.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>

#include "knitout/diagnostic.hpp"
#include "planner/mesh/mesh.hpp"

namespace planner {

// How file coordinates become millimetres: mm = coordinate * mm_per_unit * scale.
struct LoadParams {
  double mm_per_unit = 1.0;  // --units: mm 1, cm 10, m 1000
  double scale = 1.0;        // --scale
};

// "mm", "cm", "m" -> millimetres per unit; nullopt for anything else.
std::optional<double> mm_per_unit(std::string_view units);

// Reads the polygon soup of `path` (format from the extension) with no
// checks. Reports P001 and returns nullopt when the file cannot be read.
std::optional<PolygonMesh> read_polygon_soup(const std::string& path,
                                             knitout::DiagnosticSink& sink);
// Same from a stream; `extension` is "obj", "off", "ply" or "stl".
std::optional<PolygonMesh> read_polygon_soup(std::istream& in, std::string_view extension,
                                             const std::string& source,
                                             knitout::DiagnosticSink& sink);

// Reports every reason the soup is not one connected, consistently oriented
// 2-manifold surface with boundary (at most 10 messages per kind, then a
// count). Returns true when there is none.
bool check_mesh(const PolygonMesh& mesh, const std::string& source, knitout::DiagnosticSink& sink);

// read_polygon_soup + check_mesh + unit conversion to millimetres.
std::optional<PolygonMesh> load_mesh(const std::string& path, const LoadParams& params,
                                     knitout::DiagnosticSink& sink);

// Plain OBJ: `# header` lines, v lines with %.9g, f lines (1-based).
void write_obj(std::ostream& out, const PolygonMesh& mesh, std::string_view header = {});

// Axis-aligned bounding box extent (max - min), zero for an empty mesh.
Vec3 bounding_box_size(const PolygonMesh& mesh);

}  // namespace planner
