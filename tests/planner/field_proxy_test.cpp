#include "planner/proxy/field_proxy.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "planner/cut/cut.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/shapes.hpp"
#include "planner/proxy/cross_field.hpp"
#include "planner/proxy/proxy.hpp"
#include "tests/planner/test_meshes.hpp"

namespace planner {
namespace {

// Every quad split into two triangles along the diagonal from its first corner.
PolygonMesh triangulated(const PolygonMesh& quads) {
  PolygonMesh mesh;
  mesh.positions = quads.positions;
  for (const auto& f : quads.faces) {
    mesh.faces.push_back({f[0], f[1], f[2]});
    mesh.faces.push_back({f[0], f[2], f[3]});
  }
  return mesh;
}

// Sum over vertices of (valence - 6)², 4 on the boundary.
int valence_deviation(const PolygonMesh& mesh) {
  const HalfedgeMesh he(mesh);
  int sum = 0;
  for (int v = 0; v < he.num_vertices(); ++v) {
    const int ideal = he.is_boundary_vertex(v) ? 4 : 6;
    const int off = static_cast<int>(he.outgoing(v).size()) - ideal;
    sum += off * off;
  }
  return sum;
}

// The corner counts the vanishing corners leave, as FieldLabels.
FieldLabels labels_of(const PolygonMesh& mesh, const std::vector<int>& corners) {
  return labels_with_vanishing(HalfedgeMesh(mesh), corners);
}

TEST(FieldProxyTest, ValenceFlipsEqualizeAFlatGridAndKeepItAManifold) {
  // A grid whose quads are split along alternating diagonals: interior
  // vertices of valence 4 and 8.
  const PolygonMesh quads = test_meshes::grid(8, 8);
  PolygonMesh mesh;
  mesh.positions = quads.positions;
  for (std::size_t i = 0; i < quads.faces.size(); ++i) {
    const auto& f = quads.faces[i];
    const bool flip = ((i % 8) + (i / 8)) % 2 == 1;
    if (flip) {
      mesh.faces.push_back({f[0], f[1], f[3]});
      mesh.faces.push_back({f[1], f[2], f[3]});
    } else {
      mesh.faces.push_back({f[0], f[1], f[2]});
      mesh.faces.push_back({f[0], f[2], f[3]});
    }
  }
  const int before = valence_deviation(mesh);
  const int flips = equalize_valences(mesh, 30.0, 10.0);
  EXPECT_GT(flips, 0);
  EXPECT_LT(valence_deviation(mesh), before);
  EXPECT_EQ(mesh.faces.size(), 128U);
  knitout::DiagnosticSink sink;
  EXPECT_TRUE(check_mesh(mesh, "flipped", sink));
  for (const auto& f : mesh.faces) {  // still facing +z
    const Vec3 n = (mesh.positions[at(f[1])] - mesh.positions[at(f[0])])
                       .cross(mesh.positions[at(f[2])] - mesh.positions[at(f[0])]);
    EXPECT_GT(n.z(), 0.0);
  }
}

// A right-angled fold: edge p-q (vertices 0 and 1) on the fold line,
// triangle p-q-c flat in z = 0, triangle q-p-d raised in x = 0, and fans
// that give p and q valence 8 while c and d have 3. Flipping p-q to c-d
// evens the valences but bends the new triangles by 109 degrees.
PolygonMesh fold() {
  PolygonMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0.5, 0), Vec3(0, 0.5, 1)};
  auto add = [&](const Vec3& p) {
    mesh.positions.push_back(p);
    return static_cast<int>(mesh.positions.size()) - 1;
  };
  // Each triangle turned to face `normal`.
  auto face = [&](int a, int b, int c, const Vec3& normal) {
    const Vec3 n = (mesh.positions[at(b)] - mesh.positions[at(a)])
                       .cross(mesh.positions[at(c)] - mesh.positions[at(a)]);
    if (n.dot(normal) >= 0) {
      mesh.faces.push_back({a, b, c});
    } else {
      mesh.faces.push_back({a, c, b});
    }
  };
  const Vec3 up = Vec3::UnitZ(), out = -Vec3::UnitX();
  face(0, 1, 2, up);
  face(1, 0, 3, out);
  // Fans: p's below y = 0, q's above y = 1, on both halves.
  for (const int end : {0, 1}) {
    const double sign = end == 0 ? -1.0 : 1.0;
    const double y = end == 0 ? 0.0 : 1.0;
    int previous = 2;
    for (const double a : {0.3, 0.8, 1.3}) {
      const int next = add(Vec3(-std::cos(a), y + sign * std::sin(a), 0));
      face(end, previous, next, up);
      previous = next;
    }
    previous = 3;
    for (const double a : {0.6, 1.2}) {
      const int next = add(Vec3(0, y + sign * std::sin(a), std::cos(a)));
      face(end, previous, next, out);
      previous = next;
    }
  }
  return mesh;
}

// The fold's faces that hold both c and d (the flipped edge).
int faces_across_the_fold(const PolygonMesh& mesh) {
  int across = 0;
  for (const auto& f : mesh.faces) {
    const bool c = std::find(f.begin(), f.end(), 2) != f.end();
    const bool d = std::find(f.begin(), f.end(), 3) != f.end();
    across += c && d ? 1 : 0;
  }
  return across;
}

TEST(FieldProxyTest, NoFlipFoldsTheSurfaceMoreThanTheBendAllows) {
  const PolygonMesh mesh = fold();
  knitout::DiagnosticSink sink;
  ASSERT_TRUE(check_mesh(mesh, "fold", sink));
  PolygonMesh loose = mesh;
  equalize_valences(loose, 180.0, 10.0);
  EXPECT_EQ(faces_across_the_fold(loose), 2);  // allowed any fold, the flip is made
  PolygonMesh strict = mesh;
  equalize_valences(strict, 30.0, 10.0);
  EXPECT_EQ(faces_across_the_fold(strict), 0);
}

TEST(FieldProxyTest, MisalignmentIsNilAlongTheFieldAndOneAtFortyFiveDegrees) {
  PolygonMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  mesh.faces = {{0, 1, 2}};
  // Corner 0 vanishing: the side across and the median both run at 45 degrees.
  EXPECT_NEAR(vanishing_misalignment(mesh, 0, 0, Vec3::UnitX()), 1.0, 1e-9);
  // Corner 1: the side across is along y, the median 26.6 degrees off x.
  EXPECT_LT(vanishing_misalignment(mesh, 0, 1, Vec3::UnitX()), 0.25);
  // Turning the field by 45 degrees swaps the verdicts.
  const Vec3 diagonal = Vec3(1, 1, 0).normalized();
  EXPECT_NEAR(vanishing_misalignment(mesh, 0, 0, diagonal), 0.0, 1e-9);
}

TEST(FieldProxyTest, ATorusGetsNoSingularVertex) {
  // The field on a torus has no singularity, and every vertex of a
  // triangulated torus grid can keep four corners.
  const PolygonMesh mesh = triangulated(test_meshes::torus(24, 12));
  const CrossField field = smoothest_cross_field(mesh, {});
  ASSERT_EQ(field_singularities(field).count, 0);
  const std::vector<int> corners =
      field_vanishing_corners(mesh, field.index, field.direction, FieldProxyParams{});
  const FieldLabels labels = labels_of(mesh, corners);
  EXPECT_TRUE(labels.irregular_vertices.empty());
  EXPECT_TRUE(labels.singular_vertices.empty());
}

TEST(FieldProxyTest, ANearPairTheCostsKeepIsCancelledInFurtherRounds) {
  // A field with a +1 and a -1 one or two edges apart on a torus, and costs
  // that keep them (misfit far above the singular cost): the first flow
  // places both; the rounds against near pairs cancel them rather than
  // move them apart.
  const PolygonMesh mesh = triangulated(test_meshes::torus(24, 12));
  const CrossField field = smoothest_cross_field(mesh, {});
  const HalfedgeMesh q(mesh);
  const int v = 100;
  const int one_edge = q.to(q.outgoing(v).front());
  auto neighbours = [&](int u) {
    std::vector<int> out;
    for (const int h : q.outgoing(u)) out.push_back(q.to(h));
    return out;
  };
  int two_edges = -1;
  for (const int w : neighbours(one_edge)) {
    const auto around_v = neighbours(v);
    if (w != v && std::find(around_v.begin(), around_v.end(), w) == around_v.end()) two_edges = w;
  }
  ASSERT_GE(two_edges, 0);
  for (const int w : {one_edge, two_edges}) {
    SCOPED_TRACE("the -1 at vertex " + std::to_string(w));
    std::vector<int> index(field.index.size(), 0);
    index[at(v)] = 1;
    index[at(w)] = -1;
    FieldProxyParams params;
    params.misfit_cost = 100;
    params.singular_cost = 10;
    params.pair_rounds = 0;
    const FieldLabels kept =
        labels_of(mesh, field_vanishing_corners(mesh, index, field.direction, params));
    ASSERT_EQ(kept.corner_count[at(v)], 3);
    ASSERT_EQ(kept.corner_count[at(w)], 5);
    params.pair_rounds = 4;
    const FieldLabels cancelled =
        labels_of(mesh, field_vanishing_corners(mesh, index, field.direction, params));
    EXPECT_TRUE(cancelled.singular_vertices.empty());
    EXPECT_EQ(adjacent_opposite_pairs(q, cancelled), 0);
  }
}

TEST(FieldProxyTest, TheProxyOfAnEllipsoidCarriesTheFieldsSingularitiesOnly) {
  const PolygonMesh surface = triangulated(quad_ellipsoid(50.0, 0.7, 16));
  FieldProxyParams params;
  params.edge_mm = 6.0;
  const FieldProxy proxy = field_guided_proxy(surface, params);
  knitout::DiagnosticSink sink;
  ASSERT_TRUE(check_mesh(proxy.mesh, "proxy", sink));
  for (const auto& f : proxy.mesh.faces) ASSERT_EQ(f.size(), 3U);
  const HalfedgeMesh q(proxy.mesh);
  const FieldLabels labels = labels_of(proxy.mesh, proxy.vanishing_corner);
  int index_sum = 0;
  for (const int v : labels.irregular_vertices) index_sum += 4 - labels.corner_count[at(v)];
  EXPECT_EQ(index_sum, 8);  // 4χ
  EXPECT_LE(static_cast<double>(labels.singular_vertices.size()),
            1.2 * proxy.field_singularities + 4);
  EXPECT_EQ(adjacent_opposite_pairs(q, labels), 0);
  // And it cuts into one disc with the cut's guarantees.
  const CutMesh cut = cut_surface(q, CutParams{}, &proxy.vanishing_corner);
  EXPECT_TRUE(verify_cut(cut).empty());
  EXPECT_LT(cut.arcs.size(), 20U);
}

// Q is made at the target edge and at each of edge_factors of it, and the
// one with the fewest singular vertices is kept, the first on a tie: the
// very proxy that asking for that edge alone gives.
TEST(FieldProxyTest, OfTheProxiesAtNearbyEdgesTheOneWithFewestSingularVerticesIsKept) {
  // Fine enough that every edge below decimates it, and bumpy, so that the
  // field has singularities that the resampling moves and merges.
  PolygonMesh surface = triangulated(quad_ellipsoid(50.0, 0.7, 24));
  for (Vec3& p : surface.positions) {
    p *= 1.0 + 0.08 * std::sin(0.31 * p.x()) * std::sin(0.27 * p.y()) * std::sin(0.23 * p.z());
  }
  FieldProxyParams params;
  params.edge_mm = 6.0;
  params.edge_factors = {0.9, 1.1, 0.8, 1.2};
  // Alignment before all and no rounds against near pairs: Q keeps pairs,
  // and how many depends on the triangles.
  params.alignment_cost = 200;
  params.pair_rounds = 0;
  const FieldProxy kept = field_guided_proxy(surface, params);
  EXPECT_EQ(kept.candidates, 5);
  std::vector<double> edges{params.edge_mm};
  for (double f : params.edge_factors) edges.push_back(f * params.edge_mm);
  std::vector<FieldProxy> alone;
  for (double edge : edges) {
    FieldProxyParams one = params;
    one.edge_mm = edge;
    one.edge_factors.clear();
    alone.push_back(field_guided_proxy(surface, one));
    EXPECT_EQ(alone.back().candidates, 1);
    const FieldLabels labels = labels_of(alone.back().mesh, alone.back().vanishing_corner);
    EXPECT_EQ(alone.back().singular_vertices, static_cast<int>(labels.singular_vertices.size()));
  }
  std::size_t first_fewest = 0;
  for (std::size_t i = 1; i < alone.size(); ++i) {
    if (alone[i].singular_vertices < alone[first_fewest].singular_vertices) first_fewest = i;
  }
  std::cout << "singular vertices at each edge:";
  for (const FieldProxy& one : alone) std::cout << " " << one.singular_vertices;
  std::cout << "; kept the proxy at " << kept.edge_mm << " mm\n";
  EXPECT_GT(first_fewest, 0U);  // the case holds a choice to make
  EXPECT_EQ(kept.singular_vertices, alone[first_fewest].singular_vertices);
  EXPECT_DOUBLE_EQ(kept.edge_mm, edges[first_fewest]);
  EXPECT_EQ(kept.mesh.faces, alone[first_fewest].mesh.faces);
  EXPECT_EQ(kept.vanishing_corner, alone[first_fewest].vanishing_corner);
  // The candidates differ: a different edge is a different resampling.
  EXPECT_NE(alone.front().mesh.faces.size(), alone.back().mesh.faces.size());
  // A factor of no length is refused before anything is made.
  FieldProxyParams zero = params;
  zero.edge_factors = {1.1, 0.0};
  EXPECT_THROW(field_guided_proxy(surface, zero), std::invalid_argument);
  // And the choice does not depend on the threads that made the candidates.
  FieldProxyParams one_thread = params;
  one_thread.threads = 1;
  params.threads = 2;
  EXPECT_EQ(field_guided_proxy(surface, one_thread).mesh.positions, kept.mesh.positions);
  EXPECT_EQ(field_guided_proxy(surface, params).mesh.positions, kept.mesh.positions);
}

TEST(FieldProxyTest, AQuadDominantInputIsNotRemeshedByMakeProxy) {
  // make_proxy's field method replaces surfaces that are not quad-dominant
  // only; the cut stage judges quad-dominant ones (cut_stage.hpp).
  ProxyParams params;
  params.method = ProxyMethod::Field;
  const ProxyResult kept = make_proxy(quad_ellipsoid(50.0, 1.0, 8), params);
  EXPECT_EQ(kept.method, "input");
  EXPECT_TRUE(kept.vanishing_corner.empty());
  const ProxyResult field = make_proxy(triangulated(quad_ellipsoid(50.0, 1.0, 8)), params);
  EXPECT_EQ(field.method, "field");
  EXPECT_EQ(field.vanishing_corner.size(), field.mesh.faces.size());
}

TEST(FieldProxyTest, ArcsEndWhereTheCutTurnsSharperThanTheLimit) {
  const PolygonMesh surface = triangulated(quad_ellipsoid(50.0, 0.7, 16));
  FieldProxyParams params;
  params.edge_mm = 6.0;
  const FieldProxy proxy = field_guided_proxy(surface, params);
  const HalfedgeMesh q(proxy.mesh);
  std::vector<std::size_t> arcs;
  for (const double turn : {180.0, 120.0, 45.0, 0.0}) {
    CutParams cut_params;
    cut_params.arc_turn_deg = turn;
    const CutMesh cut = cut_surface(q, cut_params, &proxy.vanishing_corner);
    EXPECT_TRUE(verify_cut(cut).empty());
    arcs.push_back(cut.arcs.size());
  }
  // The same cut edges, split at more and more turns; at 0 degrees no turn
  // is straight enough on a curved surface, so every edge is an arc.
  EXPECT_LE(arcs[0], arcs[1]);
  EXPECT_LE(arcs[1], arcs[2]);
  EXPECT_LT(arcs[2], arcs[3]);
}

}  // namespace
}  // namespace planner
