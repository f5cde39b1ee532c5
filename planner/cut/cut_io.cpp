#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>

#include "knitout/output_file.hpp"
#include "planner/common/hash.hpp"
#include "planner/common/index.hpp"
#include "planner/common/json_file.hpp"
#include "planner/cut/cut_pictures.hpp"
#include "planner/mesh/girth.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/pipeline.hpp"

namespace planner {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

constexpr const char* kProxyHeader = "wearknit proxy Q (quads and triangles), mm";
constexpr const char* kSurfaceHeader = "wearknit garment surface as cut, mm";
constexpr const char* kDiscHeader =
    "wearknit cut-mesh: one disc; faces as in proxy.obj, vertices duplicated along cuts";

json arcs_json(const CutMesh& cut) {
  json arcs = json::array();
  for (std::size_t i = 0; i < cut.arcs.size(); ++i) {
    const CutArc& arc = cut.arcs[i];
    json edges = json::array();
    for (std::size_t k = 0; k + 1 < arc.vertices.size(); ++k) {
      edges.push_back({arc.vertices[k], arc.vertices[k + 1]});
    }
    arcs.push_back(
        {{"id", i}, {"edges", edges}, {"length_mm", arc.length_mm}, {"closed", arc.closed}});
  }
  return arcs;
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

// {"-1": a, "+1": b, ...}: how many vertices have each index.
json by_index_json(const FieldSingularities& s) {
  json counts = json::object();
  for (const auto& [index, count] : s.by_index)
    counts[(index > 0 ? "+" : "") + std::to_string(index)] = count;
  return counts;
}

json report_json(const CutMesh& cut, const CutSummary& s, const CutReport& r) {
  const FieldSingularities q = proxy_singularities(cut);
  const FieldReport& f = r.field;
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
            {"remesh_attempts", r.remesh_attempts},
            {"edge_candidates", r.edge_candidates},
            {"input_verdict", r.input_verdict},
            {"valence_flips", r.valence_flips},
            {"field_misfit", r.field_misfit},
            {"surface_distance_max_mm", r.surface_distance_max_mm},
            {"surface_distance_mean_mm", r.surface_distance_mean_mm},
            {"irregular_vertices", q.count},
            {"singular_vertices", cut.labels.singular_vertices.size()},
            {"adjacent_pairs", adjacent_opposite_pairs(cut.proxy, cut.labels)},
            {"index_sum", q.index_sum},
            {"by_index", by_index_json(q)}}},
          {"field",
           {{"edge_mm", f.edge_mm},
            {"faces", f.faces},
            {"euler_characteristic", f.euler_characteristic},
            {"boundary_loops", f.boundary_loops},
            {"singularities", f.singularities.count},
            {"index_sum", f.singularities.index_sum},
            {"by_index", by_index_json(f.singularities)},
            {"iterations", f.iterations}}},
          {"params",
           {{"seed", r.params.seed},
            {"cs", r.params.cs},
            {"co", r.params.co},
            {"vanishing", vanishing_name(r.params.vanishing.method)},
            {"vanishing_slack_deg", r.params.vanishing.slack_deg},
            {"arc_turn_deg", r.params.arc_turn_deg},
            {"growth", r.params.square_growth ? "square" : "random"},
            {"tighten", r.params.tighten}}},
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
            {"field", r.field_seconds},
            {"girth", r.girth_seconds},
            {"cut", r.cut_seconds},
            {"total", r.load_seconds + r.proxy_seconds + r.field_seconds + r.girth_seconds +
                          r.cut_seconds}}}};
}

// Per vertex of Q, mm to 0.01; null where no girth was measured.
json girth_json(const std::vector<double>& girth) {
  json out = json::array();
  for (const double g : girth) {
    if (std::isfinite(g)) {
      out.push_back(std::round(g * 100.0) / 100.0);
    } else {
      out.push_back(nullptr);
    }
  }
  return out;
}

std::string obj_text(const PolygonMesh& mesh, std::string_view header) {
  std::ostringstream out;
  write_obj(out, mesh, header);
  return out.str();
}

// The CutReport that cut.json's "report" describes (what report_json wrote).
CutReport report_from_json(const json& r) {
  CutReport report;
  const json input = r.value("input", json::object());
  report.input = input.value("file", std::string());
  report.units = input.value("units", std::string("mm"));
  report.scale = input.value("scale", 1.0);
  const auto size = input.value("size_mm", std::vector<double>{0, 0, 0});
  if (size.size() == 3) report.input_size_mm = Vec3(size[0], size[1], size[2]);
  report.input_vertices = input.value("vertices", 0);
  report.input_faces = input.value("faces", 0);
  const json proxy = r.value("proxy", json::object());
  report.remeshed = proxy.value("remeshed", false);
  report.proxy_method = proxy.value("method", std::string("input"));
  report.remesh_failure = proxy.value("remesh_failure", std::string());
  report.proxy_edge_mm = proxy.value("edge_mm", 0.0);
  report.polygons_split = proxy.value("polygons_split", 0);
  report.triangles_paired = proxy.value("triangles_paired", 0);
  report.samples = proxy.value("samples", 0);
  report.holes_filled = proxy.value("holes_filled", 0);
  report.folds_removed = proxy.value("folds_removed", 0);
  report.remesh_attempts = proxy.value("remesh_attempts", 0);
  report.edge_candidates = proxy.value("edge_candidates", 0);
  report.input_verdict = proxy.value("input_verdict", std::string());
  report.valence_flips = proxy.value("valence_flips", 0);
  report.field_misfit = proxy.value("field_misfit", 0);
  report.surface_distance_max_mm = proxy.value("surface_distance_max_mm", 0.0);
  report.surface_distance_mean_mm = proxy.value("surface_distance_mean_mm", 0.0);
  const json field = r.value("field", json::object());
  report.field.edge_mm = field.value("edge_mm", 0.0);
  report.field.faces = field.value("faces", 0);
  report.field.euler_characteristic = field.value("euler_characteristic", 0);
  report.field.boundary_loops = field.value("boundary_loops", 0);
  report.field.singularities.count = field.value("singularities", 0);
  report.field.singularities.index_sum = field.value("index_sum", 0);
  const json by_index = field.value("by_index", json::object());
  for (const auto& [key, count] : by_index.items()) {
    // Keys are indices ("-1", "+1"); another key is not a count of ours.
    char* end = nullptr;
    const long index = std::strtol(key.c_str(), &end, 10);
    if (!key.empty() && *end == '\0')
      report.field.singularities.by_index[static_cast<int>(index)] = count.get<int>();
  }
  report.field.iterations = field.value("iterations", 0);
  const json params = r.value("params", json::object());
  report.params.seed = params.value("seed", report.params.seed);
  report.params.cs = params.value("cs", report.params.cs);
  report.params.co = params.value("co", report.params.co);
  // A report with no rule predates the choice: its corners are the acute ones.
  report.params.vanishing.method = vanishing_method(params.value("vanishing", std::string("acute")))
                                       .value_or(VanishingRule::Method::Acute);
  report.params.vanishing.slack_deg = params.value("vanishing_slack_deg", 0.0);
  report.params.arc_turn_deg = params.value("arc_turn_deg", report.params.arc_turn_deg);
  report.params.square_growth = params.value("growth", std::string("random")) == "square";
  // A report without the field predates tightening: its cut was not tightened.
  report.params.tighten = params.value("tighten", false);
  report.picture_px = r.value("picture_px", 0);
  const json time = r.value("time_s", json::object());
  report.load_seconds = time.value("load", 0.0);
  report.proxy_seconds = time.value("proxy", 0.0);
  report.field_seconds = time.value("field", 0.0);
  report.girth_seconds = time.value("girth", 0.0);
  report.cut_seconds = time.value("cut", 0.0);
  return report;
}

}  // namespace

std::string write_cut(const std::string& dir, const Cut& cut, const CutPictures& pictures,
                      std::uint64_t* id_out) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return dir + ": cannot create folder: " + ec.message();
  const CutMesh& mesh = cut.mesh;
  const CutSummary summary = summarize(mesh);
  const fs::path base(dir);
  const std::string proxy = obj_text(mesh.proxy.polygons(), kProxyHeader);
  const std::string disc = obj_text(mesh.disc, kDiscHeader);
  const json labels = labels_json(mesh);
  const json arcs = arcs_json(mesh);
  const std::string surface =
      cut.surface.faces.empty() ? std::string() : obj_text(cut.surface, kSurfaceHeader);
  // The id covers everything a later stage reads of the cut.
  std::uint64_t id = fingerprint(proxy);
  id = fingerprint(disc, id);
  if (!surface.empty()) id = fingerprint(surface, id);
  id = fingerprint(labels.dump(), id);
  id = fingerprint(arcs.dump(), id);
  if (id_out != nullptr) *id_out = id;
  json cut_file = {{"format", "wearknit-cut 1"},
                   {"cut_id", hex64(id)},
                   {"vertices", "0-based indices of the v lines of proxy.obj"},
                   {"cut_edges", summary.cut_edges},
                   {"cut_length_mm", summary.cut_length_mm},
                   {"arcs", arcs},
                   {"report", report_json(mesh, summary, cut.report)}};
  cut_file["report"]["picture_px"] = pictures.draw ? pictures.panel_px : 0;
  // A cut made without the garment (a proxy cut as it is) records no girth.
  if (!cut.girth_mm.empty()) cut_file["girth_mm"] = girth_json(cut.girth_mm);
  const std::pair<const char*, const std::string*> objs[] = {
      {"proxy.obj", &proxy}, {"cut-mesh.obj", &disc}, {"surface.obj", &surface}};
  for (const auto& [name, text] : objs) {
    if (text->empty()) {  // a cut made without the garment has no surface
      std::error_code ignored;
      fs::remove(base / name, ignored);
      continue;
    }
    const std::string* body = text;
    const std::string failure = knitout::write_file_atomically(
        (base / name).string(), [body](std::ostream& out) { out << *body; });
    if (!failure.empty()) return failure;
  }
  const std::pair<const char*, const json*> jsons[] = {{"labels.json", &labels},
                                                       {"cut.json", &cut_file}};
  for (const auto& [name, content] : jsons) {
    const std::string failure = write_json_file((base / name).string(), *content);
    if (!failure.empty()) return failure;
  }
  if (!pictures.draw) return {};
  std::string failure = draw_cuts_3d(mesh, (base / "cuts-3d.png").string(), pictures.panel_px);
  if (failure.empty())
    failure = draw_layout_2d(mesh, (base / "layout-2d.png").string(), pictures.panel_px * 5 / 3);
  return failure;
}

CutUnits read_cut_units(const std::string& dir) {
  CutUnits out;
  std::ifstream in(fs::path(dir) / "cut.json");
  if (!in) return out;
  const json cut = json::parse(in, nullptr, false);
  if (!cut.is_object()) return out;
  const json report = cut.value("report", json::object());
  if (!report.is_object()) return out;
  const json input = report.value("input", json::object());
  if (!input.is_object()) return out;
  if (auto u = input.find("units"); u != input.end() && u->is_string()) out.units = *u;
  if (auto s = input.find("scale"); s != input.end() && s->is_number()) out.scale = *s;
  return out;
}

std::optional<Cut> read_cut(const std::string& dir, knitout::DiagnosticSink& sink) {
  const fs::path base(dir);
  const std::size_t errors_before = sink.error_count();
  for (const char* name : {"proxy.obj", "cut-mesh.obj", "cut.json", "labels.json"}) {
    if (!fs::is_regular_file(base / name)) {
      sink.error((base / name).string(), 0, 0, "P020",
                 "missing: not a cut folder (run wearknit cut)");
    }
  }
  if (sink.error_count() != errors_before) return std::nullopt;
  auto proxy = read_polygon_soup((base / "proxy.obj").string(), sink);
  auto disc = read_polygon_soup((base / "cut-mesh.obj").string(), sink);
  auto labels = read_json_object((base / "labels.json").string(), sink, "P020", "P021");
  auto cuts = read_json_object((base / "cut.json").string(), sink, "P020", "P021");
  if (!proxy || !disc || !labels || !cuts) return std::nullopt;
  if (!check_mesh(*proxy, (base / "proxy.obj").string(), sink)) return std::nullopt;
  const std::string labels_name = (base / "labels.json").string();
  Cut result;
  CutMesh& cut = result.mesh;
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
    const std::string cuts_name = (base / "cut.json").string();
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
    // The garment's surface, where the cut recorded it (older folders do not).
    if (fs::is_regular_file(base / "surface.obj")) {
      auto surface = read_polygon_soup((base / "surface.obj").string(), sink);
      if (!surface) return std::nullopt;
      result.surface = std::move(*surface);
    }
    cut.disc_source = std::move(source);
    result.report = report_from_json(cuts->value("report", json::object()));
    if (const auto g = cuts->find("girth_mm"); g != cuts->end()) {
      if (!g->is_array() || g->size() != at(q.num_vertices())) {
        sink.error(cuts_name, 0, 0, "P022",
                   "\"girth_mm\" has " + std::to_string(g->is_array() ? g->size() : 0) +
                       " values; proxy.obj has " + std::to_string(q.num_vertices()) + " vertices");
        return std::nullopt;
      }
      for (const auto& value : *g)
        result.girth_mm.push_back(value.is_null() ? kNoGirth : value.get<double>());
    }
    if (!parse_hex64(cuts->value("cut_id", std::string()), result.id)) {
      sink.error(cuts_name, 0, 0, "P021", "no \"cut_id\" of 16 hex digits");
      return std::nullopt;
    }
  } catch (const json::exception& e) {
    sink.error(labels_name, 0, 0, "P021", std::string("unexpected content: ") + e.what());
    return std::nullopt;
  } catch (const std::logic_error& e) {
    sink.error((base / "proxy.obj").string(), 0, 0, "P022", e.what());
    return std::nullopt;
  }
  return result;
}

}  // namespace planner
