// Shapes the planner builds itself, for `wearknit demo` and for tests that
// need a surface without a data file.
#pragma once

#include "planner/mesh/mesh.hpp"

namespace planner {

// An all-quad ellipsoid: a cube whose faces are split into n x n quads,
// projected onto the sphere of `radius` and stretched by `z_stretch` along
// z. Eight valence-3 vertices (the cube's corners); faces counter-clockwise
// seen from outside.
PolygonMesh quad_ellipsoid(double radius, double z_stretch, int n);

}  // namespace planner
