// The project's one polygon-mesh type: positions and faces, nothing implied.
//
// It lives at the lowest layer that needs it (the cloth simulation's
// garment); the planner names it planner::PolygonMesh and builds its own
// kinds of mesh on it (planner/mesh/mesh.hpp): a surface read from a file,
// the garment with its cut-arcs (planner::CoverMesh), the labelled disc
// (planner::LabelledDisc), with HalfedgeMesh for the walks.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace cloth {

// Faces are lists of 0-based indices into `positions`, counter-clockwise
// seen from outside (or from the front of a sheet). No connectivity is
// implied: a mesh read from a file is checked before it is used as a surface.
struct PolygonMesh {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::vector<int>> faces;
};

}  // namespace cloth
