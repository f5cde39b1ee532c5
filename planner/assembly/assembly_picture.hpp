// The assembly guide's 3D picture (internal to planner/assembly/).
#pragma once

#include <optional>
#include <string>

#include "planner/assembly/assembly_model.hpp"
#include "planner/mesh/mesh.hpp"

namespace planner::assembly {

// assembly-3d.png: the garment (the stitch mesh) on its wearer (none when
// `wearer` is empty) from four sides, seams coloured sew / lace. Returns ""
// or the failure (A006).
std::string draw_assembly_3d(const Model& m, const std::optional<PolygonMesh>& wearer,
                             const std::string& png_path);

}  // namespace planner::assembly
