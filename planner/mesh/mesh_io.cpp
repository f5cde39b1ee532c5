#include "planner/mesh/mesh_io.hpp"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <istream>
#include <map>
#include <numeric>
#include <ostream>
#include <unordered_map>

#include "planner/common/index.hpp"
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
    if (vh.idx() >= 0 && static_cast<std::size_t>(vh.idx()) < mesh_.positions.size()) {
      mesh_.positions[static_cast<std::size_t>(vh.idx())] = Vec3(p[0], p[1], p[2]);
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

std::string lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

bool supported_extension(const std::string& ext) {
  return ext == "obj" || ext == "off" || ext == "ply" || ext == "stl";
}

// Caps the messages of one kind at 10 and then says how many were left out.
class KindReporter {
 public:
  KindReporter(knitout::DiagnosticSink& sink, const std::string& source, std::string code,
               std::string plural)
      : sink_(sink), source_(source), code_(std::move(code)), plural_(std::move(plural)) {}
  void report(std::string message) {
    ++count_;
    if (count_ <= kMaxShown) sink_.error(source_, 0, 0, code_, std::move(message));
  }
  ~KindReporter() {
    if (count_ > kMaxShown) {
      sink_.error(source_, 0, 0, code_,
                  std::to_string(count_ - kMaxShown) + " more " + plural_ + " not listed (" +
                      std::to_string(count_) + " in all)");
    }
  }
  KindReporter(const KindReporter&) = delete;
  KindReporter& operator=(const KindReporter&) = delete;
  int count() const { return count_; }

 private:
  static constexpr int kMaxShown = 10;
  knitout::DiagnosticSink& sink_;
  const std::string& source_;
  std::string code_;
  std::string plural_;
  int count_ = 0;
};

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
  PolygonMesh mesh;
  SoupImporter importer(mesh);
  OpenMesh::IO::Options options;
  bool ok = false;
  {
    QuietOpenMesh quiet;
    ok = OpenMesh::IO::IOManager().read(path, importer, options);
  }
  if (!ok) {
    sink.error(path, 0, 0, "P001", "cannot read the file as " + ext + " (malformed or truncated)");
    return std::nullopt;
  }
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
  PolygonMesh mesh;
  SoupImporter importer(mesh);
  OpenMesh::IO::Options options;
  bool ok = false;
  {
    QuietOpenMesh quiet;
    ok = OpenMesh::IO::IOManager().read(in, "." + ext, importer, options);
  }
  if (!ok) {
    sink.error(source, 0, 0, "P001", "cannot read the stream as " + ext);
    return std::nullopt;
  }
  return mesh;
}

bool check_mesh(const PolygonMesh& mesh, const std::string& source, knitout::DiagnosticSink& sink) {
  const std::size_t errors_before = sink.error_count();
  const int nv = static_cast<int>(mesh.positions.size());
  const int nf = static_cast<int>(mesh.faces.size());
  if (nf == 0) {
    sink.error(source, 0, 0, "P002",
               "the mesh has no faces (" + std::to_string(nv) + " vertices); a surface is needed");
    return false;
  }
  {
    KindReporter bad(sink, source, "P003", "bad coordinates");
    for (int v = 0; v < nv; ++v) {
      if (!mesh.positions[static_cast<std::size_t>(v)].allFinite()) {
        bad.report(vname(v) + " has a coordinate that is not a finite number");
      }
    }
  }
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  for (const Vec3& p : mesh.positions) {
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double diagonal = nv > 0 ? (hi - lo).norm() : 0.0;
  const double area_epsilon = 1e-14 * diagonal * diagonal;

  std::vector<bool> usable(static_cast<std::size_t>(nf), true);
  {
    KindReporter degenerate(sink, source, "P010", "degenerate faces");
    for (int f = 0; f < nf; ++f) {
      const auto& face = mesh.faces[static_cast<std::size_t>(f)];
      bool range_ok = true;
      for (int v : face) range_ok = range_ok && v >= 0 && v < nv;
      if (face.size() < 3 || !range_ok) {
        degenerate.report(fname(f) + " has " + std::to_string(face.size()) +
                          " corners; a face needs at least 3 distinct vertices");
        usable[static_cast<std::size_t>(f)] = false;
        continue;
      }
      std::vector<int> sorted = face;
      std::sort(sorted.begin(), sorted.end());
      auto dup = std::adjacent_find(sorted.begin(), sorted.end());
      if (dup != sorted.end()) {
        degenerate.report(fname(f) + " uses " + vname(*dup) +
                          " twice; remove the face or the repeated corner");
        usable[static_cast<std::size_t>(f)] = false;
        continue;
      }
      if (!(vector_area(mesh, face).norm() > area_epsilon)) {
        degenerate.report(fname(f) + " has zero area (its corners coincide or lie on a line)");
      }
    }
  }

  // Edge use: directed half-edges and undirected edges with the faces on them.
  std::unordered_map<std::uint64_t, std::vector<int>> directed;
  std::unordered_map<std::uint64_t, std::vector<int>> undirected;
  for (int f = 0; f < nf; ++f) {
    if (!usable[static_cast<std::size_t>(f)]) continue;
    const auto& face = mesh.faces[static_cast<std::size_t>(f)];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i];
      const int b = face[(i + 1) % face.size()];
      directed[pair_key(a, b)].push_back(f);
      const std::pair<int, int> edge = undirected_edge(a, b);
      undirected[pair_key(edge.first, edge.second)].push_back(f);
    }
  }
  {
    KindReporter nonmanifold(sink, source, "P011", "non-manifold edges");
    KindReporter orientation(sink, source, "P012", "inconsistently oriented edges");
    // Reported in vertex order, so the messages do not depend on hashing.
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
  {
    // A vertex is manifold when its corners form one fan: corners that share
    // an edge out of the vertex are joined.
    const std::vector<int> corner_start = corner_starts(mesh);
    UnionFind corners = corner_fans(mesh, corner_start, usable);
    std::vector<int> corner_vertex(at(corner_start.back()), -1);
    for (int f = 0; f < nf; ++f) {
      if (!usable[at(f)]) continue;
      const auto& face = mesh.faces[at(f)];
      for (std::size_t i = 0; i < face.size(); ++i) {
        corner_vertex[at(corner_start[at(f)] + static_cast<int>(i))] = face[i];
      }
    }
    std::vector<int> fan_root(static_cast<std::size_t>(nv), -1);
    std::vector<int> fans(static_cast<std::size_t>(nv), 0);
    for (std::size_t c = 0; c < corner_vertex.size(); ++c) {
      const int v = corner_vertex[c];
      if (v < 0) continue;
      const int root = corners.find(static_cast<int>(c));
      auto& known = fan_root[static_cast<std::size_t>(v)];
      if (known == -1) {
        known = root;
        fans[static_cast<std::size_t>(v)] = 1;
      } else if (known != root && fans[static_cast<std::size_t>(v)] == 1) {
        fans[static_cast<std::size_t>(v)] = 2;  // at least two fans
      }
    }
    KindReporter nonmanifold(sink, source, "P013", "non-manifold vertices");
    KindReporter unreferenced(sink, source, "P015", "unreferenced vertices");
    for (int v = 0; v < nv; ++v) {
      if (fans[static_cast<std::size_t>(v)] >= 2) {
        nonmanifold.report(vname(v) +
                           " joins surface sheets that share no edge there (a pinch point); "
                           "split the vertex or connect the sheets");
      }
    }
    std::vector<bool> referenced(static_cast<std::size_t>(nv), false);
    for (const auto& face : mesh.faces) {
      for (int v : face) {
        if (v >= 0 && v < nv) referenced[static_cast<std::size_t>(v)] = true;
      }
    }
    for (int v = 0; v < nv; ++v) {
      if (!referenced[static_cast<std::size_t>(v)]) {
        unreferenced.report(vname(v) + " is used by no face; remove it");
      }
    }
  }
  {
    UnionFind vertices = vertex_components(mesh, usable);
    std::map<int, std::pair<int, int>> components;  // root -> (first face, face count)
    for (int f = 0; f < nf; ++f) {
      if (!usable[static_cast<std::size_t>(f)]) continue;
      const int root = vertices.find(mesh.faces[static_cast<std::size_t>(f)][0]);
      auto [it, inserted] = components.emplace(root, std::make_pair(f, 0));
      ++it->second.second;
    }
    if (components.size() > 1) {
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
                 "the mesh has " + std::to_string(components.size()) + " separate components: " +
                     text + "; cut one garment piece at a time (keep a single component)");
    }
  }
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
