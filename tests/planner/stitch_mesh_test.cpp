#include "planner/stitch_mesh/stitch_mesh.hpp"

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <vector>

#include "planner/stitch_mesh/gauge.hpp"

namespace planner {
namespace {

using R = EdgeRole;

// Two rows of two knit stitches, then a decrease on top: 3 x 2 grid of
// vertices plus a top row of two vertices over the decrease... kept small:
//
//   6 ----- 7            row 2: one decrease (two course-in below, one course-out)
//   |       |
//   3 - 4 - 5            row 1: two knit stitches
//   |   |   |
//   0 - 1 - 2
StitchMesh small_mesh() {
  StitchMesh mesh;
  mesh.course_mm = 1.0;
  mesh.wale_mm = 3.0;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 3, 0},
                    {1, 3, 0}, {2, 3, 0}, {0, 6, 0}, {2, 6, 0}};
  StitchFace a{{0, 1, 4, 3},
               {R::CourseIn, R::Wale, R::CourseOut, R::Wale},
               {5, kNoArc, kNoArc, 7},
               FaceType::Knit};
  StitchFace b{{1, 2, 5, 4},
               {R::CourseIn, R::Wale, R::CourseOut, R::Wale},
               {5, kNoArc, kNoArc, kNoArc},
               FaceType::Knit};
  StitchFace c{{3, 4, 5, 7, 6},
               {R::CourseIn, R::CourseIn, R::Wale, R::CourseOut, R::Wale},
               {kNoArc, kNoArc, kNoArc, kNoArc, 7},
               FaceType::Decrease};
  mesh.faces = {a, b, c};
  return mesh;
}

TEST(StitchMeshTest, ValidMeshHasNoProblems) {
  EXPECT_TRUE(check(small_mesh()).empty());
}

TEST(StitchMeshTest, ClassifiesTheFourFaceTypesInAnyRotation) {
  EXPECT_EQ(classify_roles({R::Wale, R::CourseOut, R::Wale, R::CourseIn}), FaceType::Knit);
  EXPECT_EQ(classify_roles({R::CourseOut, R::CourseOut, R::Wale, R::CourseIn, R::Wale}),
            FaceType::Increase);
  EXPECT_EQ(classify_roles({R::CourseIn, R::CourseIn, R::Wale, R::CourseOut, R::Wale}),
            FaceType::Decrease);
  EXPECT_EQ(classify_roles({R::CourseIn, R::Wale, R::CourseOut}), FaceType::ShortRow);
  EXPECT_EQ(classify_roles({R::CourseIn, R::CourseOut, R::Wale}), FaceType::ShortRow);
  std::size_t first = 99;
  classify_roles({R::Wale, R::CourseIn, R::CourseIn, R::Wale, R::CourseOut}, &first);
  EXPECT_EQ(first, 1u);
}

TEST(StitchMeshTest, RejectsFacesThatAreNoneOfTheFourTypes) {
  // Should-fail twins of the valid types: wale sides touching, two wale
  // sides on a triangle, a hexagon, course sides only.
  EXPECT_FALSE(classify_roles({R::CourseIn, R::Wale, R::Wale, R::CourseOut}));
  EXPECT_FALSE(classify_roles({R::CourseIn, R::Wale, R::Wale}));
  EXPECT_FALSE(
      classify_roles({R::CourseIn, R::Wale, R::CourseOut, R::CourseOut, R::CourseOut, R::Wale}));
  EXPECT_FALSE(classify_roles({R::CourseIn, R::CourseIn, R::CourseOut, R::CourseOut}));
  EXPECT_FALSE(classify_roles({R::CourseIn, R::Wale, R::CourseIn, R::Wale}));
}

TEST(StitchMeshTest, ReportsAWrongTypeAndMismatchedSharedSides) {
  StitchMesh mesh = small_mesh();
  mesh.faces[2].type = FaceType::Increase;
  mesh.faces[1].roles[3] = R::CourseOut;  // its side shared with face 0 is no longer wale
  const std::vector<std::string> problems = check(mesh);
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0],
            "face 1: roles course-in wale course-out course-out make no valid face (§6.3)");
  EXPECT_EQ(problems[1], "face 2: type increase but its roles make decrease");
  EXPECT_EQ(problems[2], "face 0 side 1: wale meets face 1 side 3 as course-out");
}

TEST(StitchMeshTest, ReportsSidesThatDoNotMatchAcrossAWaleEdge) {
  StitchMesh mesh = small_mesh();
  mesh.faces[0].roles = {R::Wale, R::CourseIn, R::Wale, R::CourseOut};  // turned a quarter
  const std::vector<std::string> problems = check(mesh);
  ASSERT_FALSE(problems.empty());
  EXPECT_EQ(problems[0], "face 0 side 1: course-in meets face 1 side 3 as wale");
}

TEST(StitchMeshTest, ReportsBadIndicesAndArrayLengths) {
  StitchMesh mesh = small_mesh();
  mesh.faces[0].vertices[2] = 42;
  mesh.faces[1].arcs.pop_back();
  const std::vector<std::string> problems = check(mesh);
  ASSERT_EQ(problems.size(), 2u);
  EXPECT_EQ(problems[0], "face 0 corner 2: vertex 42 out of range (8 vertices)");
  EXPECT_EQ(problems[1], "face 1: 4 vertices, 4 roles, 3 arcs");
}

TEST(StitchMeshTest, SmobjRoundTripKeepsFacesTypesAndArcs) {
  const StitchMesh mesh = small_mesh();
  std::ostringstream out;
  write_smobj(out, mesh);
  const std::string text = out.str();
  // The face library names each type with its edge types.
  EXPECT_NE(text.find("L knit -l1 y1 +l1 y1\n"), std::string::npos);
  EXPECT_NE(text.find("L decrease -l1 -l1 y1 +l1 y1\n"), std::string::npos);
  EXPECT_NE(text.find("# arc 1/4 7\n"), std::string::npos);
  std::istringstream in(text);
  knitout::DiagnosticSink sink;
  const std::optional<StitchMesh> back = parse_smobj(in, "mesh.smobj", sink);
  ASSERT_TRUE(back) << (sink.diagnostics().empty() ? "" : format(sink.diagnostics()[0]));
  EXPECT_TRUE(check(*back).empty());
  EXPECT_EQ(back->course_mm, 1.0);
  EXPECT_EQ(back->wale_mm, 3.0);
  ASSERT_EQ(back->positions.size(), mesh.positions.size());
  ASSERT_EQ(back->faces.size(), mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    EXPECT_EQ(back->faces[f].type, mesh.faces[f].type);
    // Faces are written from their bottom-left course-in side; these start there.
    EXPECT_EQ(back->faces[f].vertices, mesh.faces[f].vertices);
    EXPECT_EQ(back->faces[f].roles, mesh.faces[f].roles);
    EXPECT_EQ(back->faces[f].arcs, mesh.faces[f].arcs);
  }
}

TEST(StitchMeshTest, WriterRefusesAnInvalidMesh) {
  StitchMesh mesh = small_mesh();
  mesh.faces[2].type = FaceType::Knit;
  std::ostringstream out;
  EXPECT_THROW(write_smobj(out, mesh), std::logic_error);
}

std::vector<std::string> read_errors(const std::string& text) {
  std::istringstream in(text);
  knitout::DiagnosticSink sink;
  EXPECT_FALSE(parse_smobj(in, "bad.smobj", sink));
  std::vector<std::string> lines;
  for (const knitout::Diagnostic& d : sink.diagnostics()) lines.push_back(format(d));
  return lines;
}

const char* kTwoKnits =
    "L knit -l1 y1 +l1 y1\n"
    "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 3 0\nv 1 3 0\nv 2 3 0\n"
    "f 1 2 5 4\nf 2 3 6 5\nT 1\nT 1\n";

TEST(StitchMeshTest, ReadsAMinimalSmobj) {
  std::istringstream in(kTwoKnits);
  knitout::DiagnosticSink sink;
  const std::optional<StitchMesh> mesh = parse_smobj(in, "ok.smobj", sink);
  ASSERT_TRUE(mesh);
  EXPECT_EQ(mesh->faces.size(), 2u);
  EXPECT_TRUE(check(*mesh).empty());
}

TEST(StitchMeshTest, SmobjReaderNamesTheLineOfEachProblem) {
  EXPECT_EQ(read_errors("L purl -l1 y1 +l1 y1\n"),
            std::vector<std::string>{"bad.smobj:1: error: [P082] unknown face type `purl` (knit, "
                                     "increase, decrease, short-row)"});
  EXPECT_EQ(
      read_errors("L knit -l1 y1 +x1 y1\n"),
      std::vector<std::string>{"bad.smobj:1: error: [P082] edge type `+x1` is not -lN, +lN or yN"});
  EXPECT_EQ(read_errors("v 1 2\n"),
            std::vector<std::string>{"bad.smobj:1: error: [P081] vertex needs three numbers"});
  EXPECT_EQ(read_errors(std::string(kTwoKnits) + "T 1\n"),
            std::vector<std::string>{"bad.smobj: error: [P083] 2 faces but 3 T lines"});
  EXPECT_EQ(read_errors("L knit -l1 y1 +l1 y1\nv 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\nT 1\n"),
            std::vector<std::string>{
                "bad.smobj:5: error: [P083] face 1 has 3 corners but its type has 4 edges"});
  // A library that is fine, faces that do not fit together (a knit face
  // turned a quarter against its neighbour).
  EXPECT_EQ(read_errors("L knit -l1 y1 +l1 y1\nL knit y1 -l1 y1 +l1\n"
                        "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 3 0\nv 1 3 0\nv 2 3 0\n"
                        "f 1 2 5 4\nf 2 3 6 5\nT 1\nT 2\n"),
            std::vector<std::string>{
                "bad.smobj: error: [P084] face 0 side 1: wale meets face 1 side 3 as course-out"});
}

TEST(StitchMeshGaugeTest, DefaultIsThePapersSeedSwatch) {
  const StitchGauge gauge;
  EXPECT_DOUBLE_EQ(gauge.course_mm, 1.05);
  EXPECT_DOUBLE_EQ(gauge.wale_mm, 2.875);
  EXPECT_EQ(gauge.needles_per_inch, 15.0);
}

TEST(StitchMeshGaugeTest, ParsesSwatchAndStitchSize) {
  StitchGauge gauge;
  EXPECT_EQ(parse_swatch("20x30:40x60", gauge), "");
  EXPECT_DOUBLE_EQ(gauge.course_mm, 2.0);
  EXPECT_DOUBLE_EQ(gauge.wale_mm, 2.0);
  EXPECT_EQ(gauge.source, "swatch 20x30:40x60");
  EXPECT_EQ(parse_stitch_mm("1.5x2.5", gauge), "");
  EXPECT_DOUBLE_EQ(gauge.course_mm, 1.5);
  EXPECT_DOUBLE_EQ(gauge.wale_mm, 2.5);
}

TEST(StitchMeshGaugeTest, RejectsMalformedSizesAndKeepsTheGauge) {
  StitchGauge gauge;
  EXPECT_EQ(
      parse_swatch("40x40", gauge),
      "`40x40` is not STITCHESxROWS:WIDTHxHEIGHT_MM with positive numbers (e.g. 40x40:42x115)");
  EXPECT_EQ(parse_swatch("0x40:42x115", gauge),
            "`0x40:42x115` is not STITCHESxROWS:WIDTHxHEIGHT_MM with positive numbers (e.g. "
            "40x40:42x115)");
  EXPECT_EQ(parse_stitch_mm("1.05", gauge),
            "`1.05` is not COURSExWALE in mm with positive numbers (e.g. 1.05x2.875)");
  EXPECT_EQ(parse_stitch_mm("-1x2", gauge),
            "`-1x2` is not COURSExWALE in mm with positive numbers (e.g. 1.05x2.875)");
  EXPECT_DOUBLE_EQ(gauge.course_mm, 1.05);
  gauge.needles_per_inch = 0;
  EXPECT_EQ(check_gauge(gauge), "the gauge (needles per inch) must be positive");
}

}  // namespace
}  // namespace planner
