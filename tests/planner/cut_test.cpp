#include "planner/cut/cut.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <set>

#include "planner/cut/vanishing.hpp"
#include "planner/mesh/girth.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/pipeline.hpp"
#include "planner/proxy/proxy.hpp"
#include "tests/planner/test_meshes.hpp"
#include "tests/test_support.hpp"

namespace planner {
namespace {

CutParams cut_params(std::uint64_t seed, double cs = 1000, double co = 1) {
  CutParams params;
  params.seed = seed;
  params.cs = cs;
  params.co = co;
  return params;
}

CutMesh cut_of(const PolygonMesh& mesh, std::uint64_t seed = 1, double cs = 1000, double co = 1) {
  return cut_surface(HalfedgeMesh(mesh), cut_params(seed, cs, co));
}

// Q's vertices that lie on the boundary of the disc.
std::set<int> disc_boundary_sources(const CutMesh& cut) {
  const HalfedgeMesh disc(cut.disc);
  std::set<int> out;
  for (int v = 0; v < disc.num_vertices(); ++v) {
    if (disc.is_boundary_vertex(v)) out.insert(cut.disc_source[static_cast<std::size_t>(v)]);
  }
  return out;
}

TEST(LabelsTest, VanishingCornerIsTheMostAcuteCornerOfATriangle) {
  PolygonMesh mesh;
  mesh.positions = {{0, 0, 0}, {4, 0, 0}, {4, 1, 0}};  // corner at vertex 0 is the sharpest
  mesh.faces = {{1, 2, 0}};
  VanishingRule acute;
  acute.method = VanishingRule::Method::Acute;
  const FieldLabels labels = label_field(HalfedgeMesh(mesh), acute);
  EXPECT_EQ(labels.vanishing_corner[0], 2);  // corner index of vertex 0 in the face
  // Its two sides are opposite: directions d, d+1, d+2 around the face.
  const HalfedgeMesh q(mesh);
  EXPECT_EQ(halfedge_direction(q, labels, 0, 0), 0);
  EXPECT_EQ(halfedge_direction(q, labels, 0, 1), 1);
  EXPECT_EQ(halfedge_direction(q, labels, 0, 2), 3);  // turns by 2 only at the vanishing corner
}

// A 3 x 3 grid whose middle cell is two triangles split along the diagonal
// a-c, with c pulled outwards so that both triangles are sharpest at c.
PolygonMesh grid_with_split_cell() {
  PolygonMesh mesh;
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) mesh.positions.push_back({double(x), double(y), 0.0});
  }
  auto id = [](int x, int y) { return y * 4 + x; };
  mesh.positions[static_cast<std::size_t>(id(2, 2))] = {2.1, 2.1, 0.0};
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 3; ++x) {
      if (x == 1 && y == 1) continue;
      mesh.faces.push_back({id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)});
    }
  }
  mesh.faces.push_back({id(1, 1), id(2, 1), id(2, 2)});
  mesh.faces.push_back({id(1, 1), id(2, 2), id(1, 2)});
  return mesh;
}

TEST(LabelsTest, AcuteVanishingCornersCanLeaveAPairOfIrregularVertices) {
  const HalfedgeMesh q(grid_with_split_cell());
  VanishingRule acute;
  acute.method = VanishingRule::Method::Acute;
  const FieldLabels labels = label_field(q, acute);
  // Both triangles vanish at c = vertex 10: it keeps 3 corners, a = vertex 5 gets 5.
  EXPECT_EQ(labels.irregular_vertices, (std::vector<int>{5, 10}));
  EXPECT_EQ(labels.corner_count[5], 5);
  EXPECT_EQ(labels.corner_count[10], 3);
}

TEST(LabelsTest, RegularVanishingCornersMakeTheSplitCellRegular) {
  const HalfedgeMesh q(grid_with_split_cell());
  VanishingRule rule;
  rule.method = VanishingRule::Method::Regular;
  rule.slack_deg = 10.0;
  const FieldLabels labels = label_field(q, rule);
  EXPECT_TRUE(labels.irregular_vertices.empty());
  // One triangle vanishes at a, the other at c.
  auto vanishing_vertex = [&](int f) {
    return q.from(q.face_start(f) + labels.vanishing_corner[static_cast<std::size_t>(f)]);
  };
  EXPECT_NE(vanishing_vertex(8), vanishing_vertex(9));
  // A corner wider than the slack allows is never taken: a is 45 degrees,
  // c about 40, so a 1-degree slack keeps the acute choice.
  rule.slack_deg = 1.0;
  EXPECT_EQ(label_field(q, rule).irregular_vertices.size(), 2u);
  // The cut of either labelling is a valid disc.
  CutParams params;
  params.vanishing.method = VanishingRule::Method::Regular;
  params.vanishing.slack_deg = 10.0;
  const CutMesh cut = cut_surface(q, params);
  const auto problems = verify_cut(cut);
  EXPECT_TRUE(problems.empty()) << problems.front();
  EXPECT_EQ(summarize(cut).cut_edges, 0);
}

TEST(LabelsTest, CubeCornersAreTheIrregularVertices) {
  const HalfedgeMesh q(test_meshes::cube(3));
  const FieldLabels labels = label_field(q);
  EXPECT_EQ(labels.irregular_vertices.size(), 8u);
  EXPECT_EQ(labels.singular_vertices.size(), 8u);
  for (int v : labels.irregular_vertices)
    EXPECT_EQ(labels.corner_count[static_cast<std::size_t>(v)], 3);
}

TEST(LabelsTest, GridHasNoIrregularVertexBoundaryIgnored) {
  const FieldLabels labels = label_field(HalfedgeMesh(test_meshes::grid(4, 3)));
  EXPECT_TRUE(labels.irregular_vertices.empty());
}

TEST(CutTest, DiscNeedsNoCut) {
  const CutMesh cut = cut_of(test_meshes::grid(6, 5));
  EXPECT_TRUE(verify_cut(cut).empty());
  const CutSummary s = summarize(cut);
  EXPECT_EQ(s.cut_edges, 0);
  EXPECT_EQ(s.arcs, 0);
  EXPECT_EQ(s.overlapping_faces, 0);
  // Each face sits in its own cell: the grid is its own parameterisation.
  std::set<std::pair<int, int>> cells;
  for (const auto& uv : cut.face_uv) cells.insert({uv[0], uv[1]});
  EXPECT_EQ(cells.size(), 30u);
}

TEST(CutTest, ASpindleWithFannedPolesStillOpensIntoADisc) {
  // Quads round the axis, a fan of triangles at each pole: the growth can
  // fuse all of the cut but one edge, and a cut of one edge splits no
  // vertex. The last two edges stay, so the disc opens.
  for (const int segments : {4, 8, 16}) {
    const PolygonMesh spindle = test_meshes::revolution(
        60.0, 10, segments, [](double z) { return 1.0 + 0.2 * z * (60.0 - z) / 30.0; });
    for (const std::uint64_t seed : {1u, 2u, 3u}) {
      const CutMesh cut = cut_of(spindle, seed);
      EXPECT_EQ(verify_cut(cut), std::vector<std::string>{}) << segments << " seed " << seed;
      EXPECT_GE(std::count(cut.cut_edge.begin(), cut.cut_edge.end(), true), 2);
    }
  }
}

TEST(CutTest, RegularTorusIsOpenedByTwoLoops) {
  const CutMesh cut = cut_of(test_meshes::torus(10, 6));
  const auto problems = verify_cut(cut);
  EXPECT_TRUE(problems.empty()) << problems.front();
  const CutSummary s = summarize(cut);
  EXPECT_EQ(s.euler_characteristic, 1);
  EXPECT_EQ(s.boundary_loops, 1);
  EXPECT_GE(s.cut_edges, 6 + 10 - 0);  // a meridian and a longitude at least... minus shared vertex
  EXPECT_EQ(s.irregular_vertices, 0);
  EXPECT_EQ(s.overlapping_faces, 0);
}

TEST(CutTest, SingularVerticesEndUpOnTheCut) {
  const CutMesh cut = cut_of(test_meshes::cube(4), 3);
  EXPECT_TRUE(verify_cut(cut).empty());
  const std::set<int> boundary = disc_boundary_sources(cut);
  for (int v : cut.labels.singular_vertices) EXPECT_TRUE(boundary.count(v)) << "vertex " << v;
}

TEST(CutTest, MotorcyclesRunStraightFromIrregularVertices) {
  const CutMesh cut = cut_of(test_meshes::cube(4));
  // On the 4x4-per-side cube the motorcycles from the 8 corners run along
  // the cube's 12 edges (4 mesh edges each) and stop at the first visited
  // vertex: every crossed edge lies on a cube edge.
  int crossed = 0;
  for (int e = 0; e < cut.proxy.num_edges(); ++e) {
    if (cut.motorcycle_edges[static_cast<std::size_t>(e)] == 0) continue;
    ++crossed;
    const int h = cut.proxy.edge_halfedge(e);
    const Vec3 a = cut.proxy.position(cut.proxy.from(h));
    const Vec3 b = cut.proxy.position(cut.proxy.to(h));
    int on_faces = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const bool extreme = (a[axis] == 0 || a[axis] == 4) && a[axis] == b[axis];
      on_faces += extreme ? 1 : 0;
    }
    EXPECT_EQ(on_faces, 2) << "edge " << e << " is not on a cube edge";
  }
  EXPECT_EQ(crossed, 48);
}

TEST(CutTest, StraightnessWeightPutsCutsOnMotorcycleEdges) {
  auto fraction_on_motorcycles = [](const CutMesh& cut) {
    int on = 0, all = 0;
    for (int e = 0; e < cut.proxy.num_edges(); ++e) {
      if (!cut.cut_edge[static_cast<std::size_t>(e)]) continue;
      ++all;
      on += cut.motorcycle_edges[static_cast<std::size_t>(e)] > 0 ? 1 : 0;
    }
    return all == 0 ? 0.0 : static_cast<double>(on) / all;
  };
  const PolygonMesh cube = test_meshes::cube(6);
  double with = 0, without = 0;
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    with += fraction_on_motorcycles(cut_of(cube, seed, 1000, 0));
    without += fraction_on_motorcycles(cut_of(cube, seed, 0, 0));
  }
  EXPECT_GT(with / 4, 0.95);
  EXPECT_LT(without / 4, with / 4);
}

TEST(CutTest, SameSeedSameCutOtherSeedOtherSeedFace) {
  const PolygonMesh cube = test_meshes::cube(5);
  const CutMesh a = cut_of(cube, 7);
  const CutMesh b = cut_of(cube, 7);
  EXPECT_EQ(a.cut_edge, b.cut_edge);
  EXPECT_EQ(a.face_uv, b.face_uv);
  std::set<int> seeds;
  for (std::uint64_t s = 1; s <= 5; ++s) seeds.insert(cut_of(cube, s).seed_face);
  EXPECT_GT(seeds.size(), 1u);
}

TEST(CutTest, VerifyCatchesABrokenCut) {
  CutMesh cut = cut_of(test_meshes::torus(8, 6));
  ASSERT_TRUE(verify_cut(cut).empty());
  // Glue one cut edge back: the arcs no longer match and the disc changes.
  const auto it = std::find(cut.cut_edge.begin(), cut.cut_edge.end(), true);
  ASSERT_NE(it, cut.cut_edge.end());
  *it = false;
  EXPECT_FALSE(verify_cut(cut).empty());
  // A flipped direction breaks label consistency.
  CutMesh other = cut_of(test_meshes::grid(3, 3));
  other.direction[0] = (other.direction[0] + 1) % 4;
  const auto problems = verify_cut(other);
  ASSERT_FALSE(problems.empty());
  EXPECT_EQ(problems[0], "face 0: direction of side 0 does not follow its corners");
}

TEST(CutIoTest, FolderRoundTrips) {
  const CutMesh cut = cut_of(test_meshes::cube(4), 2);
  const auto dir = wearknit::test::make_temp_dir("cut_io");
  Cut written{cut, {}, 0, {}, {}};
  written.report.input = "cube";
  // The girth per vertex of Q, with one no ray could measure.
  for (int v = 0; v < cut.proxy.num_vertices(); ++v) written.girth_mm.push_back(1.0 + 0.25 * v);
  written.girth_mm[1] = kNoGirth;
  std::uint64_t id = 0;
  ASSERT_EQ(write_cut(dir.string(), written, {false, 600}, &id), "");
  knitout::DiagnosticSink sink;
  const auto read = read_cut(dir.string(), sink);
  ASSERT_TRUE(read.has_value()) << knitout::format(sink.diagnostics().at(0));
  // The id the files record is the one write_cut gave, and the report comes back.
  EXPECT_NE(id, 0u);
  EXPECT_EQ(read->id, id);
  EXPECT_EQ(read->report.input, "cube");
  const CutMesh* back = &read->mesh;
  EXPECT_EQ(back->proxy.polygons().faces, cut.proxy.polygons().faces);
  EXPECT_EQ(back->cut_edge, cut.cut_edge);
  EXPECT_EQ(back->direction, cut.direction);
  EXPECT_EQ(back->face_uv, cut.face_uv);
  EXPECT_EQ(back->disc.faces, cut.disc.faces);
  EXPECT_EQ(back->disc_source, cut.disc_source);
  EXPECT_EQ(back->arcs.size(), cut.arcs.size());
  EXPECT_EQ(back->labels.irregular_vertices, cut.labels.irregular_vertices);
  EXPECT_TRUE(verify_cut(*back).empty());
  EXPECT_EQ(read->girth_mm, written.girth_mm);
  // cut-mesh.obj starts with proxy.obj's vertices in order, the cut copies follow.
  ASSERT_GT(cut.disc_source.size(), static_cast<std::size_t>(cut.proxy.num_vertices()));
  for (int v = 0; v < cut.proxy.num_vertices(); ++v) {
    EXPECT_EQ(cut.disc_source[static_cast<std::size_t>(v)], v);
  }
  std::filesystem::remove_all(dir);
}

TEST(CutIoTest, MissingFolderIsADiagnostic) {
  knitout::DiagnosticSink sink;
  EXPECT_FALSE(read_cut("/nonexistent/cut", sink).has_value());
  ASSERT_EQ(sink.diagnostics().size(), 4u);
  EXPECT_EQ(
      knitout::format(sink.diagnostics()[0]),
      "/nonexistent/cut/proxy.obj: error: [P020] missing: not a cut folder (run wearknit cut)");
}

TEST(CutIoTest, ArcOverANonEdgeIsADiagnostic) {
  const CutMesh cut = cut_of(test_meshes::torus(6, 4));
  const auto dir = wearknit::test::make_temp_dir("cut_io_bad");
  ASSERT_EQ(write_cut(dir.string(), Cut{cut, {}, 0, {}, {}}, {false, 600}), "");
  std::string cuts = wearknit::test::read_file(dir / "cut.json");
  const auto pos = cuts.find("\"edges\": [");
  ASSERT_NE(pos, std::string::npos);
  cuts.insert(pos + 10, "[0, 99999], ");
  wearknit::test::write_file(dir / "cut.json", cuts);
  knitout::DiagnosticSink sink;
  EXPECT_FALSE(read_cut(dir.string(), sink).has_value());
  ASSERT_EQ(sink.diagnostics().size(), 1u);
  EXPECT_EQ(sink.diagnostics()[0].code, "P022");
  EXPECT_NE(sink.diagnostics()[0].message.find("0-99999 is not an edge of proxy.obj"),
            std::string::npos);
  std::filesystem::remove_all(dir);
}

// Done-when of the cutting stage: every shared mesh, two seeds, one disc
// with no interior singularity and consistent labels. Triangle meshes are
// remeshed coarsely to keep the test fast.
TEST(CutTest, EverySharedMeshBecomesOneDisc) {
  WEARKNIT_REQUIRE_SHARED(shared);
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(shared / "meshes")) {
    if (entry.path().extension() == ".obj") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 38u);
  int remeshed = 0;
  int extracted = 0;
  std::size_t irregular_acute = 0, irregular_regular = 0;
  for (const auto& file : files) {
    knitout::DiagnosticSink sink;
    const auto mesh = load_mesh(file.string(), {}, sink);
    ASSERT_TRUE(mesh.has_value()) << file << ": "
                                  << (sink.diagnostics().empty()
                                          ? ""
                                          : knitout::format(sink.diagnostics()[0]));
    ProxyParams proxy_params;
    proxy_params.method = ProxyMethod::Remesh;
    proxy_params.auto_faces = 300;
    proxy_params.field_iterations = 30;
    proxy_params.position_iterations = 30;
    const ProxyResult proxy = make_proxy(*mesh, proxy_params);
    if (proxy.remeshed) {
      ++remeshed;
      extracted += proxy.method == "instant-meshes" ? 1 : 0;
      std::cout << file.filename().string() << ": " << proxy.method << " " << proxy.remesh_failure
                << "\n";
    }
    const HalfedgeMesh input(*mesh);
    const HalfedgeMesh q(proxy.mesh);
    // The proxy keeps the topology of the input.
    EXPECT_EQ(q.euler_characteristic(), input.euler_characteristic()) << file;
    EXPECT_EQ(q.count_boundary_loops(), input.count_boundary_loops()) << file;
    for (std::uint64_t seed : {1u, 2u}) {
      const CutMesh cut = cut_surface(q, cut_params(seed));
      const auto problems = verify_cut(cut);
      EXPECT_TRUE(problems.empty()) << file << " seed " << seed << ": " << problems.front();
      const HalfedgeMesh disc(cut.disc);
      EXPECT_EQ(disc.euler_characteristic(), 1) << file << " seed " << seed;
      EXPECT_EQ(disc.count_boundary_loops(), 1) << file << " seed " << seed;
      const std::set<int> boundary = disc_boundary_sources(cut);
      for (int v : cut.labels.singular_vertices) {
        EXPECT_TRUE(boundary.count(v)) << file << ": singular vertex " << v << " inside the disc";
      }
    }
    // The same holds with the other vanishing rules: the optimal corners,
    // the most regular of the three, and the corners moved one at a time for
    // regularity, which never leaves more irregular vertices than the most
    // acute ones (§4.1, the default).
    CutParams optimal = cut_params(1);
    optimal.vanishing.method = VanishingRule::Method::Optimal;
    const CutMesh optimal_cut = cut_surface(q, optimal);
    CutParams acute = cut_params(1);
    acute.vanishing.method = VanishingRule::Method::Acute;
    CutParams regular = cut_params(1);
    regular.vanishing.method = VanishingRule::Method::Regular;
    regular.vanishing.slack_deg = 30.0;
    const CutMesh acute_cut = cut_surface(q, acute);
    const CutMesh cut = cut_surface(q, regular);
    for (const CutMesh* other : {&optimal_cut, &cut}) {
      const auto problems = verify_cut(*other);
      EXPECT_TRUE(problems.empty()) << file << ": " << problems.front();
      EXPECT_EQ(HalfedgeMesh(other->disc).euler_characteristic(), 1) << file;
      EXPECT_EQ(HalfedgeMesh(other->disc).count_boundary_loops(), 1) << file;
    }
    EXPECT_LE(cut.labels.irregular_vertices.size(), acute_cut.labels.irregular_vertices.size())
        << file;
    const int misfit = corner_misfit(q, optimal_cut.labels.vanishing_corner);
    EXPECT_LE(misfit, corner_misfit(q, cut.labels.vanishing_corner)) << file;
    EXPECT_LE(misfit, corner_misfit(q, acute_cut.labels.vanishing_corner)) << file;
    irregular_acute += acute_cut.labels.irregular_vertices.size();
    irregular_regular += cut.labels.irregular_vertices.size();
  }
  // Most triangle meshes get a lattice-extracted proxy; the rest fall back
  // to triangle pairing (docs/cutting.md lists which).
  EXPECT_GE(remeshed, 20);
  EXPECT_GE(extracted * 3, remeshed * 2) << extracted << " of " << remeshed;
  // Over all meshes the regular choice removes a good share of them.
  EXPECT_LT(irregular_regular * 10, irregular_acute * 9)
      << irregular_regular << " of " << irregular_acute;
}

double cut_length(const CutMesh& cut) {
  double length = 0.0;
  for (const CutArc& arc : cut.arcs) length += arc.length_mm;
  return length;
}

TEST(CutTightenTest, ATorusIsOpenedByItsShortestLoops) {
  // The cut of a torus needs one loop round the tube and one round the
  // hole; the shortest are the tube's circle and the hole's inner ring.
  const int n = 24, m = 12;
  const PolygonMesh torus = test_meshes::torus(n, m);
  const HalfedgeMesh q(torus);
  double inner_ring = 0.0, tube = 0.0;
  for (int i = 0; i < n; ++i) {
    inner_ring +=
        (torus.positions[(m / 2) * n + (i + 1) % n] - torus.positions[(m / 2) * n + i]).norm();
  }
  for (int j = 0; j < m; ++j)
    tube += (torus.positions[((j + 1) % m) * n] - torus.positions[j * n]).norm();
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    CutParams params = cut_params(seed);
    params.tighten = false;
    const CutMesh grown = cut_surface(q, params);
    params.tighten = true;
    const CutMesh cut = cut_surface(q, params);
    for (const CutMesh* c : {&grown, &cut}) {
      const auto problems = verify_cut(*c);
      EXPECT_TRUE(problems.empty()) << "seed " << seed << ": " << problems.front();
    }
    // The grown cut runs where the fronts met (36-50 units here); the
    // tightened one comes within 10% of the two shortest loops.
    EXPECT_LT(cut_length(cut), cut_length(grown)) << "seed " << seed;
    EXPECT_LE(cut_length(cut), 1.1 * (inner_ring + tube)) << "seed " << seed;
    EXPECT_LE(cut.arcs.size(), 3u) << "seed " << seed;
  }
}

}  // namespace
}  // namespace planner
