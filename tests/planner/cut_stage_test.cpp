// The cut stage's report of the smoothest cross field beside Q's own
// irregular vertices (cut_stage.hpp FieldReport, proxy_singularities).
#include "planner/cut/cut_stage.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/shapes.hpp"
#include "planner/pipeline.hpp"
#include "tests/planner/test_meshes.hpp"
#include "tests/test_support.hpp"

namespace planner {
namespace {

using nlohmann::json;
using wearknit::test::read_file;
using wearknit::test::run_wearknit;
using wearknit::test::TempDir;

TEST(CutStageTest, ReportsTheFieldBesideTheProxysIrregularVertices) {
  // The cube-sphere is its own proxy (all quads): eight valence-3 vertices,
  // and the smoothest field's eight +1 singularities.
  const Cut cut = cut_garment(quad_ellipsoid(50.0, 1.0, 12), {});
  const FieldReport& field = cut.report.field;
  EXPECT_EQ(cut.report.proxy_method, "input");
  EXPECT_DOUBLE_EQ(field.edge_mm, cut.report.proxy_edge_mm);
  EXPECT_GT(field.faces, 0);
  EXPECT_EQ(field.euler_characteristic, 2);
  EXPECT_EQ(field.boundary_loops, 0);
  EXPECT_EQ(field.singularities.index_sum, 8);
  EXPECT_EQ(field.singularities.by_index, (std::map<int, int>{{1, 8}}));
  const FieldSingularities q = proxy_singularities(cut.mesh);
  EXPECT_EQ(q.count, 8);
  EXPECT_EQ(q.index_sum, 8);
  EXPECT_EQ(q.by_index, (std::map<int, int>{{1, 8}}));
  EXPECT_NE(describe(cut).find("\nfield: 8 singularities (+1: 8; index sum 8, Euler characteristic "
                               "2) at "),
            std::string::npos)
      << describe(cut);
  EXPECT_NE(
      describe(cut).find(
          "; Q: 8 irregular vertices (+1: 8), 8 singular, 0 adjacent +1/-1 pairs\nproxy kept: "),
      std::string::npos)
      << describe(cut);
}

TEST(CutStageTest, ProxyIndicesCountTheCornersOfIrregularVertices) {
  // A valence-5 vertex in a flat quad patch: index 4 - 5 = -1.
  PolygonMesh mesh;
  const double pi = std::acos(-1.0);
  mesh.positions.emplace_back(0, 0, 0);
  for (int i = 0; i < 10; ++i) {
    const double r = i % 2 == 0 ? 1.0 : 1.4;
    mesh.positions.emplace_back(r * std::cos(pi * i / 5), r * std::sin(pi * i / 5), 0);
  }
  for (int i = 0; i < 5; ++i)
    mesh.faces.push_back({0, 1 + 2 * i, 1 + (2 * i + 1) % 10, 1 + (2 * i + 2) % 10});
  CutMesh cut;
  cut.proxy = HalfedgeMesh(mesh);
  cut.labels = label_field(cut.proxy);
  const FieldSingularities q = proxy_singularities(cut);
  EXPECT_EQ(q.count, 1);
  EXPECT_EQ(q.index_sum, -1);
  EXPECT_EQ(q.by_index, (std::map<int, int>{{-1, 1}}));
}

TEST(CutStageTest, TheFieldReportSurvivesTheCutFolder) {
  const Cut cut = cut_garment(quad_ellipsoid(50.0, 1.0, 12), {});
  const TempDir dir("cut_stage_field");
  ASSERT_EQ(write_cut(dir.path().string(), cut, {false, 100}), "");
  const json report = json::parse(read_file(dir.path() / "cut.json"))["report"];
  EXPECT_EQ(report["field"]["singularities"], 8);
  EXPECT_EQ(report["field"]["index_sum"], 8);
  EXPECT_EQ(report["field"]["euler_characteristic"], 2);
  EXPECT_EQ(report["field"]["by_index"], json({{"+1", 8}}));
  EXPECT_EQ(report["proxy"]["irregular_vertices"], 8);
  EXPECT_EQ(report["proxy"]["singular_vertices"], 8);
  EXPECT_EQ(report["proxy"]["by_index"], json({{"+1", 8}}));
  EXPECT_GE(report["time_s"]["field"].get<double>(), 0.0);

  knitout::DiagnosticSink sink;
  const std::optional<Cut> read = read_cut(dir.path().string(), sink);
  ASSERT_TRUE(read) << (sink.diagnostics().empty() ? ""
                                                   : knitout::format(sink.diagnostics().front()));
  const FieldReport& back = read->report.field;
  EXPECT_DOUBLE_EQ(back.edge_mm, cut.report.field.edge_mm);
  EXPECT_EQ(back.faces, cut.report.field.faces);
  EXPECT_EQ(back.euler_characteristic, 2);
  EXPECT_EQ(back.singularities.count, 8);
  EXPECT_EQ(back.singularities.index_sum, 8);
  EXPECT_EQ(back.singularities.by_index, (std::map<int, int>{{1, 8}}));
}

TEST(CutStageTest, TheCutVerbPrintsTheFieldLineAndTheSummaryHoldsIt) {
  const TempDir dir("cut_stage_cli");
  {
    std::ofstream out(dir.path() / "sphere.obj");
    write_obj(out, quad_ellipsoid(50.0, 1.0, 12));
  }
  const auto result = run_wearknit("cut " + (dir.path() / "sphere.obj").string() + " -o " +
                                   (dir.path() / "out").string() + " --no-pictures");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("\nfield: 8 singularities (+1: 8; index sum 8"), std::string::npos)
      << result.out;
  const json report = json::parse(read_file(dir.path() / "out" / "report.json"));
  EXPECT_EQ(report["field"]["index_sum"], 8);
  EXPECT_EQ(report["proxy"]["by_index"], json({{"+1", 8}}));
}

}  // namespace
}  // namespace planner
