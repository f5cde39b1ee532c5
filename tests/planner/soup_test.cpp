#include "planner/mesh/soup.hpp"

#include <gtest/gtest.h>

#include "tests/planner/test_meshes.hpp"

namespace planner {
namespace {

// Two triangles that touch only at vertex 0: a pinch point.
PolygonMesh bowtie() {
  PolygonMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(-1, 0, 0), Vec3(-1, -1, 0)};
  mesh.faces = {{0, 1, 2}, {0, 3, 4}};
  return mesh;
}

TEST(SoupTest, PairKeysAreDistinctAndDirected) {
  EXPECT_NE(pair_key(1, 2), pair_key(2, 1));
  EXPECT_NE(pair_key(-1, 0), pair_key(0, -1));
  EXPECT_EQ(pair_key(3, 4), pair_key(3, 4));
  EXPECT_EQ(undirected_edge(5, 2), std::make_pair(2, 5));
  EXPECT_EQ(undirected_edge(2, 5), std::make_pair(2, 5));
}

TEST(SoupTest, CornerStartsCountTheCornersOfEachFace) {
  PolygonMesh mesh = test_meshes::grid(2, 1);
  mesh.faces.push_back({0, 1, 4});
  EXPECT_EQ(corner_starts(mesh), (std::vector<int>{0, 4, 8, 11}));
}

TEST(SoupTest, CornersAroundAnInteriorVertexFormOneFan) {
  const PolygonMesh mesh = test_meshes::grid(2, 2);  // vertex 4 is the centre
  const std::vector<int> start = corner_starts(mesh);
  UnionFind fans = corner_fans(mesh, start);
  std::vector<int> roots;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (std::size_t i = 0; i < mesh.faces[f].size(); ++i) {
      if (mesh.faces[f][i] == 4) roots.push_back(fans.find(start[f] + static_cast<int>(i)));
    }
  }
  ASSERT_EQ(roots.size(), 4u);
  for (int root : roots) EXPECT_EQ(root, roots.front());
}

TEST(SoupTest, APinchedVertexHasTwoFans) {
  const PolygonMesh mesh = bowtie();
  const std::vector<int> start = corner_starts(mesh);
  UnionFind fans = corner_fans(mesh, start);
  EXPECT_NE(fans.find(start[0]), fans.find(start[1]));
}

TEST(SoupTest, UnusableFacesJoinNothing) {
  PolygonMesh mesh = test_meshes::grid(2, 1);
  UnionFind all = vertex_components(mesh);
  EXPECT_EQ(all.find(0), all.find(2));
  UnionFind first_only = vertex_components(mesh, {true, false});
  EXPECT_EQ(first_only.find(0), first_only.find(4));
  EXPECT_NE(first_only.find(0), first_only.find(2));
}

TEST(SoupTest, UnusedVerticesAreDroppedInOrderOfFirstUse) {
  PolygonMesh mesh;
  mesh.positions = {Vec3(9, 9, 9), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  mesh.faces = {{3, 1, 2}};
  drop_unused_vertices(mesh);
  EXPECT_EQ(mesh.faces, (std::vector<std::vector<int>>{{0, 1, 2}}));
  ASSERT_EQ(mesh.positions.size(), 3u);
  EXPECT_EQ(mesh.positions[0], Vec3(0, 1, 0));
  EXPECT_EQ(mesh.positions[1], Vec3(0, 0, 0));
}

TEST(SoupTest, MeanEdgeLengthAndVectorAreaOfAUnitSquare) {
  const PolygonMesh mesh = test_meshes::grid(1, 1);
  EXPECT_DOUBLE_EQ(mean_edge_length(mesh), 1.0);
  EXPECT_EQ(vector_area(mesh, mesh.faces[0]), Vec3(0, 0, 1));
  EXPECT_EQ(mean_edge_length(PolygonMesh{}), 0.0);
}

}  // namespace
}  // namespace planner
