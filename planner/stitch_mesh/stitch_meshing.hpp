// Internals of the stitch mesher (stitch_mesher.hpp has the method and the
// public interface): what its steps share. Only planner/stitch_mesh/ includes
// this header.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "planner/common/index.hpp"
#include "planner/stitch_mesh/stitch_mesher.hpp"
#include "simulators/cloth/sdf.hpp"

namespace planner::stitch_meshing {

// ---------------------------------------------------------------------------
// Geometry helpers (geometry.cpp).

// The directed vertex pair a -> b as one key.
inline std::uint64_t key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

// Twice the vector area of a disc face (Newell), not normalised.
Vec3 face_normal(const LabelledDisc& disc, const std::vector<int>& face);

// The disc as triangles (fans of its faces), for exact distances and
// nearest points.
cloth::TriangleMeshQuery disc_surface(const LabelledDisc& disc);

// A side is the right length when it is within this fraction of its target
// (StitchMeshFigures::within_15_percent; the shared-mesh test asks 90% of
// course and of wale sides to be).
constexpr double kLengthTolerance = 0.15;

// The cost of a side whose length is off its target by the fraction `off`:
// its square, and `outside` more if it is over kLengthTolerance.
double length_cost(double off, double outside);

}  // namespace planner::stitch_meshing
