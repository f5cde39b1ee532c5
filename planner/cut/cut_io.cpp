#include "planner/cut/cut_io.hpp"

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>

#include "knitout/output_file.hpp"
#include "planner/common/index.hpp"
#include "planner/mesh/mesh_io.hpp"

namespace planner {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

json cuts_json(const CutMesh& cut, const CutSummary& summary) {
  json arcs = json::array();
  for (std::size_t i = 0; i < cut.arcs.size(); ++i) {
    const CutArc& arc = cut.arcs[i];
    json edges = json::array();
    for (std::size_t k = 0; k + 1 < arc.vertices.size(); ++k) {
      edges.push_back({arc.vertices[k], arc.vertices[k + 1]});
    }
    arcs.push_back({{"id", i},
                    {"edges", edges},
                    {"length_mm", arc.length_mm},
                    {"closed", arc.closed},
                    {"label", nullptr}});
  }
  return {{"format", "wearknit-cuts 1"},
          {"vertices", "0-based indices of the v lines of proxy.obj"},
          {"cut_edges", summary.cut_edges},
          {"cut_length_mm", summary.cut_length_mm},
          {"arcs", arcs}};
}

json labels_json(const CutMesh& cut) {
  const HalfedgeMesh& q = cut.proxy;
  json sides = json::array();
  json uv = json::array();
  for (int f = 0; f < q.num_faces(); ++f) {
    json d = json::array();
    for (int i = 0; i < q.degree(f); ++i) d.push_back(cut.direction[at(q.face_start(f) + i)]);
    sides.push_back(d);
    uv.push_back({cut.face_uv[at(f)][0], cut.face_uv[at(f)][1]});
  }
  json edges = json::array();
  json motorcycles = json::array();
  for (int e = 0; e < q.num_edges(); ++e) {
    const int h = q.edge_halfedge(e);
    const int t = q.twin(h);
    std::string label = is_course(cut.direction[at(h)]) ? "course" : "wale";
    if (t >= 0 && is_course(cut.direction[at(t)]) != is_course(cut.direction[at(h)])) {
      label += is_course(cut.direction[at(t)]) ? "|course" : "|wale";
    }
    edges.push_back({q.from(h), q.to(h), label});
    if (cut.motorcycle_edges[at(e)] > 0) {
      motorcycles.push_back({q.from(h), q.to(h), cut.motorcycle_edges[at(e)]});
    }
  }
  return {{"format", "wearknit-labels 1"},
          {"directions",
           "per face side i (corner i to corner i+1 of proxy.obj's face): "
           "0 +u course, 1 +v wale, 2 -u course, 3 -v wale"},
          {"seed_face", cut.seed_face},
          {"frame", cut.face_frame},
          {"vanishing_corner", cut.labels.vanishing_corner},
          {"side_directions", sides},
          {"uv", uv},
          {"overlap_count", cut.overlap_count},
          {"edges", edges},
          {"motorcycle_edges", motorcycles},
          {"irregular_vertices", cut.labels.irregular_vertices},
          {"cut_mesh_vertex_source", cut.disc_source}};
}

json report_json(const CutMesh& cut, const CutSummary& s, const CutReport& r) {
  return {{"format", "wearknit-cut-report 1"},
          {"input",
           {{"file", r.input},
            {"units", r.units},
            {"scale", r.scale},
            {"size_mm", {r.input_size_mm.x(), r.input_size_mm.y(), r.input_size_mm.z()}},
            {"vertices", r.input_vertices},
            {"faces", r.input_faces}}},
          {"proxy",
           {{"remeshed", r.remeshed},
            {"method", r.proxy_method},
            {"remesh_failure", r.remesh_failure},
            {"edge_mm", r.proxy_edge_mm},
            {"vertices", cut.proxy.num_vertices()},
            {"faces", cut.proxy.num_faces()},
            {"polygons_split", r.polygons_split},
            {"triangles_paired", r.triangles_paired},
            {"samples", r.samples},
            {"holes_filled", r.holes_filled},
            {"folds_removed", r.folds_removed},
            {"remesh_attempts", r.remesh_attempts}}},
          {"params",
           {{"seed", r.params.seed},
            {"cs", r.params.cs},
            {"co", r.params.co},
            {"vanishing", r.params.vanishing.fewest_irregular ? "regular" : "acute"},
            {"vanishing_slack_deg", r.params.vanishing.slack_deg}}},
          {"irregular_vertices", cut.labels.irregular_vertices},
          {"irregular_vertex_count", s.irregular_vertices},
          {"cut_edges", s.cut_edges},
          {"arcs", s.arcs},
          {"cut_length_mm", s.cut_length_mm},
          {"overlapping_faces", s.overlapping_faces},
          {"disc",
           {{"vertices", s.disc_vertices},
            {"euler_characteristic", s.euler_characteristic},
            {"boundary_loops", s.boundary_loops}}},
          {"time_s",
           {{"load", r.load_seconds},
            {"proxy", r.proxy_seconds},
            {"cut", r.cut_seconds},
            {"total", r.load_seconds + r.proxy_seconds + r.cut_seconds}}}};
}

std::optional<json> read_json(const fs::path& path, knitout::DiagnosticSink& sink) {
  std::ifstream in(path);
  if (!in) {
    sink.error(path.string(), 0, 0, "P020", "cannot open file (is this a cut folder?)");
    return std::nullopt;
  }
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    sink.error(path.string(), 0, 0, "P021", std::string("malformed JSON: ") + e.what());
    return std::nullopt;
  }
}

}  // namespace

std::string write_cut_result(const std::string& dir, const CutMesh& cut, const CutReport& report) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return dir + ": cannot create folder: " + ec.message();
  const CutSummary summary = summarize(cut);
  const fs::path base(dir);
  std::string failure =
      knitout::write_file_atomically((base / "proxy.obj").string(), [&](std::ostream& out) {
        write_obj(out, cut.proxy.polygons(), "wearknit proxy Q (quads and triangles), mm");
      });
  if (!failure.empty()) return failure;
  failure =
      knitout::write_file_atomically((base / "cut-mesh.obj").string(), [&](std::ostream& out) {
        write_obj(
            out, cut.disc,
            "wearknit cut-mesh: one disc; faces as in proxy.obj, vertices duplicated along cuts");
      });
  if (!failure.empty()) return failure;
  const std::pair<const char*, json> files[] = {{"cuts.json", cuts_json(cut, summary)},
                                                {"labels.json", labels_json(cut)},
                                                {"report.json", report_json(cut, summary, report)}};
  for (const auto& [name, content] : files) {
    failure = knitout::write_file_atomically(
        (base / name).string(), [&](std::ostream& out) { out << content.dump(1) << '\n'; });
    if (!failure.empty()) return failure;
  }
  return {};
}

std::optional<CutMesh> read_cut_result(const std::string& dir, knitout::DiagnosticSink& sink) {
  const fs::path base(dir);
  const std::size_t errors_before = sink.error_count();
  for (const char* name : {"proxy.obj", "cut-mesh.obj", "cuts.json", "labels.json"}) {
    if (!fs::is_regular_file(base / name)) {
      sink.error((base / name).string(), 0, 0, "P020",
                 "missing: not a cut folder (run wearknit cut)");
    }
  }
  if (sink.error_count() != errors_before) return std::nullopt;
  auto proxy = read_polygon_soup((base / "proxy.obj").string(), sink);
  auto disc = read_polygon_soup((base / "cut-mesh.obj").string(), sink);
  auto labels = read_json(base / "labels.json", sink);
  auto cuts = read_json(base / "cuts.json", sink);
  if (!proxy || !disc || !labels || !cuts) return std::nullopt;
  if (!check_mesh(*proxy, (base / "proxy.obj").string(), sink)) return std::nullopt;
  const std::string labels_name = (base / "labels.json").string();
  CutMesh cut;
  try {
    cut.proxy = HalfedgeMesh(std::move(*proxy));
    const HalfedgeMesh& q = cut.proxy;
    const std::size_t nf = at(q.num_faces());
    auto vanishing = labels->at("vanishing_corner").get<std::vector<int>>();
    auto frames = labels->at("frame").get<std::vector<int>>();
    auto uv = labels->at("uv").get<std::vector<std::array<int, 2>>>();
    auto overlap = labels->at("overlap_count").get<std::vector<int>>();
    auto source = labels->at("cut_mesh_vertex_source").get<std::vector<int>>();
    if (vanishing.size() != nf || frames.size() != nf || uv.size() != nf || overlap.size() != nf ||
        disc->faces.size() != nf || source.size() != disc->positions.size()) {
      sink.error(labels_name, 0, 0, "P022",
                 "labels.json, proxy.obj and cut-mesh.obj disagree on the number of faces or "
                 "vertices");
      return std::nullopt;
    }
    for (std::size_t f = 0; f < nf; ++f) {
      const int degree = q.degree(static_cast<int>(f));
      if (frames[f] < 0 || frames[f] > 3 || vanishing[f] < -1 || vanishing[f] >= degree ||
          (degree == 3) != (vanishing[f] >= 0) || disc->faces[f].size() != at(degree)) {
        sink.error(labels_name, 0, 0, "P022",
                   "face " + std::to_string(f + 1) + ": frame or vanishing corner out of range");
        return std::nullopt;
      }
    }
    cut.labels = labels_with_vanishing(q, std::move(vanishing));
    cut.face_frame = std::move(frames);
    cut.face_uv = std::move(uv);
    cut.overlap_count = std::move(overlap);
    cut.seed_face = labels->value("seed_face", -1);
    cut.direction.assign(at(q.num_halfedges()), 0);
    for (int h = 0; h < q.num_halfedges(); ++h) {
      cut.direction[at(h)] = halfedge_direction(q, cut.labels, cut.face_frame[at(q.face(h))], h);
    }
    std::map<std::pair<int, int>, int> edge_of;
    for (int e = 0; e < q.num_edges(); ++e) {
      const int h = q.edge_halfedge(e);
      edge_of[{std::min(q.from(h), q.to(h)), std::max(q.from(h), q.to(h))}] = e;
    }
    auto find_edge = [&](int a, int b) {
      auto it = edge_of.find({std::min(a, b), std::max(a, b)});
      return it == edge_of.end() ? -1 : it->second;
    };
    cut.motorcycle_edges.assign(at(q.num_edges()), 0);
    for (const auto& m : labels->at("motorcycle_edges")) {
      const int e = find_edge(m.at(0).get<int>(), m.at(1).get<int>());
      if (e >= 0) cut.motorcycle_edges[at(e)] = m.at(2).get<int>();
    }
    cut.cut_edge.assign(at(q.num_edges()), false);
    const std::string cuts_name = (base / "cuts.json").string();
    for (const auto& a : cuts->at("arcs")) {
      CutArc arc;
      for (const auto& edge : a.at("edges")) {
        const int u = edge.at(0).get<int>();
        const int v = edge.at(1).get<int>();
        const int e = find_edge(u, v);
        if (e < 0) {
          sink.error(cuts_name, 0, 0, "P022",
                     "arc " + std::to_string(a.value("id", -1)) + ": " + std::to_string(u) + "-" +
                         std::to_string(v) + " is not an edge of proxy.obj");
          return std::nullopt;
        }
        cut.cut_edge[at(e)] = true;
        if (arc.vertices.empty()) arc.vertices.push_back(u);
        arc.vertices.push_back(v);
      }
      arc.length_mm = a.value("length_mm", 0.0);
      arc.closed = a.value("closed", false);
      cut.arcs.push_back(std::move(arc));
    }
    cut.disc = std::move(*disc);
    cut.disc_source = std::move(source);
  } catch (const json::exception& e) {
    sink.error(labels_name, 0, 0, "P021", std::string("unexpected content: ") + e.what());
    return std::nullopt;
  } catch (const std::logic_error& e) {
    sink.error((base / "proxy.obj").string(), 0, 0, "P022", e.what());
    return std::nullopt;
  }
  return cut;
}

}  // namespace planner
