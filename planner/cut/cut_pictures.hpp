// Pictures of the cut stage, as in Fig. 5: the cuts drawn on Q from four
// views, and the approximate 2D layout (faces at their integer parametric
// positions, overlaps darker). PNG files, written atomically.
#pragma once

#include <string>

#include "planner/cut/cut.hpp"

namespace planner {

// Four orthographic views (front, right, back, left, each from 20 degrees
// above) in a 2x2 grid of `panel_px` square panels. Cut edges red, mesh
// boundary blue. Returns an empty string or the failure.
std::string draw_cuts_3d(const CutMesh& cut, const std::string& png_path, int panel_px = 600);

// The patch in its parametric space: a unit square per face at (u, v),
// grey darker with every extra face in the same cell; cut sides red,
// mesh-boundary sides blue.
std::string draw_layout_2d(const CutMesh& cut, const std::string& png_path, int size_px = 1000);

}  // namespace planner
