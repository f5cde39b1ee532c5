// Reading a planner::StitchMesh back from the textiles-lab .smobj text format
// that `wearknit stitch-mesh` writes (planner/stitch_mesh.hpp, write_smobj).
//
// Lines read: `L NAME EDGE...` (face library; an edge is `-l…` course-in,
// `+l…` course-out, `y…`/`+y…`/`-y…` wale), `v X Y Z`, `f V1 V2 …` (1-based,
// `V/VT` allowed), `T K` (1-based library index, one per face, in face
// order). `e`, `vt`, `N`, `U`, `tex` lines and comments are skipped: the
// connections follow from shared vertices. The face type comes from its
// roles (three sides: short row; two course-in: decrease; two course-out:
// increase; else knit). Cut-arc ids are not read (every arc is kNoArc).
//
// Problems are diagnostics (codes S901-S905, docs/diagnostics.md) with the
// source and line; the mesh returned is then incomplete and must not be used.
#pragma once

#include <iosfwd>
#include <string>
#include <string_view>

#include "knitout/diagnostic.hpp"
#include "planner/stitch_mesh.hpp"

namespace planner {

StitchMesh read_smobj(std::istream& in, std::string_view source, knitout::DiagnosticSink& sink);
StitchMesh read_smobj_file(const std::string& path, knitout::DiagnosticSink& sink);

}  // namespace planner
