// wearknit stitch-mesh end to end, on a cut folder written by wearknit cut.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "planner/mesh/mesh_io.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "tests/planner/test_meshes.hpp"
#include "tests/test_support.hpp"

namespace {

using wearknit::test::read_file;
using wearknit::test::run_wearknit;

TEST(StitchMeshCliTest, MeshesACutFolderAndKeepsTheCutReport) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const wearknit::test::TempDir folder("stitch-cli");
  const auto& dir = folder.path();
  const auto cut = run_wearknit("cut '" + (shared / "meshes" / "half-torus-qd.obj").string() +
                                "' --scale 30 -q --no-pictures -o '" + dir.string() + "'");
  ASSERT_EQ(cut.exit_code, 0) << cut.err;
  const auto result = run_wearknit("stitch-mesh '" + dir.string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("stitch mesh: "), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(dir / "stitch-mesh.obj"));
  EXPECT_TRUE(std::filesystem::exists(dir / "stitch-mesh.png"));
  std::istringstream smobj(read_file(dir / "stitch-mesh.smobj"));
  knitout::DiagnosticSink sink;
  const auto mesh = planner::parse_smobj(smobj, "stitch-mesh.smobj", sink);
  ASSERT_TRUE(mesh);
  EXPECT_DOUBLE_EQ(mesh->course_mm, 1.05);
  EXPECT_DOUBLE_EQ(mesh->wale_mm, 2.875);
  const auto report = nlohmann::json::parse(read_file(dir / "report.json"));
  EXPECT_TRUE(report.contains("cut_edges"));  // the cut stage's figures are kept
  const auto& s = report.at("stitch_mesh");
  EXPECT_EQ(s.at("faces").at("total").get<std::size_t>(), mesh->faces.size());
  EXPECT_EQ(s.at("gauge").at("from"), "swatch 40x40:42x115");
  EXPECT_EQ(s.at("boundary_loops"), 1);
  EXPECT_TRUE(s.at("row_time_levelled").is_number_integer());
  EXPECT_TRUE(s.at("tip_sides").is_number_integer());
  // The straightening fits stop once the row time settles, and say how far
  // the rows stray from the labels.
  EXPECT_GE(s.at("straighten_fits").get<int>(), 1);
  EXPECT_LT(s.at("straighten_fits").get<int>(), 100);
  EXPECT_GE(s.at("label_deviation_deg").get<double>(), 0.0);
  EXPECT_LT(s.at("label_deviation_deg").get<double>(), 90.0);
  // Stitches off the surface are counted, and warned about when there are any.
  EXPECT_DOUBLE_EQ(s.at("off_surface").at("tolerance_mm").get<double>(), 2.875);
  const auto off_faces = s.at("off_surface").at("faces").get<std::size_t>();
  EXPECT_EQ(off_faces > 0, result.err.find("P087") != std::string::npos) << result.err;
  EXPECT_EQ(off_faces > 0, s.at("off_surface").at("max_offset_mm").get<double>() > 2.875);
  // The stitches lie on the garment's surface (surface.obj of the cut),
  // within half a wale of it, and P090 says when any does not.
  const auto& shape = s.at("surface_distance");
  EXPECT_EQ(shape.at("against"), "garment");
  EXPECT_LE(shape.at("mean_mm").get<double>(), shape.at("max_mm").get<double>());
  EXPECT_LT(shape.at("max_mm").get<double>(), 0.5 * 2.875);
  EXPECT_EQ(result.err.find("P090"), std::string::npos) << result.err;
  std::filesystem::remove(dir / "surface.obj");
  const auto without = run_wearknit("stitch-mesh '" + dir.string() + "' --no-picture");
  ASSERT_EQ(without.exit_code, 0) << without.err;
  EXPECT_EQ(nlohmann::json::parse(read_file(dir / "report.json"))
                .at("stitch_mesh")
                .at("surface_distance")
                .at("against"),
            "cut mesh");
  EXPECT_GT(s.at("relax_sweeps").get<int>(), 0);
  EXPECT_LE(s.at("relax_sweeps").get<int>(), 150);
  EXPECT_GE(s.at("relax_seconds").get<double>(), 0.0);
  // Both ways were meshed (--knit-direction best) and the better kept.
  const auto& way = s.at("knit_direction");
  const double as_cut = way.at("scores").at("as_cut").get<double>();
  const double turned = way.at("scores").at("turned").get<double>();
  EXPECT_EQ(way.at("turned").get<bool>(), turned > as_cut);

  // --relax 0 keeps the zipped places: the same stitches, other vertex places.
  const auto zipped = run_wearknit("stitch-mesh '" + dir.string() + "' --relax 0 -q --no-picture");
  ASSERT_EQ(zipped.exit_code, 0) << zipped.err;
  std::istringstream zipped_smobj(read_file(dir / "stitch-mesh.smobj"));
  const auto as_zipped = planner::parse_smobj(zipped_smobj, "stitch-mesh.smobj", sink);
  ASSERT_TRUE(as_zipped);
  ASSERT_EQ(as_zipped->faces.size(), mesh->faces.size());
  for (std::size_t f = 0; f < mesh->faces.size(); ++f) {
    EXPECT_EQ(as_zipped->faces[f].vertices, mesh->faces[f].vertices) << "face " << f;
    EXPECT_EQ(as_zipped->faces[f].type, mesh->faces[f].type) << "face " << f;
  }
  ASSERT_EQ(as_zipped->positions.size(), mesh->positions.size());
  std::size_t moved = 0;
  for (std::size_t v = 0; v < mesh->positions.size(); ++v) {
    moved += (as_zipped->positions[v] - mesh->positions[v]).norm() > 1e-6;
  }
  EXPECT_GT(moved, 0u);
  EXPECT_EQ(
      nlohmann::json::parse(read_file(dir / "report.json")).at("stitch_mesh").at("relax_sweeps"),
      0);

  // --stitch-mm replaces the swatch; a run again replaces only its own member.
  // --straighten caps the fits.
  const auto again = run_wearknit("stitch-mesh '" + dir.string() +
                                  "' --stitch-mm 2x3 --straighten 1 -q --no-picture");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out, "");
  const auto report2 = nlohmann::json::parse(read_file(dir / "report.json"));
  EXPECT_TRUE(report2.contains("cut_edges"));
  EXPECT_EQ(report2.at("stitch_mesh").at("gauge").at("course_mm"), 2.0);
  EXPECT_EQ(report2.at("stitch_mesh").at("straighten_fits"), 1);
  EXPECT_LT(report2.at("stitch_mesh").at("faces").at("total").get<int>(),
            s.at("faces").at("total").get<int>());
}

TEST(StitchMeshCliTest, RejectsBadGaugeOptions) {
  const wearknit::test::TempDir folder("stitch-cli-bad");
  const auto& dir = folder.path();
  auto r = run_wearknit("stitch-mesh '" + dir.string() + "' --swatch 40x40");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "wearknit stitch-mesh: `40x40` is not STITCHESxROWS:WIDTHxHEIGHT_MM with positive "
            "numbers (e.g. 40x40:42x115)\n");
  r = run_wearknit("stitch-mesh '" + dir.string() + "' --swatch 40x40:42x115 --stitch-mm 1x2");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "wearknit stitch-mesh: give --swatch or --stitch-mm, not both\n");
  r = run_wearknit("stitch-mesh '" + dir.string() + "' --gauge 0");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "wearknit stitch-mesh: the gauge (needles per inch) must be positive\n");
  for (const char* option : {"--row-end-wales -1", "--relax -1", "--saddle-wales -1"}) {
    r = run_wearknit("stitch-mesh '" + dir.string() + "' " + option);
    EXPECT_EQ(r.exit_code, 2) << option;
    EXPECT_EQ(r.err,
              "wearknit stitch-mesh: --straighten, --label-weight, --pentagon-cost, "
              "--stability-cost, --outside-cost, --row-end-wales, --saddle-wales and --relax "
              "must not be negative\n")
        << option;
  }
  r = run_wearknit("stitch-mesh '" + dir.string() + "' --knit-direction sideways");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "wearknit stitch-mesh: --knit-direction takes best, as-cut or turned, not "
            "'sideways'\n");
}

TEST(StitchMeshCliTest, SaysWhatIsMissingAndWritesNothing) {
  const wearknit::test::TempDir folder("stitch-cli-missing");
  const auto& dir = folder.path();
  auto r = run_wearknit("stitch-mesh '" + (dir / "nowhere").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            (dir / "nowhere").string() +
                ": error: [P020] no such folder (run `wearknit cut GARMENT -o DIR` first)\n");
  r = run_wearknit("stitch-mesh '" + dir.string() + "'");  // a folder without cut files
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("[P020]"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir / "stitch-mesh.smobj"));
  EXPECT_FALSE(std::filesystem::exists(dir / "report.json"));
}

TEST(StitchMeshCliTest, FineFeaturesAreKnittedWithAWarningOrRefused) {
  // A ring whose tube is 7.5 mm round: under 3 stitches of 2.875 mm.
  const wearknit::test::TempDir folder("stitch-cli-fine");
  const auto& dir = folder.path();
  {
    std::ofstream out(dir / "ring.obj");
    planner::write_obj(out, planner::test_meshes::torus(64, 12, 15.0, 1.2));
  }
  const std::string cut_dir = (dir / "cut").string();
  const auto cut = run_wearknit("cut '" + (dir / "ring.obj").string() + "' -q --no-pictures -o '" +
                                cut_dir + "'");
  ASSERT_EQ(cut.exit_code, 0) << cut.err;
  // Refused: the list with the place and girth, what would work, nothing written.
  auto r = run_wearknit("stitch-mesh '" + cut_dir + "' --fine-features refuse --no-picture");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("error: [P089] fine feature 1 of 1: 7.5 mm round (2.6 stitches"),
            std::string::npos)
      << r.err;
  const std::string larger = "make the garment 1.15 times larger";
  EXPECT_NE(r.err.find(larger), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::path(cut_dir) / "stitch-mesh.smobj"));
  // Knitted (the default): a warning, and the figures in the report.
  r = run_wearknit("stitch-mesh '" + cut_dir + "' --no-picture");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: [P088] fine feature 1 of 1"), std::string::npos) << r.err;
  const auto report =
      nlohmann::json::parse(read_file(std::filesystem::path(cut_dir) / "stitch-mesh.json"));
  const auto& fine = report.at("report").at("fine_features");
  EXPECT_DOUBLE_EQ(fine.at("bound_mm").get<double>(), 3 * 2.875);
  ASSERT_EQ(fine.at("parts").size(), 1u);
  EXPECT_NEAR(fine.at("parts")[0].at("girth_mm").get<double>(), 7.5, 0.4);
  // The size the message names knits the ring without the warning.
  const std::string cut2 = (dir / "cut2").string();
  ASSERT_EQ(run_wearknit("cut '" + (dir / "ring.obj").string() +
                         "' --scale 1.16 -q --no-pictures -o '" + cut2 + "'")
                .exit_code,
            0);
  r = run_wearknit("stitch-mesh '" + cut2 + "' --fine-features refuse --no-picture");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.err.find("P08"), std::string::npos) << r.err;
  // A bad choice is a usage error.
  r = run_wearknit("stitch-mesh '" + cut_dir + "' --fine-features maybe");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "wearknit stitch-mesh: --fine-features takes knit or refuse, not 'maybe'\n");
}

}  // namespace
