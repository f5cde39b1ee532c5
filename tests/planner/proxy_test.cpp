#include "planner/proxy.hpp"

#include <gtest/gtest.h>

#include "planner/mesh_io.hpp"
#include "tests/planner/test_meshes.hpp"

namespace planner {
namespace {

TEST(ProxyTest, QuadDominantMeansMoreThanHalfQuads) {
  PolygonMesh mesh = test_meshes::grid(2, 1);
  EXPECT_TRUE(is_quad_dominant(mesh));
  mesh.positions.emplace_back(3, 0, 0);
  mesh.faces.push_back({2, 6, 5});
  mesh.positions.emplace_back(3, 1, 0);
  mesh.faces.push_back({6, 7, 5});
  EXPECT_FALSE(is_quad_dominant(mesh));  // 2 quads, 2 triangles
}

TEST(ProxyTest, PentagonIsSplitThroughItsLargestCorner) {
  // A lopsided house: corners 90, 90, 129.8 (vertex 2), 88.9 (roof top,
  // vertex 3) and 141.3 degrees (vertex 4, the largest). Of the two
  // diagonals from vertex 4, 4-2 halves its corner best (51.3 / 90 degrees
  // against 45 / 96.3 for 4-1): a quad 4-0-1-2 and a triangle 4-2-3.
  PolygonMesh mesh;
  mesh.positions = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0.8, 3, 0}, {0, 2, 0}};
  mesh.faces = {{0, 1, 2, 3, 4}};
  EXPECT_EQ(split_polygons(mesh), 1);
  ASSERT_EQ(mesh.faces.size(), 2u);
  EXPECT_EQ(mesh.faces[0], (std::vector<int>{4, 0, 1, 2}));
  EXPECT_EQ(mesh.faces[1], (std::vector<int>{4, 2, 3}));
}

TEST(ProxyTest, QuadsAndTrianglesAreNotSplit) {
  PolygonMesh mesh = test_meshes::grid(2, 2);
  const auto before = mesh.faces;
  EXPECT_EQ(split_polygons(mesh), 0);
  EXPECT_EQ(mesh.faces, before);
}

TEST(ProxyTest, HexagonBecomesTwoQuadsAndHeptagonQuadPlusPentagonSplit) {
  PolygonMesh hexagon;
  const double pi = std::acos(-1.0);
  for (int i = 0; i < 6; ++i)
    hexagon.positions.emplace_back(std::cos(pi * i / 3), std::sin(pi * i / 3), 0);
  hexagon.faces = {{0, 1, 2, 3, 4, 5}};
  split_polygons(hexagon);
  ASSERT_EQ(hexagon.faces.size(), 2u);
  EXPECT_EQ(hexagon.faces[0].size(), 4u);
  EXPECT_EQ(hexagon.faces[1].size(), 4u);

  PolygonMesh heptagon;
  for (int i = 0; i < 7; ++i)
    heptagon.positions.emplace_back(std::cos(2 * pi * i / 7), std::sin(2 * pi * i / 7), 0);
  heptagon.faces = {{0, 1, 2, 3, 4, 5, 6}};
  split_polygons(heptagon);
  ASSERT_EQ(heptagon.faces.size(), 3u);  // quad + (pentagon -> quad + triangle)
  int quads = 0, triangles = 0;
  for (const auto& f : heptagon.faces) (f.size() == 4 ? quads : triangles) += 1;
  EXPECT_EQ(quads, 2);
  EXPECT_EQ(triangles, 1);
}

TEST(ProxyTest, QuadDominantInputIsKept) {
  const PolygonMesh mesh = test_meshes::torus(8, 6);
  const ProxyResult proxy = make_proxy(mesh, {});
  EXPECT_FALSE(proxy.remeshed);
  EXPECT_EQ(proxy.mesh.faces, mesh.faces);
}

TEST(ProxyTest, TriangleInputIsRemeshedIntoQuadDominantSurfaceOfSameTopology) {
  // Triangulate a fine torus, then ask for a coarser proxy.
  PolygonMesh tri = test_meshes::torus(40, 20);
  std::vector<std::vector<int>> faces;
  for (const auto& f : tri.faces) {
    faces.push_back({f[0], f[1], f[2]});
    faces.push_back({f[0], f[2], f[3]});
  }
  tri.faces = faces;
  ProxyParams params;
  params.proxy_edge_mm = 0.6;
  const ProxyResult proxy = make_proxy(tri, params);
  EXPECT_TRUE(proxy.remeshed);
  EXPECT_TRUE(is_quad_dominant(proxy.mesh));
  EXPECT_LT(proxy.mesh.faces.size(), tri.faces.size() / 2);
  knitout::DiagnosticSink sink;
  EXPECT_TRUE(check_mesh(proxy.mesh, "proxy", sink));
  const HalfedgeMesh he(proxy.mesh);
  EXPECT_EQ(he.euler_characteristic(), 0);  // still a torus
  EXPECT_EQ(he.count_boundary_loops(), 0);
}

}  // namespace
}  // namespace planner
