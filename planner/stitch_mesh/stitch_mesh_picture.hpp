// The stitch-mesh stage's picture (stitch-mesh.png).
#pragma once

#include <string>

#include "planner/stitch_mesh/stitch_mesh.hpp"

namespace planner {

// A picture of the stitch mesh from four sides, faces coloured by type
// (knit grey, increase green, decrease blue, short row orange; no text, so no
// font library is needed), course edges darker than wale edges, the boundary red. Returns an empty
// string or what went wrong.
std::string draw_stitch_mesh(const StitchMesh& mesh, const std::string& png_path,
                             int panel_px = 600);

}  // namespace planner
