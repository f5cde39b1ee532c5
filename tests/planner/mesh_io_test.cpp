#include "planner/mesh/mesh_io.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <sstream>

#include "tests/test_support.hpp"

namespace planner {
namespace {

// Two triangles sharing an edge, consistently oriented: the should-pass twin.
const char* kGoodPair =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "f 1 2 3\nf 1 3 4\n";

std::vector<std::string> messages(const knitout::DiagnosticSink& sink) {
  std::vector<std::string> out;
  for (const auto& d : sink.diagnostics()) out.push_back(knitout::format(d));
  return out;
}

struct Checked {
  bool ok;
  std::vector<std::string> messages;
};

Checked check_obj(const std::string& text) {
  knitout::DiagnosticSink sink;
  std::istringstream in(text);
  auto mesh = read_polygon_soup(in, "obj", "m.obj", sink);
  if (!mesh) return {false, messages(sink)};
  const bool ok = check_mesh(*mesh, "m.obj", sink);
  return {ok, messages(sink)};
}

TEST(MeshIoTest, AcceptsConsistentlyOrientedPair) {
  const auto result = check_obj(kGoodPair);
  EXPECT_TRUE(result.ok);
  EXPECT_TRUE(result.messages.empty());
}

TEST(MeshIoTest, RejectsInconsistentOrientationNamingBothFaces) {
  const auto result = check_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 4 3\n");
  ASSERT_FALSE(result.ok);
  ASSERT_EQ(result.messages.size(), 1u);
  EXPECT_EQ(result.messages[0],
            "m.obj: error: [P012] face 1 and face 2 both run from vertex 3 to vertex 1: their "
            "orientations disagree; flip one of them so the normals point to the same side");
}

TEST(MeshIoTest, RejectsNonManifoldEdgeNamingItsFaces) {
  const auto result =
      check_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 3 1 5\n");
  ASSERT_FALSE(result.ok);
  ASSERT_FALSE(result.messages.empty());
  EXPECT_EQ(result.messages[0],
            "m.obj: error: [P011] edge between vertex 1 and vertex 3 is shared by 3 faces (1, 2, "
            "3); an edge may border at most 2 faces");
}

TEST(MeshIoTest, RejectsPinchedVertex) {
  // Two triangles touching at vertex 1 only: a bow tie.
  const auto result =
      check_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv -1 0 0\nv -1 -1 0\nf 1 2 3\nf 1 4 5\n");
  ASSERT_FALSE(result.ok);
  ASSERT_EQ(result.messages.size(), 1u);
  EXPECT_EQ(result.messages[0],
            "m.obj: error: [P013] vertex 1 joins surface sheets that share no edge there (a pinch "
            "point); split the vertex or connect the sheets");
}

TEST(MeshIoTest, RejectsSeveralComponents) {
  const auto result = check_obj(
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 5 0 0\nv 6 0 0\nv 6 1 0\nv 5 1 0\nf 1 2 3\nf 4 5 6\nf 4 6 7\n");
  ASSERT_FALSE(result.ok);
  ASSERT_EQ(result.messages.size(), 1u);
  EXPECT_EQ(result.messages[0],
            "m.obj: error: [P014] the mesh has 2 separate components: one with face 1 (1 faces); "
            "one with face 2 (2 faces); cut one garment piece at a time (keep a single component)");
}

TEST(MeshIoTest, RejectsUnreferencedVertex) {
  const auto result = check_obj(std::string(kGoodPair) + "v 9 9 9\n");
  ASSERT_FALSE(result.ok);
  ASSERT_EQ(result.messages.size(), 1u);
  EXPECT_EQ(result.messages[0], "m.obj: error: [P015] vertex 5 is used by no face; remove it");
}

TEST(MeshIoTest, RejectsZeroAreaFace) {
  const auto result = check_obj("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 1 1 0\nf 1 2 4\nf 2 3 4\nf 1 3 2\n");
  ASSERT_FALSE(result.ok);
  ASSERT_FALSE(result.messages.empty());
  EXPECT_EQ(result.messages[0],
            "m.obj: error: [P010] face 3 has zero area (its corners coincide or lie on a line)");
}

TEST(MeshIoTest, RejectsFaceUsingAVertexTwice) {
  PolygonMesh mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.faces = {{0, 1, 2, 1}, {0, 2, 3}};
  knitout::DiagnosticSink sink;
  EXPECT_FALSE(check_mesh(mesh, "m.obj", sink));
  ASSERT_FALSE(sink.diagnostics().empty());
  EXPECT_EQ(knitout::format(sink.diagnostics()[0]),
            "m.obj: error: [P010] face 1 uses vertex 2 twice; remove the face or the repeated "
            "corner");
}

TEST(MeshIoTest, RejectsEmptyMesh) {
  const auto result = check_obj("v 0 0 0\n");
  ASSERT_FALSE(result.ok);
  EXPECT_EQ(result.messages.at(0),
            "m.obj: error: [P002] the mesh has no faces (1 vertices); a surface is needed");
}

TEST(MeshIoTest, CapsMessagesPerKind) {
  std::string text = kGoodPair;
  for (int i = 0; i < 13; ++i) text += "v 9 9 " + std::to_string(i) + "\n";
  const auto result = check_obj(text);
  ASSERT_FALSE(result.ok);
  ASSERT_EQ(result.messages.size(), 11u);
  EXPECT_EQ(result.messages.back(),
            "m.obj: error: [P015] 3 more unreferenced vertices not listed (13 in all)");
}

TEST(MeshIoTest, ReadsOffAndConvertsUnits) {
  const auto dir = wearknit::test::make_temp_dir("mesh_io");
  wearknit::test::write_file(dir / "quad.off",
                             "OFF\n4 1 0\n0 0 0\n2 0 0\n2 1 0\n0 1 0\n4 0 1 2 3\n");
  knitout::DiagnosticSink sink;
  auto mesh = load_mesh((dir / "quad.off").string(), {*mm_per_unit("cm"), 2.0}, sink);
  ASSERT_TRUE(mesh.has_value()) << knitout::format(sink.diagnostics().at(0));
  ASSERT_EQ(mesh->faces.size(), 1u);
  EXPECT_EQ(mesh->faces[0].size(), 4u);
  const Vec3 size = bounding_box_size(*mesh);
  EXPECT_DOUBLE_EQ(size.x(), 40.0);  // 2 cm * scale 2 = 40 mm
  EXPECT_DOUBLE_EQ(size.y(), 20.0);
  std::filesystem::remove_all(dir);
}

TEST(MeshIoTest, ReportsMissingFileAndUnknownFormat) {
  knitout::DiagnosticSink sink;
  EXPECT_FALSE(read_polygon_soup("/nonexistent/garment.obj", sink).has_value());
  EXPECT_FALSE(read_polygon_soup("garment.xyz", sink).has_value());
  ASSERT_EQ(sink.diagnostics().size(), 2u);
  EXPECT_EQ(knitout::format(sink.diagnostics()[0]),
            "/nonexistent/garment.obj: error: [P001] cannot open file");
  EXPECT_EQ(knitout::format(sink.diagnostics()[1]),
            "garment.xyz: error: [P001] cannot read a mesh from a '.xyz' file; use OBJ, OFF, PLY "
            "or STL (the format is taken from the extension)");
}

TEST(MeshIoTest, UnitsAreMillimetresCentimetresOrMetres) {
  EXPECT_EQ(mm_per_unit("mm"), 1.0);
  EXPECT_EQ(mm_per_unit("cm"), 10.0);
  EXPECT_EQ(mm_per_unit("m"), 1000.0);
  EXPECT_FALSE(mm_per_unit("inch").has_value());
}

// What the scan before OpenMesh finds (mesh_scan.hpp): each fault its own
// code, with the line and the element, and nothing read past it.
Checked check_text(const std::string& text, const std::string& ext) {
  knitout::DiagnosticSink sink;
  std::istringstream in(text);
  auto mesh = read_polygon_soup(in, ext, "m." + ext, sink);
  if (!mesh) return {false, messages(sink)};
  const bool ok = check_mesh(*mesh, "m." + ext, sink);
  return {ok, messages(sink)};
}

TEST(MeshScanTest, NamesNonFiniteCoordinatesAndTheirLines) {
  const auto result =
      check_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv nan 0 1\nv 0 inf 0\nv 0 0 1e999\nf 1 2 3\n", "obj");
  ASSERT_FALSE(result.ok);
  ASSERT_EQ(result.messages.size(), 3u);
  EXPECT_EQ(result.messages[0],
            "m.obj:4: error: [P003] vertex 4 has a coordinate that is not a finite number (`nan`)");
  EXPECT_EQ(result.messages[1],
            "m.obj:5: error: [P003] vertex 5 has a coordinate that is not a finite number (`inf`)");
  EXPECT_EQ(result.messages[2],
            "m.obj:6: error: [P003] vertex 6 has a coordinate that is not a "
            "finite number (`1e999`)");
}

TEST(MeshScanTest, NamesCornersThatNameNoVertex) {
  const auto obj = check_text(std::string(kGoodPair) + "f 1 2 99\nf 0 1 2\nf 1 2 -9\n", "obj");
  ASSERT_FALSE(obj.ok);
  ASSERT_EQ(obj.messages.size(), 3u);
  EXPECT_EQ(obj.messages[0],
            "m.obj:7: error: [P005] face 3 refers to vertex 99; the file has 4 vertices");
  EXPECT_EQ(obj.messages[1],
            "m.obj:8: error: [P005] face 4 has a corner 0; OBJ numbers vertices from 1");
  EXPECT_EQ(obj.messages[2],
            "m.obj:9: error: [P005] face 5 refers to vertex -9 (-4); the file has 4 vertices");
  // Negative corners count back from the last vertex: the twin passes.
  EXPECT_TRUE(check_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nf -3 -2 -1\n", "obj").ok);

  const auto off = check_text("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n3 1 3 4\n", "off");
  ASSERT_FALSE(off.ok);
  ASSERT_EQ(off.messages.size(), 1u);
  EXPECT_EQ(off.messages[0],
            "m.off:8: error: [P005] face 2 refers to vertex 4 (OFF numbers "
            "vertices from 0); the file has 4 vertices");
}

TEST(MeshScanTest, HeadersClaimingMoreThanTheFileHoldsAreRefusedBeforeReading) {
  const auto off = check_text("OFF\n100000000 200000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "off");
  ASSERT_FALSE(off.ok);
  ASSERT_EQ(off.messages.size(), 1u);
  EXPECT_EQ(off.messages[0],
            "m.off:2: error: [P006] the header claims 100000000 vertices and 200000000 faces, more "
            "than the 26 bytes after it can hold; the header is wrong or the file is cut short");
  // Within what the size allows, a short file says where it ends.
  const auto cut = check_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n" + std::string(8, '\n'), "off");
  ASSERT_FALSE(cut.ok);
  EXPECT_EQ(cut.messages.at(0),
            "m.off:13: error: [P006] the file ends after 0 of the 1 face its header claims");

  const auto ply = check_text(
      "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n",
      "ply");
  ASSERT_FALSE(ply.ok);
  EXPECT_EQ(ply.messages.at(0),
            "m.ply:3: error: [P006] the header claims 1000000000 vertex elements, more than the 0 "
            "bytes after it can hold; the header is wrong or the file is cut short");

  std::string stl(80, 'x');
  const std::uint32_t triangles = 100000000;
  stl.append(reinterpret_cast<const char*>(&triangles), 4);
  stl.append(100, '\0');
  const auto binary = check_text(stl, "stl");
  ASSERT_FALSE(binary.ok);
  EXPECT_EQ(binary.messages.at(0),
            "m.stl: error: [P006] the header claims 100000000 triangles "
            "(5000000084 bytes) but the file has 184 bytes");
}

TEST(MeshScanTest, MalformedLinesAndShortFacesAreNamed) {
  const auto result = check_text("v 0 0\nv 1 0 zero\nv 1 1 0\nf 1 2\nf 1 x 3\n", "obj");
  ASSERT_FALSE(result.ok);
  ASSERT_EQ(result.messages.size(), 4u);
  EXPECT_EQ(result.messages[0],
            "m.obj:1: error: [P004] vertex 1 has 2 coordinates; a vertex needs three numbers");
  EXPECT_EQ(result.messages[1], "m.obj:2: error: [P004] vertex 2: `zero` is not a number");
  EXPECT_EQ(result.messages[2],
            "m.obj:4: error: [P010] face 1 has 2 corners; a face needs at least 3");
  EXPECT_EQ(result.messages[3], "m.obj:5: error: [P004] face 2: corner `x` is not a vertex number");
}

// OpenMesh's PLY reader loops for ever on a header line it does not know
// and on a header without end_header: the scan names the line first.
TEST(MeshScanTest, PlyHeaderLinesOpenMeshCannotReadAreNamed) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n";
  const auto unknown = check_text(head + "elemenle_endian 1.0\nend_header\n", "ply");
  ASSERT_FALSE(unknown.ok);
  EXPECT_EQ(unknown.messages.at(0),
            "m.ply:5: error: [P004] PLY header: `elemenle_endian 1.0` is not a header line "
            "(format, element, property, comment, end_header)");
  const auto unended = check_text(head, "ply");
  ASSERT_FALSE(unended.ok);
  EXPECT_EQ(unended.messages.at(0), "m.ply:4: error: [P004] PLY header: no `end_header` line");
  const auto type = check_text(head + "property quaternion q\nend_header\n", "ply");
  ASSERT_FALSE(type.ok);
  EXPECT_EQ(type.messages.at(0).substr(0, 44), "m.ply:5: error: [P004] PLY header: `property");
}

// Every format's well-formed twin reads: the scan refuses nothing valid.
TEST(MeshScanTest, WellFormedFilesOfEveryFormatRead) {
  EXPECT_TRUE(
      check_text("# c\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3//1\n", "obj")
          .ok);
  EXPECT_TRUE(check_text("OFF 3 1 0\n# comment\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n", "off").ok);
  EXPECT_TRUE(check_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty "
                         "float y\nproperty float z\nelement face 1\nproperty list uchar int "
                         "vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
                         "ply")
                  .ok);
  EXPECT_TRUE(check_text("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                         "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n",
                         "stl")
                  .ok);
}

// A face that names a vertex the soup does not have (a PLY body, where the
// scan reads only the header) is named as such by check_mesh.
TEST(MeshScanTest, CheckMeshNamesACornerOutOfRange) {
  PolygonMesh mesh;
  mesh.positions = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
  mesh.faces = {{0, 1, 2}, {0, 2, 7}};
  knitout::DiagnosticSink sink;
  EXPECT_FALSE(check_mesh(mesh, "m.ply", sink));
  ASSERT_FALSE(sink.diagnostics().empty());
  EXPECT_EQ(knitout::format(sink.diagnostics()[0]),
            "m.ply: error: [P005] face 2 refers to vertex 8; the mesh has 3 vertices");
}

TEST(MeshIoTest, WrittenObjReadsBack) {
  knitout::DiagnosticSink sink;
  std::istringstream in(kGoodPair);
  auto mesh = read_polygon_soup(in, "obj", "m.obj", sink);
  ASSERT_TRUE(mesh);
  std::ostringstream out;
  write_obj(out, *mesh, "header");
  std::istringstream back(out.str());
  auto again = read_polygon_soup(back, "obj", "again.obj", sink);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->faces, mesh->faces);
  EXPECT_EQ(again->positions.size(), mesh->positions.size());
  EXPECT_EQ(out.str().substr(0, 9), "# header\n");
}

}  // namespace
}  // namespace planner
