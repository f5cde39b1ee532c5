// planner::StitchMesh: the stitch mesh of paper §6, the contract between the
// anisotropic stitch meshing stage (§6, produces it) and the flat-sheet
// scheduler (§7, consumes it).
//
// A stitch mesh is a polygon mesh, one face per stitch, in millimetres. Each
// side of each face has a role seen from that face: the course edge the face
// is knit through (its loops come from the row below), the course edge whose
// loops it makes (the row above is knit through them), or a wale edge (a
// side, where the yarn enters or leaves). Only the three face kinds of §6.3
// exist; `check` says which faces break that and why.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "knitout/diagnostic.hpp"

namespace planner {

// The role of one side of a face, seen from that face (§6.2–6.3).
enum class EdgeRole : std::uint8_t {
  CourseIn,   // bottom course edge: loops of the previous row enter the face here
  CourseOut,  // top course edge: the face's new loops leave here
  Wale,       // side edge: the yarn passes here between faces of one row
};

// The only faces a machine can knit (§6.3). Sides are listed counter-clockwise
// seen from the front (the technical face) of the knit.
enum class FaceType : std::uint8_t {
  Knit,      // quad: CourseIn, Wale, CourseOut, Wale (two disconnected wale edges)
  Increase,  // pentagon: one CourseIn, two CourseOut, two disconnected wale edges
  Decrease,  // pentagon: two CourseIn, one CourseOut, two disconnected wale edges
  ShortRow,  // triangle: one CourseIn, one CourseOut, one Wale (a short row's end)
};

std::string_view face_type_name(FaceType type);  // "knit", "increase", "decrease", "short-row"

inline constexpr std::int32_t kNoArc = -1;

struct StitchFace {
  std::vector<std::uint32_t> vertices;  // counter-clockwise seen from the front
  std::vector<EdgeRole> roles;          // roles[i]: the side vertices[i] -> vertices[i+1]
  // arcs[i]: for a side on the mesh boundary that lies on a cut-arc, the arc's
  // index in cuts.json (so seams can be numbered for assembly); else kNoArc.
  std::vector<std::int32_t> arcs;
  FaceType type = FaceType::Knit;
};

struct StitchMesh {
  std::vector<Eigen::Vector3d> positions;  // mm
  std::vector<StitchFace> faces;
  double course_mm = 0;  // target course (loop width) edge length
  double wale_mm = 0;    // target wale (row height) edge length
};

// Problems with the §6.3 invariants, one line each naming the face (0-based)
// and side: a face whose roles do not make one of the four types, a type that
// disagrees with the roles, a side shared by two faces with roles that do not
// match (a CourseOut must meet a CourseIn, a Wale a Wale), a vertex index out
// of range, or parallel arrays of different lengths. Empty when valid.
std::vector<std::string> check(const StitchMesh& mesh);

// The face type that side roles (read cyclically) make, or nullopt when they
// make none of the four. `first`, if given, receives the side a writer starts
// the face at: its bottom-left course-in side.
std::optional<FaceType> classify_roles(const std::vector<EdgeRole>& roles,
                                       std::size_t* first = nullptr);

// The textiles-lab .smobj text format: a face library (knit, increase,
// decrease, short-row with their edge types: `l` loop (course) edges with
// direction - in / + out, `y` yarn (wale) edges), vertices, faces, types, and
// the `e` connections between faces. Arcs are kept in `# arc` comment lines
// that other readers ignore.
// Each face is written from its bottom-left course-in side (so vertex order
// may be rotated relative to `mesh`); course_mm and wale_mm go in a
// `# wearknit` comment line. A mesh that fails `check` is a programming error
// (std::logic_error).
void write_smobj(std::ostream& out, const StitchMesh& mesh);

// Reads what write_smobj writes, cut-arcs included (and any .smobj whose library uses the face
// names knit, increase, decrease, short-row with -lN/+lN/yN edges). Problems
// are diagnostics naming the line: P081 malformed line, P082 unknown face or
// edge type in the library, P083 faces and types that disagree, P084 a mesh
// that fails `check`. Returns nullopt when there was any error.
std::optional<StitchMesh> parse_smobj(std::istream& in, const std::string& source,
                                      knitout::DiagnosticSink& sink);

}  // namespace planner
