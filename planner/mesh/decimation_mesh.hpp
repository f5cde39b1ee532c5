// The triangle mesh the planner runs OpenMesh's decimater and edge splits
// on (the remesher's sampling, the wearability stage's coarse cloth):
// double points and normals, and the status attributes a decimater needs.
#pragma once

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace planner {

struct DecimationTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
  HalfedgeAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::PrevHalfedge);
};
using DecimationMesh = OpenMesh::TriMesh_ArrayKernelT<DecimationTraits>;

}  // namespace planner
