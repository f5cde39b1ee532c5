// Sampling for the remesher (remesh.hpp): the input triangulated and
// brought to the sample spacing with OpenMesh's decimater, 1-to-4
// subdivision and midpoint splits.
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModEdgeLengthT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <algorithm>
#include <map>
#include <optional>
#include <stdexcept>

#include "knitout/diagnostic.hpp"
#include "planner/common/index.hpp"
#include "planner/mesh/decimation_mesh.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/soup.hpp"
#include "planner/proxy/remesh.hpp"

namespace planner {

namespace {

using TriMesh = DecimationMesh;

TriMesh to_trimesh(const PolygonMesh& input) {
  TriMesh tri;
  std::vector<TriMesh::VertexHandle> handles;
  handles.reserve(input.positions.size());
  for (const Vec3& p : input.positions) {
    handles.push_back(tri.add_vertex(TriMesh::Point(p.x(), p.y(), p.z())));
  }
  for (const auto& face : input.faces) {
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      const auto fh =
          tri.add_face(handles[at(face[0])], handles[at(face[i])], handles[at(face[i + 1])]);
      if (!fh.is_valid()) throw std::logic_error("resample: checked mesh rejected by OpenMesh");
    }
  }
  return tri;
}

PolygonMesh from_trimesh(TriMesh& tri) {
  tri.garbage_collection();
  PolygonMesh out;
  out.positions.reserve(tri.n_vertices());
  for (const auto vh : tri.vertices()) {
    const auto& p = tri.point(vh);
    out.positions.emplace_back(p[0], p[1], p[2]);
  }
  for (const auto fh : tri.faces()) {
    std::vector<int> face;
    for (const auto vh : tri.fv_range(fh)) face.push_back(vh.idx());
    out.faces.push_back(std::move(face));
  }
  return out;
}

// Shortest edges collapse first until none is shorter than `target`; normal
// flips are refused and OpenMesh's link condition keeps the topology. With
// `guard_aspect`, a collapse may also not make the worst triangle around it
// thinner than aspect ratio 10 unless it was already: slower, and used only
// when the plain pass leaves a zero-area sliver (which happened at one scale
// of a mesh and not at another, and made the samples depend on the units).
PolygonMesh decimate(const PolygonMesh& input, double target, bool guard_aspect) {
  TriMesh tri = to_trimesh(input);
  tri.update_face_normals();
  tri.update_vertex_normals();
  {
    using Decimater = OpenMesh::Decimater::DecimaterT<TriMesh>;
    using EdgeLength = OpenMesh::Decimater::ModEdgeLengthT<TriMesh>::Handle;
    using NormalFlipping = OpenMesh::Decimater::ModNormalFlippingT<TriMesh>::Handle;
    using AspectRatio = OpenMesh::Decimater::ModAspectRatioT<TriMesh>::Handle;
    Decimater decimater(tri);
    EdgeLength edge_length;
    NormalFlipping normal_flipping;
    AspectRatio aspect_ratio;
    decimater.add(edge_length);
    decimater.add(normal_flipping);
    if (guard_aspect) {
      decimater.add(aspect_ratio);
      decimater.module(aspect_ratio).set_binary(true);
      decimater.module(aspect_ratio).set_aspect_ratio(10.0);
    }
    decimater.module(edge_length).set_edge_length(target);
    decimater.module(edge_length).set_binary(false);
    decimater.module(normal_flipping).set_max_normal_deviation(60.0);
    decimater.initialize();
    decimater.decimate();
  }
  return from_trimesh(tri);
}

// `decimate`, checked; once more with the aspect guard if the plain pass
// leaves a degenerate face; nothing if that fails too.
std::optional<PolygonMesh> checked_decimation(const PolygonMesh& input, double target) {
  for (const bool guard_aspect : {false, true}) {
    PolygonMesh decimated = decimate(input, target, guard_aspect);
    knitout::DiagnosticSink sink;
    if (check_mesh(decimated, "resample", sink)) return decimated;
  }
  return std::nullopt;
}

// Every edge longer than `max_length` is split at its midpoint (with the
// triangles on both sides) until none is: the fields compare neighbouring
// samples, and a sample edge longer than half a lattice step can span two
// lattice steps, which the extraction cannot connect (Instant Meshes
// subdivides its input the same way before solving).
PolygonMesh split_long_edges(const PolygonMesh& input, double max_length) {
  TriMesh tri = to_trimesh(input);
  const double limit = max_length * max_length;
  for (bool split = true; split;) {
    split = false;
    const std::size_t edges = tri.n_edges();
    for (std::size_t e = 0; e < edges; ++e) {
      const auto eh = tri.edge_handle(static_cast<int>(e));
      const auto heh = tri.halfedge_handle(eh, 0);
      const auto& a = tri.point(tri.from_vertex_handle(heh));
      const auto& b = tri.point(tri.to_vertex_handle(heh));
      if ((b - a).sqrnorm() <= limit) continue;
      tri.split(eh, TriMesh::Point((a + b) * 0.5));
      split = true;
    }
  }
  return from_trimesh(tri);
}

// 1-to-4 midpoint subdivision of a triangle mesh (positions unchanged).
PolygonMesh subdivide(const PolygonMesh& mesh) {
  PolygonMesh out;
  out.positions = mesh.positions;
  std::map<std::pair<int, int>, int> midpoint;
  auto mid = [&](int a, int b) {
    const auto key = undirected_edge(a, b);
    auto it = midpoint.find(key);
    if (it != midpoint.end()) return it->second;
    out.positions.push_back(0.5 * (mesh.positions[at(a)] + mesh.positions[at(b)]));
    const int id = static_cast<int>(out.positions.size()) - 1;
    midpoint.emplace(key, id);
    return id;
  };
  for (const auto& f : mesh.faces) {
    const int ab = mid(f[0], f[1]);
    const int bc = mid(f[1], f[2]);
    const int ca = mid(f[2], f[0]);
    out.faces.push_back({f[0], ab, ca});
    out.faces.push_back({ab, f[1], bc});
    out.faces.push_back({ca, bc, f[2]});
    out.faces.push_back({ab, bc, ca});
  }
  return out;
}

}  // namespace

PolygonMesh resample(const PolygonMesh& input, double target_mm, double keep_above) {
  PolygonMesh tri;
  tri.positions = input.positions;
  for (const auto& face : input.faces) {
    for (std::size_t i = 1; i + 1 < face.size(); ++i)
      tri.faces.push_back({face[0], face[i], face[i + 1]});
  }
  // Coarse input is refined; input within a factor 2 of the target is used
  // as it is; only a much finer one is decimated (the decimater is the
  // slowest step, so it is kept for the meshes that need it).
  while (mean_edge_length(tri) > 2.0 * target_mm && tri.faces.size() < 4000000)
    tri = subdivide(tri);
  if (mean_edge_length(tri) < keep_above * target_mm) {
    // OpenMesh keeps the topology; should a collapse still leave a fold, the
    // finer mesh is the safe answer.
    std::optional<PolygonMesh> decimated = checked_decimation(tri, target_mm);
    if (decimated) tri = std::move(*decimated);
  }
  return tri;
}

PolygonMesh sample_surface(const PolygonMesh& input, double target_mm) {
  PolygonMesh tri = split_long_edges(resample(input, target_mm), 1.25 * target_mm);
  std::size_t edges = 0;
  std::size_t short_edges = 0;
  for (const auto& face : tri.faces) {
    for (std::size_t i = 0; i < face.size(); ++i) {
      const double length =
          (tri.positions[at(face[(i + 1) % face.size()])] - tri.positions[at(face[i])]).norm();
      ++edges;
      if (length < 0.5 * target_mm) ++short_edges;
    }
  }
  if (short_edges * 5 <= edges) return tri;
  std::optional<PolygonMesh> decimated = checked_decimation(tri, 0.7 * target_mm);
  if (!decimated) return tri;
  return split_long_edges(*decimated, 1.25 * target_mm);
}

}  // namespace planner
