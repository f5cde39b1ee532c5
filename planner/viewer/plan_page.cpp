#include "planner/viewer/plan_page.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <unordered_set>
#include <utility>

#include "knitout/output_file.hpp"
#include "knitout/parser.hpp"
#include "planner/assembly/assembly_model.hpp"
#include "planner/assembly/assembly_page_layout.hpp"
#include "planner/common/index.hpp"
#include "planner/common/json_file.hpp"
#include "planner/pipeline.hpp"
#include "planner/schedule/piece_layout.hpp"
#include "planner/viewer/web_assets.hpp"
#include "planner/wearability/wearability_io.hpp"
#include "simulators/bed/bed_timeline.hpp"
#include "simulators/bed/profile.hpp"
#include "simulators/bed/web_assets.hpp"

namespace planner::viewer {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Coordinates in the page's JSON: 0.01 mm is far below a stitch.
double r2(double v) {
  return std::round(v * 100.0) / 100.0;
}

// A little-endian binary array (every machine wearknit builds for is
// little-endian; static_assert below).
class Binary {
 public:
  void f32(double v) { put(static_cast<float>(v)); }
  void u32(std::uint32_t v) { put(v); }
  void u8(std::uint8_t v) { bytes_.push_back(static_cast<char>(v)); }
  std::string take() { return std::move(bytes_); }
  std::size_t size() const { return bytes_.size(); }

 private:
  template <typename T>
  void put(T v) {
    char raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));
    bytes_.append(raw, sizeof(T));
  }
  std::string bytes_;
};
static_assert(std::endian::native == std::endian::little, "the page's arrays are little-endian");

// Adds a binary block named `id` and records it in meta["blocks"].
void add_block(PlanPageData& page, const std::string& id, const std::string& type, Binary binary) {
  const std::size_t bytes = binary.size();
  page.meta["blocks"][id] = {{"type", type}, {"bytes", bytes}};
  page.blocks.push_back({id, binary.take()});
}

// A polygon mesh as positions, fan triangles and (when `types` is given, per
// face) the type of every triangle's face; `prefix`-pos, -tri, -type blocks.
void add_mesh(PlanPageData& page, const std::string& prefix,
              const std::vector<Eigen::Vector3d>& positions,
              const std::vector<std::vector<std::uint32_t>>& faces,
              const std::vector<std::uint8_t>* types) {
  Binary pos, tri, type, edges;
  for (const Eigen::Vector3d& p : positions) {
    for (int k = 0; k < 3; ++k) pos.f32(p[k]);
  }
  std::unordered_set<std::uint64_t> seen;
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto& face = faces[f];
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      tri.u32(face[0]);
      tri.u32(face[i]);
      tri.u32(face[i + 1]);
      if (types) type.u8((*types)[f]);
    }
    if (!types) continue;
    for (std::size_t i = 0; i < face.size(); ++i) {
      const std::uint32_t a = face[i], b = face[(i + 1) % face.size()];
      if (seen.insert(assembly::side_key(a, b)).second) {
        edges.u32(a);
        edges.u32(b);
      }
    }
  }
  page.meta[prefix] = {{"vertices", positions.size()}, {"faces", faces.size()}};
  add_block(page, prefix + "-pos", "f32", std::move(pos));
  add_block(page, prefix + "-tri", "u32", std::move(tri));
  if (types) {
    add_block(page, prefix + "-type", "u8", std::move(type));
    add_block(page, prefix + "-edges", "u32", std::move(edges));
  }
}

std::vector<std::vector<std::uint32_t>> faces_of(const PolygonMesh& mesh) {
  std::vector<std::vector<std::uint32_t>> out;
  out.reserve(mesh.faces.size());
  for (const auto& face : mesh.faces) out.emplace_back(face.begin(), face.end());
  return out;
}

void add_stitch_mesh(PlanPageData& page, const StitchMesh& mesh) {
  std::vector<std::vector<std::uint32_t>> faces;
  std::vector<std::uint8_t> types;
  json counts = {{"knit", 0}, {"increase", 0}, {"decrease", 0}, {"short-row", 0}};
  for (const StitchFace& face : mesh.faces) {
    faces.push_back(face.vertices);
    types.push_back(static_cast<std::uint8_t>(face.type));
    counts[std::string(face_type_name(face.type))] =
        counts[std::string(face_type_name(face.type))].get<int>() + 1;
  }
  add_mesh(page, "garment", mesh.positions, faces, &types);
  page.meta["garment"]["kind"] = "stitch mesh";
  page.meta["garment"]["face_types"] = counts;
  page.meta["garment"]["course_mm"] = mesh.course_mm;
  page.meta["garment"]["wale_mm"] = mesh.wale_mm;
}

// Newell's normal of a face, unit length (zero for a degenerate face).
Eigen::Vector3d face_normal(const StitchMesh& mesh, const StitchFace& face) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < face.vertices.size(); ++i) {
    const Eigen::Vector3d& a = mesh.positions[face.vertices[i]];
    const Eigen::Vector3d& b = mesh.positions[face.vertices[(i + 1) % face.vertices.size()]];
    n += a.cross(b);
  }
  const double len = n.norm();
  return len > 0 ? Eigen::Vector3d(n / len) : n;
}

const char* kind_name(assembly::SeamKind kind) {
  switch (kind) {
    case assembly::SeamKind::ScheduleCut:
      return "scheduling cut";
    case assembly::SeamKind::WaleSeam:
      return "wale seam";
    case assembly::SeamKind::CutArc:
      break;
  }
  return "cut-arc";
}

// The seams of a plan folder the assembly guide can read: numbered as in
// the guide, with both sides in 3D and laid flat in their pieces (mm from
// the piece's bottom-left).
void add_seams(PlanPageData& page, const assembly::Model& m) {
  using assembly::SideRef;
  const double cw = m.mesh.course_mm, ww = m.mesh.wale_mm;
  auto layout_of = [&](int face) -> const FaceLayout& {
    return m.layouts[at(m.piece_of_face[at(face)])].faces[at(m.layout_index[at(face)])];
  };
  json seams = json::array();
  for (const assembly::Seam& s : m.seams) {
    // The guide's own line for the seam ("3  lace  piece 2 to piece 2  cut-arcs 0+4, ...").
    json seam = {
        {"number", s.number},     {"name", s.name()},          {"label", s.lace ? "lace" : "sew"},
        {"labelled", s.labelled}, {"kind", kind_name(s.kind)}, {"text", assembly::seam_line(m, s)}};
    if (s.kind == assembly::SeamKind::ScheduleCut) seam["source"] = s.arc;
    if (s.kind == assembly::SeamKind::CutArc) seam["source"] = s.arcs;
    if (s.parts > 1) seam["part"] = {s.part, s.parts};
    double length = 0;
    json p3 = json::array();
    json sides = json::array();
    for (int w = 0; w < 2; ++w) {
      json flat = json::array();
      double n_lo = 1e18, n_hi = -1e18, r_lo = 1e18, r_hi = -1e18;
      double side_length = 0;
      for (const SideRef& side : s.sides[at(w)]) {
        const StitchFace& face = m.mesh.faces[at(side.face)];
        const auto v = assembly::side_vertices(m, side);
        const Eigen::Vector3d& a = m.mesh.positions[v[0]];
        const Eigen::Vector3d& b = m.mesh.positions[v[1]];
        side_length += (b - a).norm();
        const Eigen::Vector3d n = face_normal(m.mesh, face);
        for (const Eigen::Vector3d* p : {&a, &b, &n}) {
          for (int k = 0; k < 3; ++k) p3.push_back(r2((*p)[k]));
        }
        const auto seg = side_in_layout(face, layout_of(side.face), side.side);
        flat.push_back(m.piece_of_face[at(side.face)] + 1);
        for (const auto& q : seg) {
          flat.push_back(r2(q[0] * cw));
          flat.push_back(r2(q[1] * ww));
          n_lo = std::min(n_lo, q[0]);
          n_hi = std::max(n_hi, q[0]);
          r_lo = std::min(r_lo, q[1]);
          r_hi = std::max(r_hi, q[1]);
        }
      }
      if (w == 0) length = side_length;
      json one = {{"piece", s.piece[at(w)] + 1},
                  {"stitch_sides", s.sides[at(w)].size()},
                  {"length_mm", r2(side_length)},
                  {"flat", std::move(flat)}};
      if (!s.sides[at(w)].empty()) {
        // Needles of the loops the stretch runs along, and the rows it spans
        // (row 1 is the piece's first).
        one["needles"] = {static_cast<int>(std::lround(n_lo + 0.5)),
                          static_cast<int>(std::lround(n_hi - 0.5))};
        if (one["needles"][1].get<int>() < one["needles"][0].get<int>())
          one["needles"][1] = one["needles"][0];
        one["rows"] = {static_cast<int>(std::floor(r_lo)) + 1,
                       std::max(static_cast<int>(std::ceil(r_hi)), 1)};
      }
      sides.push_back(std::move(one));
    }
    seam["length_mm"] = r2(length);
    seam["sides"] = std::move(sides);
    seam["p3"] = std::move(p3);
    // Where its number goes in 3D: the middle of the side the guide numbers.
    const SideRef at_side = s.label_at[0];
    if (!s.sides[0].empty() && at_side.face >= 0) {
      const auto v = assembly::side_vertices(m, at_side);
      const Eigen::Vector3d mid = 0.5 * (m.mesh.positions[v[0]] + m.mesh.positions[v[1]]);
      const Eigen::Vector3d n = face_normal(m.mesh, m.mesh.faces[at(at_side.face)]);
      seam["at"] = {r2(mid.x()), r2(mid.y()), r2(mid.z()), r2(n.x()), r2(n.y()), r2(n.z())};
    }
    seams.push_back(std::move(seam));
  }
  page.meta["seams"] = std::move(seams);
  page.meta["seam_kind"] = "seam";
  page.meta["sewn"] = m.sewn;
  json unjoined = json::array();
  for (const assembly::ArcInfo& a : m.arcs) {
    if (a.seams == 0) unjoined.push_back(a.id);
  }
  page.meta["arcs_without_seam"] = std::move(unjoined);
}

// Every piece laid flat: the corners of its stitches (mm, 4 per stitch,
// bottom-left, bottom-right, top-right, top-left) and its open edges.
void add_flat_pieces(PlanPageData& page, const assembly::Model& m, const json& piece_figures) {
  using assembly::SideRef;
  const double cw = m.mesh.course_mm, ww = m.mesh.wale_mm;
  Binary quads, edges;
  std::uint32_t quad_count = 0, edge_count = 0;
  json pieces = json::array();
  for (std::size_t p = 0; p < m.layouts.size(); ++p) {
    const PieceLayout& layout = m.layouts[p];
    json piece = {{"number", p + 1},
                  {"needles", layout.needles},
                  {"rows", layout.levels},
                  {"stitches", layout.faces.size()},
                  {"width_mm", r2(std::max(1, layout.needles + 1) * cw)},
                  {"height_mm", r2(std::max(1, layout.levels) * ww)},
                  {"quads", {quad_count, layout.faces.size()}}};
    for (const FaceLayout& f : layout.faces) {
      for (const auto& q : face_corners(f)) {
        quads.f32(q[0] * cw);
        quads.f32(q[1] * ww);
      }
      const StitchFace& face = m.mesh.faces[at(f.face)];
      for (std::size_t i = 0; i < face.vertices.size(); ++i) {
        const SideRef side{f.face, static_cast<int>(i)};
        if (m.seam_of_side.count(side)) continue;
        const SideRef other = assembly::other_side(m, side);
        if (other.face != kNone && m.piece_of_face[at(other.face)] == static_cast<int>(p)) continue;
        for (const auto& q : side_in_layout(face, f, static_cast<int>(i))) {
          edges.f32(q[0] * cw);
          edges.f32(q[1] * ww);
        }
        ++edge_count;
      }
    }
    piece["edges"] = {edge_count, 0};  // the end, made [first, count] below
    quad_count += static_cast<std::uint32_t>(layout.faces.size());
    pieces.push_back(std::move(piece));
  }
  // Edge ranges: [first, count] in segments.
  std::uint32_t start = 0;
  for (json& piece : pieces) {
    const auto end = piece["edges"][0].get<std::uint32_t>();
    piece["edges"] = {start, end - start};
    start = end;
  }
  if (piece_figures.is_array()) {
    for (std::size_t p = 0; p < pieces.size() && p < piece_figures.size(); ++p)
      pieces[p]["figures"] = piece_figures[p];
  }
  page.meta["pieces"] = std::move(pieces);
  add_block(page, "flat-quads", "f32", std::move(quads));
  add_block(page, "flat-edges", "f32", std::move(edges));
}

// Before the schedule: the cut-arcs as polylines through the proxy, with
// their labels when the folder has them.
void add_arcs(PlanPageData& page, const Cut& cut, const std::optional<WearabilityRecord>& labels) {
  json seams = json::array();
  for (std::size_t i = 0; i < cut.mesh.arcs.size(); ++i) {
    const CutArc& arc = cut.mesh.arcs[i];
    const bool labelled = labels && labels->labels.size() == cut.mesh.arcs.size();
    const bool lace = labelled && labels->labels[i] == Label::Lace;
    json p3 = json::array();
    for (std::size_t k = 0; k + 1 < arc.vertices.size(); ++k) {
      for (const int v : {arc.vertices[k], arc.vertices[k + 1]}) {
        const Vec3& p = cut.mesh.proxy.position(v);
        for (int c = 0; c < 3; ++c) p3.push_back(r2(p[c]));
      }
      for (int c = 0; c < 3; ++c) p3.push_back(0);  // no normal: always shown
    }
    json seam = {{"number", i},
                 {"label", lace ? "lace" : "sew"},
                 {"labelled", labelled},
                 {"kind", "cut-arc"},
                 {"text", "cut-arc " + std::to_string(i) +
                              (labelled ? (lace ? " (lace)" : " (sew)") : " (not labelled yet)")},
                 {"length_mm", r2(arc.length_mm)},
                 {"sides", json::array()},
                 {"p3", std::move(p3)}};
    if (!arc.vertices.empty()) {
      const Vec3& p = cut.mesh.proxy.position(arc.vertices[arc.vertices.size() / 2]);
      seam["at"] = {r2(p.x()), r2(p.y()), r2(p.z()), 0, 0, 0};
    }
    seams.push_back(std::move(seam));
  }
  page.meta["seams"] = std::move(seams);
  page.meta["seam_kind"] = "cut-arc";
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

void note(PlanPageData& page, const std::string& text) {
  page.meta["notes"].push_back(text);
}

}  // namespace

PlanPageData collect_plan_page(const fs::path& dir) {
  if (!fs::is_directory(dir)) throw std::runtime_error(dir.string() + ": not a folder");
  PlanPageData page;
  page.meta = {{"format", "wearknit-plan-page 1"},
               {"folder", fs::absolute(dir).lexically_normal().filename().string()},
               {"notes", json::array()},
               {"blocks", json::object()},
               {"seams", json::array()},
               {"pieces", json::array()}};
  const std::string folder = dir.string();
  for (const char* name : {"report.json", "plan.json"}) {
    if (auto value = read_json_object_if_any((dir / name).string()))
      page.meta[std::string(name).substr(0, std::string(name).find('.'))] = std::move(*value);
  }
  json piece_figures;
  if (auto schedule = read_json_object_if_any((dir / "schedule.json").string())) {
    if (schedule->contains("report")) piece_figures = (*schedule)["report"].value("pieces", json());
  }

  // The whole folder as the assembly guide reads it; else what exists.
  assembly::Model model;
  bool full = false;
  try {
    assembly::load(model, dir);
    full = true;
  } catch (const assembly::Failure& e) {
    note(page, std::string("no seams and pieces yet: ") + e.what());
  } catch (const std::logic_error& e) {
    note(page, std::string("the seams cannot be shown: internal error: ") + e.what());
  }
  if (full) {
    add_stitch_mesh(page, model.mesh);
    add_seams(page, model);
    add_flat_pieces(page, model, piece_figures);
  } else {
    knitout::DiagnosticSink sink;
    std::optional<Cut> cut;
    if (fs::exists(dir / "cut.json")) cut = read_cut(folder, sink);
    std::optional<WearabilityRecord> labels;
    if (cut && fs::exists(dir / "wearability.json")) {
      knitout::DiagnosticSink wear_sink;
      labels = read_wearability(folder, wear_sink);
      if (labels && labels->labels.size() != cut->mesh.arcs.size()) labels.reset();
    }
    std::optional<StitchMeshFile> stitches;
    if (fs::exists(dir / "stitch-mesh.smobj")) {
      knitout::DiagnosticSink mesh_sink;
      stitches = read_stitch_mesh(folder, mesh_sink);
    }
    if (stitches) {
      add_stitch_mesh(page, stitches->mesh);
    } else if (cut) {
      std::vector<Eigen::Vector3d> positions(cut->mesh.disc.positions.begin(),
                                             cut->mesh.disc.positions.end());
      add_mesh(page, "garment", positions, faces_of(cut->mesh.disc), nullptr);
      page.meta["garment"]["kind"] = "cut disc";
    } else {
      note(page, "the folder has no cut yet (run wearknit cut or wearknit plan)");
    }
    if (cut) add_arcs(page, *cut, labels);
  }

  // The wearer as the plan wrote it (mm, like the garment).
  if (fs::exists(dir / "wearer.obj")) {
    knitout::DiagnosticSink sink;
    if (auto wearer = read_stage_mesh((dir / "wearer.obj").string(), sink)) {
      std::vector<Eigen::Vector3d> positions(wearer->positions.begin(), wearer->positions.end());
      add_mesh(page, "wearer", positions, faces_of(*wearer), nullptr);
    } else {
      note(page, "wearer.obj cannot be read");
    }
  }

  // Each piece's bed view, as the schedule drew it.
  json& pieces = page.meta["pieces"];
  if (pieces.empty() && piece_figures.is_array()) {
    for (std::size_t p = 0; p < piece_figures.size(); ++p)
      pieces.push_back({{"number", p + 1}, {"figures", piece_figures[p]}});
  }
  // Each piece's knitout through the machine, as the interactive bed view
  // (simulators/bed/web/bed_view.js) draws it, with its source text while the
  // page's sources stay within kMaxPageSourceBytes; else its line numbers only.
  // A piece whose knitout is missing keeps the schedule's picture.
  std::size_t source_bytes = 0;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    const std::string name = "piece-" + std::to_string(p + 1);
    const fs::path knitout_path = dir / "pieces" / (name + ".k");
    if (fs::is_regular_file(knitout_path)) {
      const std::string text = read_text(knitout_path);
      knitout::DiagnosticSink sink;
      const knitout::Program program = knitout::parse_string(text, knitout_path.string(), sink);
      page.blocks.push_back(
          {"bed-" + std::to_string(p + 1),
           bed::timeline_bytes(program, bed::default_profile(), knitout_path.string(), sink)});
      pieces[p]["bed_timeline"] = "bed-" + std::to_string(p + 1);
      if (source_bytes + text.size() <= kMaxPageSourceBytes) {
        source_bytes += text.size();
        pieces[p]["bed_source"] = "bed-source-" + std::to_string(p + 1);
        page.blocks.push_back({"bed-source-" + std::to_string(p + 1), text});
      }
      continue;
    }
    const fs::path svg = dir / "pieces" / (name + ".svg");
    if (!fs::is_regular_file(svg)) continue;
    const std::string id = "bed-" + std::to_string(p + 1);
    pieces[p]["bed_svg"] = id;
    page.blocks.push_back({id, read_text(svg)});
  }
  page.blocks.insert(page.blocks.begin(), bed::PageData{"plan", page.meta.dump()});
  return page;
}

std::string write_plan_page(const fs::path& dir, PlanPageSummary* summary) {
  PlanPageData data;
  try {
    data = collect_plan_page(dir);
  } catch (const std::exception& e) {
    return (dir / "index.html").string() + ": " + e.what();
  }
  bed::Page page;
  page.title = "wearknit plan: " + data.meta.value("folder", std::string());
  page.styles = {bed::web_asset("page.css"), bed::web_asset("bed_view.css"),
                 web_asset("plan_view.css")};
  page.scripts = {bed::web_asset("common.js"), bed::web_asset("bed_view.js"),
                  web_asset("scene3d.js"), web_asset("flat.js"), web_asset("plan_view.js")};
  page.body = "<div id=\"app\"></div>";
  page.data = std::move(data.blocks);
  const fs::path path = dir / "index.html";
  std::size_t bytes = 0;
  const std::string failure = knitout::write_file_atomically(path.string(), [&](std::ostream& out) {
    std::ostringstream text;
    bed::write_page(text, page);
    const std::string s = text.str();
    bytes = s.size();
    out << s;
  });
  if (!failure.empty()) return failure;
  if (summary) {
    summary->bytes = bytes;
    // A seam in parts counts once.
    int seams = 0;
    for (const json& seam : data.meta["seams"]) {
      const json part = seam.value("part", json());
      seams += !part.is_array() || part.at(0) == 1;
    }
    summary->seams = seams;
    summary->pieces = static_cast<int>(data.meta["pieces"].size());
    summary->wearer = data.meta.contains("wearer");
  }
  return "";
}

}  // namespace planner::viewer
