#include "planner/mesh/mesh_io.hpp"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <istream>
#include <iterator>
#include <map>
#include <numeric>
#include <ostream>
#include <sstream>
#include <unordered_map>

#include "planner/common/index.hpp"
#include "planner/mesh/kind_reporter.hpp"
#include "planner/mesh/mesh_scan.hpp"
#include "planner/mesh/soup.hpp"

namespace planner {

namespace {

using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::VertexHandle;
using OpenMesh::IO::BaseImporter;

// Collects the polygon soup exactly as the reader delivers it: OpenMesh's
// own mesh kernels would silently drop non-manifold faces, and those are
// exactly what the checks must name.
class SoupImporter final : public BaseImporter {
 public:
  explicit SoupImporter(PolygonMesh& mesh) : mesh_(mesh) {}

  VertexHandle add_vertex(const OpenMesh::Vec3f& p) override {
    return add_vertex(OpenMesh::Vec3d(p[0], p[1], p[2]));
  }
  VertexHandle add_vertex(const OpenMesh::Vec3d& p) override {
    mesh_.positions.emplace_back(p[0], p[1], p[2]);
    return VertexHandle(static_cast<int>(mesh_.positions.size()) - 1);
  }
  VertexHandle add_vertex() override { return add_vertex(OpenMesh::Vec3d(0, 0, 0)); }
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(const VHandles& indices) override {
    std::vector<int> face;
    face.reserve(indices.size());
    for (const auto& vh : indices) face.push_back(vh.idx());
    mesh_.faces.push_back(std::move(face));
    return FaceHandle(static_cast<int>(mesh_.faces.size()) - 1);
  }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<OpenMesh::Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_point(VertexHandle vh, const OpenMesh::Vec3f& p) override {
    if (vh.idx() >= 0 && at(vh.idx()) < mesh_.positions.size()) {
      mesh_.positions[at(vh.idx())] = Vec3(p[0], p[1], p[2]);
    }
  }
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(VertexHandle, const OpenMesh::Vec3d&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_color(VertexHandle, const OpenMesh::Vec4f&) override {}
  void set_texcoord(VertexHandle, const OpenMesh::Vec2f&) override {}
  void set_status(VertexHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const OpenMesh::Vec2f&) override {}
  void set_texcoord(VertexHandle, const OpenMesh::Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const OpenMesh::Vec3f&) override {}
  void set_status(HalfedgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec3f&) override {}
  void set_color(EdgeHandle, const OpenMesh::Vec4f&) override {}
  void set_status(EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_normal(FaceHandle, const OpenMesh::Vec3d&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec3uc&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec4uc&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec3f&) override {}
  void set_color(FaceHandle, const OpenMesh::Vec4f&) override {}
  void set_status(FaceHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}
  size_t n_vertices() const override { return mesh_.positions.size(); }
  size_t n_faces() const override { return mesh_.faces.size(); }
  size_t n_edges() const override { return 0; }

 private:
  PolygonMesh& mesh_;
};

// OpenMesh prints its own complaints on std::cerr; ours are diagnostics.
class QuietOpenMesh {
 public:
  QuietOpenMesh() {
    ::omerr().disable();
    ::omlog().disable();
  }
  ~QuietOpenMesh() {
    ::omerr().enable();
    ::omlog().enable();
  }
  QuietOpenMesh(const QuietOpenMesh&) = delete;
  QuietOpenMesh& operator=(const QuietOpenMesh&) = delete;
};

// A polygon soup from one OpenMesh read (`read(importer, options)`), with
// OpenMesh's own messages kept quiet; nullopt when the read fails.
template <typename Read>
std::optional<PolygonMesh> import_soup(Read read) {
  PolygonMesh mesh;
  SoupImporter importer(mesh);
  OpenMesh::IO::Options options;
  QuietOpenMesh quiet;
  if (!read(importer, options)) return std::nullopt;
  return mesh;
}

std::string lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

bool supported_extension(const std::string& ext) {
  return ext == "obj" || ext == "off" || ext == "ply" || ext == "stl";
}

std::string vname(int v) {
  return "vertex " + std::to_string(v + 1);
}
std::string fname(int f) {
  return "face " + std::to_string(f + 1);
}

}  // namespace

std::optional<double> mm_per_unit(std::string_view units) {
  if (units == "mm") return 1.0;
  if (units == "cm") return 10.0;
  if (units == "m") return 1000.0;
  return std::nullopt;
}

std::optional<PolygonMesh> read_polygon_soup(const std::string& path,
                                             knitout::DiagnosticSink& sink) {
  const std::string ext = lower(std::filesystem::path(path).extension().string().substr(
      std::min<std::size_t>(1, std::filesystem::path(path).extension().string().size())));
  if (!supported_extension(ext)) {
    sink.error(path, 0, 0, "P001",
               "cannot read a mesh from a '." + ext +
                   "' file; use OBJ, OFF, PLY or STL (the format is taken from the extension)");
    return std::nullopt;
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    sink.error(path, 0, 0, "P001", "cannot open file");
    return std::nullopt;
  }
  std::string bytes;
  {
    std::ifstream in(path, std::ios::binary);
    if (in) bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (!in && !in.eof()) {
      sink.error(path, 0, 0, "P001", "cannot read file");
      return std::nullopt;
    }
  }
  ScanResult scanned = scan_mesh_bytes(bytes, ext, path, sink);
  if (!scanned.ok) return std::nullopt;
  if (scanned.soup) return std::move(scanned.soup);
  auto mesh = import_soup([&](SoupImporter& importer, OpenMesh::IO::Options& options) {
    return OpenMesh::IO::IOManager().read(path, importer, options);
  });
  if (!mesh)
    sink.error(path, 0, 0, "P001", "cannot read the file as " + ext + " (malformed or truncated)");
  return mesh;
}

std::optional<PolygonMesh> read_polygon_soup(std::istream& in, std::string_view extension,
                                             const std::string& source,
                                             knitout::DiagnosticSink& sink) {
  const std::string ext = lower(extension);
  if (!supported_extension(ext)) {
    sink.error(source, 0, 0, "P001", "cannot read a mesh in format '" + ext + "'");
    return std::nullopt;
  }
  const std::string bytes(std::istreambuf_iterator<char>(in), {});
  ScanResult scanned = scan_mesh_bytes(bytes, ext, source, sink);
  if (!scanned.ok) return std::nullopt;
  if (scanned.soup) return std::move(scanned.soup);
  std::istringstream copy(bytes, std::ios::in | std::ios::binary);
  auto mesh = import_soup([&](SoupImporter& importer, OpenMesh::IO::Options& options) {
    return OpenMesh::IO::IOManager().read(copy, "." + ext, importer, options);
  });
  if (!mesh) sink.error(source, 0, 0, "P001", "cannot read the stream as " + ext);
  return mesh;
}

namespace {

// P003: coordinates that are not finite numbers.
void check_coordinates(const PolygonMesh& mesh, const std::string& source,
                       knitout::DiagnosticSink& sink) {
  KindReporter bad(sink, source, "P003", "bad coordinates");
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    if (!mesh.positions[v].allFinite()) {
      bad.report(vname(static_cast<int>(v)) + " has a coordinate that is not a finite number");
    }
  }
}

// Faces of less area are degenerate: 1e-14 of the squared diagonal of the
// finite positions' bounding box, so the test does not depend on the units.
double area_epsilon(const PolygonMesh& mesh) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  for (const Vec3& p : mesh.positions) {
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double diagonal = mesh.positions.empty() ? 0.0 : (hi - lo).norm();
  return 1e-14 * diagonal * diagonal;
}

// P005 (a corner naming no vertex) and P010 (fewer than 3 corners, a
// corner used twice, zero area). Returns per face whether the connectivity
// checks can use it: all but those with bad corners (a zero-area face still
// connects).
std::vector<bool> check_faces(const PolygonMesh& mesh, const std::string& source,
                              knitout::DiagnosticSink& sink) {
  const int nv = static_cast<int>(mesh.positions.size());
  const double epsilon = area_epsilon(mesh);
  std::vector<bool> usable(mesh.faces.size(), true);
  KindReporter degenerate(sink, source, "P010", "degenerate faces");
  KindReporter corners(sink, source, "P005", "face corners naming no vertex");
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    const std::string name = fname(static_cast<int>(f));
    const auto missing =
        std::find_if(face.begin(), face.end(), [nv](int v) { return v < 0 || v >= nv; });
    if (missing != face.end()) {
      corners.report(name + " refers to " + vname(*missing) + "; the mesh has " +
                     std::to_string(nv) + (nv == 1 ? " vertex" : " vertices"));
      usable[f] = false;
      continue;
    }
    if (face.size() < 3) {
      degenerate.report(name + " has " + std::to_string(face.size()) +
                        (face.size() == 1 ? " corner" : " corners") + "; a face needs at least 3");
      usable[f] = false;
      continue;
    }
    std::vector<int> sorted = face;
    std::sort(sorted.begin(), sorted.end());
    auto dup = std::adjacent_find(sorted.begin(), sorted.end());
    if (dup != sorted.end()) {
      degenerate.report(name + " uses " + vname(*dup) +
                        " twice; remove the face or the repeated corner");
      usable[f] = false;
      continue;
    }
    if (!(vector_area(mesh, face).norm() > epsilon)) {
      degenerate.report(name + " has zero area (its corners coincide or lie on a line)");
    }
  }
  return usable;
}

// P011 (an edge of more than two faces) and P012 (two faces that run the
// same way along their common edge), in vertex order so the messages do not
// depend on hashing.
void check_edges(const PolygonMesh& mesh, const std::vector<bool>& usable,
                 const std::string& source, knitout::DiagnosticSink& sink) {
  // Directed half-edges and undirected edges with the faces on them.
  std::unordered_map<std::uint64_t, std::vector<int>> directed;
  std::unordered_map<std::uint64_t, std::vector<int>> undirected;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!usable[f]) continue;
    const auto& face = mesh.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i];
      const int b = face[(i + 1) % face.size()];
      const std::pair<int, int> edge = undirected_edge(a, b);
      directed[pair_key(a, b)].push_back(static_cast<int>(f));
      undirected[pair_key(edge.first, edge.second)].push_back(static_cast<int>(f));
    }
  }
  KindReporter nonmanifold(sink, source, "P011", "non-manifold edges");
  KindReporter orientation(sink, source, "P012", "inconsistently oriented edges");
  std::vector<std::uint64_t> keys;
  keys.reserve(undirected.size());
  for (const auto& entry : undirected) keys.push_back(entry.first);
  std::sort(keys.begin(), keys.end());
  for (const std::uint64_t key : keys) {
    const std::vector<int>& faces = undirected.at(key);
    const std::pair<int, int> edge{static_cast<int>(key >> 32),
                                   static_cast<int>(key & 0xffffffffu)};
    const std::string ename = "edge between " + vname(edge.first) + " and " + vname(edge.second);
    if (faces.size() > 2) {
      std::string list;
      for (std::size_t i = 0; i < faces.size() && i < 6; ++i) {
        list += (i == 0 ? "" : ", ") + std::to_string(faces[i] + 1);
      }
      if (faces.size() > 6) list += ", ...";
      nonmanifold.report(ename + " is shared by " + std::to_string(faces.size()) + " faces (" +
                         list + "); an edge may border at most 2 faces");
      continue;
    }
    for (const int dir : {0, 1}) {
      const int a = dir == 0 ? edge.first : edge.second;
      const int b = dir == 0 ? edge.second : edge.first;
      auto it = directed.find(pair_key(a, b));
      if (it != directed.end() && it->second.size() == 2) {
        orientation.report(fname(it->second[0]) + " and " + fname(it->second[1]) +
                           " both run from " + vname(a) + " to " + vname(b) +
                           ": their orientations disagree; flip one of them so the normals "
                           "point to the same side");
      }
    }
  }
}

// P013 (a vertex whose corners form more than one fan: a pinch point) and
// P015 (a vertex no face uses).
void check_vertices(const PolygonMesh& mesh, const std::vector<bool>& usable,
                    const std::string& source, knitout::DiagnosticSink& sink) {
  const std::size_t nv = mesh.positions.size();
  const std::vector<int> corner_start = corner_starts(mesh);
  UnionFind corners = corner_fans(mesh, corner_start, usable);
  std::vector<int> fan_root(nv, -1);
  std::vector<int> fans(nv, 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!usable[f]) continue;
    for (std::size_t i = 0; i < mesh.faces[f].size(); ++i) {
      const int root = corners.find(corner_start[f] + static_cast<int>(i));
      const std::size_t v = at(mesh.faces[f][i]);
      if (fan_root[v] == -1) {
        fan_root[v] = root;
        fans[v] = 1;
      } else if (fan_root[v] != root && fans[v] == 1) {
        fans[v] = 2;  // at least two fans
      }
    }
  }
  KindReporter nonmanifold(sink, source, "P013", "non-manifold vertices");
  KindReporter unreferenced(sink, source, "P015", "unreferenced vertices");
  for (std::size_t v = 0; v < nv; ++v) {
    if (fans[v] >= 2) {
      nonmanifold.report(vname(static_cast<int>(v)) +
                         " joins surface sheets that share no edge there (a pinch point); "
                         "split the vertex or connect the sheets");
    }
  }
  std::vector<bool> referenced(nv, false);
  for (const auto& face : mesh.faces) {
    for (int v : face) {
      if (v >= 0 && at(v) < nv) referenced[at(v)] = true;
    }
  }
  for (std::size_t v = 0; v < nv; ++v) {
    if (!referenced[v])
      unreferenced.report(vname(static_cast<int>(v)) + " is used by no face; remove it");
  }
}

// P014: more than one connected component, each named by its first face.
void check_components(const PolygonMesh& mesh, const std::vector<bool>& usable,
                      const std::string& source, knitout::DiagnosticSink& sink) {
  UnionFind vertices = vertex_components(mesh, usable);
  std::map<int, std::pair<int, int>> components;  // root -> (first face, face count)
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!usable[f]) continue;
    const int root = vertices.find(mesh.faces[f][0]);
    auto [it, inserted] = components.emplace(root, std::make_pair(static_cast<int>(f), 0));
    ++it->second.second;
  }
  if (components.size() <= 1) return;
  std::vector<std::pair<int, int>> list;
  for (const auto& [root, info] : components) list.push_back(info);
  std::sort(list.begin(), list.end());
  std::string text;
  for (std::size_t i = 0; i < list.size() && i < 5; ++i) {
    text += (i == 0 ? "" : "; ") + std::string("one with ") + fname(list[i].first) + " (" +
            std::to_string(list[i].second) + " faces)";
  }
  if (list.size() > 5) text += "; ...";
  sink.error(source, 0, 0, "P014",
             "the mesh has " + std::to_string(components.size()) + " separate components: " + text +
                 "; cut one garment piece at a time (keep a single component)");
}

}  // namespace

bool check_mesh(const PolygonMesh& mesh, const std::string& source, knitout::DiagnosticSink& sink) {
  const std::size_t errors_before = sink.error_count();
  if (mesh.faces.empty()) {
    sink.error(source, 0, 0, "P002",
               "the mesh has no faces (" + std::to_string(mesh.positions.size()) +
                   " vertices); a surface is needed");
    return false;
  }
  check_coordinates(mesh, source, sink);
  const std::vector<bool> usable = check_faces(mesh, source, sink);
  check_edges(mesh, usable, source, sink);
  check_vertices(mesh, usable, source, sink);
  check_components(mesh, usable, source, sink);
  return sink.error_count() == errors_before;
}

std::optional<PolygonMesh> load_mesh(const std::string& path, const LoadParams& params,
                                     knitout::DiagnosticSink& sink) {
  auto mesh = read_polygon_soup(path, sink);
  if (!mesh) return std::nullopt;
  if (!check_mesh(*mesh, path, sink)) return std::nullopt;
  const double factor = params.mm_per_unit * params.scale;
  for (Vec3& p : mesh->positions) p *= factor;
  return mesh;
}

void write_obj(std::ostream& out, const PolygonMesh& mesh, std::string_view header) {
  std::size_t start = 0;
  while (start < header.size()) {
    std::size_t end = header.find('\n', start);
    if (end == std::string_view::npos) end = header.size();
    out << "# " << header.substr(start, end - start) << '\n';
    start = end + 1;
  }
  char buffer[96];
  for (const Vec3& p : mesh.positions) {
    std::snprintf(buffer, sizeof buffer, "v %.9g %.9g %.9g\n", p.x(), p.y(), p.z());
    out << buffer;
  }
  for (const auto& face : mesh.faces) {
    out << 'f';
    for (int v : face) out << ' ' << (v + 1);
    out << '\n';
  }
}

Vec3 bounding_box_size(const PolygonMesh& mesh) {
  if (mesh.positions.empty()) return Vec3::Zero();
  Vec3 lo = mesh.positions.front();
  Vec3 hi = lo;
  for (const Vec3& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return hi - lo;
}

}  // namespace planner
