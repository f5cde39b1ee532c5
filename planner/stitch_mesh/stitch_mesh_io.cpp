#include "planner/stitch_mesh/stitch_mesh_io.hpp"

#include <cairo.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "knitout/output_file.hpp"
#include "planner/common/index.hpp"

namespace planner {
namespace {}  // namespace

LabelledDisc labelled_disc(const CutMesh& cut) {
  LabelledDisc disc;
  disc.positions = cut.disc.positions;
  disc.faces = cut.disc.faces;
  std::map<std::pair<int, int>, std::int32_t> arc_of_edge;  // proxy vertices, sorted
  for (std::size_t a = 0; a < cut.arcs.size(); ++a) {
    const std::vector<int>& path = cut.arcs[a].vertices;
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      arc_of_edge[{std::min(path[i], path[i + 1]), std::max(path[i], path[i + 1])}] =
          static_cast<std::int32_t>(a);
    }
  }
  // Boundary sides of the disc: directed sides with no reverse.
  std::map<std::pair<int, int>, int> directed;
  for (const std::vector<int>& face : disc.faces) {
    for (std::size_t i = 0; i < face.size(); ++i)
      ++directed[{face[i], face[(i + 1) % face.size()]}];
  }
  for (std::size_t f = 0; f < disc.faces.size(); ++f) {
    const std::vector<int>& face = disc.faces[f];
    std::vector<int> dir;
    std::vector<std::int32_t> arcs;
    const int start = cut.proxy.face_start(static_cast<int>(f));
    for (std::size_t i = 0; i < face.size(); ++i) {
      dir.push_back(cut.direction[at(start + static_cast<int>(i))]);
      const int a = face[i];
      const int b = face[(i + 1) % face.size()];
      std::int32_t arc = kNoArc;
      if (directed.find({b, a}) == directed.end()) {
        const int qa = cut.disc_source[at(a)];
        const int qb = cut.disc_source[at(b)];
        auto it = arc_of_edge.find({std::min(qa, qb), std::max(qa, qb)});
        if (it != arc_of_edge.end()) arc = it->second;
      }
      arcs.push_back(arc);
    }
    disc.directions.push_back(std::move(dir));
    disc.arcs.push_back(std::move(arcs));
  }
  return disc;
}

void write_stitch_obj(std::ostream& out, const StitchMesh& mesh) {
  std::ostringstream text;
  text << std::setprecision(10);
  text << "# stitch mesh (wearknit, paper §6), mm; course " << mesh.course_mm << " wale "
       << mesh.wale_mm << "\n";
  for (const Eigen::Vector3d& p : mesh.positions) {
    text << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  }
  for (const StitchFace& face : mesh.faces) {
    text << "f";
    for (std::uint32_t v : face.vertices) text << " " << v + 1;
    text << "\n";
  }
  for (const StitchFace& face : mesh.faces) text << "# type " << face_type_name(face.type) << "\n";
  out << text.str();
}

namespace {

cairo_status_t write_to_stream(void* closure, const unsigned char* data, unsigned int length) {
  auto* out = static_cast<std::ostream*>(closure);
  out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(length));
  return *out ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

std::array<double, 3> type_colour(FaceType type) {
  switch (type) {
    case FaceType::Knit:
      return {0.80, 0.80, 0.82};
    case FaceType::Increase:
      return {0.30, 0.75, 0.35};
    case FaceType::Decrease:
      return {0.25, 0.45, 0.90};
    case FaceType::ShortRow:
      return {0.95, 0.55, 0.15};
  }
  return {1, 0, 1};
}

}  // namespace

std::string draw_stitch_mesh(const StitchMesh& mesh, const std::string& png_path, int panel_px) {
  const int size = panel_px * 2;
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, size, size);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  Vec3 center = Vec3::Zero();
  for (const Vec3& p : mesh.positions) center += p;
  center /= std::max<std::size_t>(1, mesh.positions.size());
  double radius = 1e-9;
  for (const Vec3& p : mesh.positions) radius = std::max(radius, (p - center).norm());
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const StitchFace& face : mesh.faces) {
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      ++directed[{face.vertices[i], face.vertices[(i + 1) % face.vertices.size()]}];
    }
  }
  const double pi = std::acos(-1.0);
  const Vec3 light = Vec3(0.3, 0.5, 1.0).normalized();
  for (int panel = 0; panel < 4; ++panel) {
    const double yaw = panel * 90.0 * pi / 180.0;
    const double pitch = 20.0 * pi / 180.0;
    auto transform = [&](const Vec3& p) {
      const Vec3 r = p - center;
      const double x = std::cos(yaw) * r.x() + std::sin(yaw) * r.z();
      const double z = -std::sin(yaw) * r.x() + std::cos(yaw) * r.z();
      return Vec3(x, std::cos(pitch) * r.y() - std::sin(pitch) * z,
                  std::sin(pitch) * r.y() + std::cos(pitch) * z);
    };
    std::vector<Vec3> projected;
    projected.reserve(mesh.positions.size());
    for (const Vec3& p : mesh.positions) projected.push_back(transform(p));
    const double ox = (panel % 2) * panel_px + panel_px / 2.0;
    const double oy = (panel / 2) * panel_px + panel_px / 2.0;
    const double scale = 0.46 * panel_px / radius;
    auto move = [&](const Vec3& p, bool first) {
      if (first) {
        cairo_move_to(cr, ox + scale * p.x(), oy - scale * p.y());
      } else {
        cairo_line_to(cr, ox + scale * p.x(), oy - scale * p.y());
      }
    };
    // Painter's order: far faces first.
    std::vector<std::pair<double, std::size_t>> order;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      double depth = 0;
      for (std::uint32_t v : mesh.faces[f].vertices) depth += projected[v].z();
      order.emplace_back(depth / static_cast<double>(mesh.faces[f].vertices.size()), f);
    }
    std::sort(order.begin(), order.end());
    cairo_save(cr);
    cairo_rectangle(cr, (panel % 2) * panel_px, (panel / 2) * panel_px, panel_px, panel_px);
    cairo_clip(cr);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    for (const auto& [depth, f] : order) {
      const StitchFace& face = mesh.faces[f];
      const std::size_t n = face.vertices.size();
      Vec3 normal = Vec3::Zero();
      for (std::size_t i = 0; i < n; ++i) {
        normal += projected[face.vertices[i]].cross(projected[face.vertices[(i + 1) % n]]);
      }
      if (normal.norm() > 0) normal.normalize();
      const bool front = normal.z() > 0;
      const double shade = (0.45 + 0.55 * std::abs(normal.dot(light))) * (front ? 1.0 : 0.6);
      const std::array<double, 3> colour = type_colour(face.type);
      for (std::size_t i = 0; i < n; ++i) move(projected[face.vertices[i]], i == 0);
      cairo_close_path(cr);
      cairo_set_source_rgb(cr, colour[0] * shade, colour[1] * shade, colour[2] * shade);
      cairo_fill(cr);
      for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t a = face.vertices[i];
        const std::uint32_t b = face.vertices[(i + 1) % n];
        const bool boundary = directed.find({b, a}) == directed.end();
        move(projected[a], true);
        move(projected[b], false);
        if (boundary) {
          cairo_set_source_rgb(cr, 0.85, 0.05, 0.05);
          cairo_set_line_width(cr, front ? 2.0 : 1.0);
        } else if (face.roles[i] == EdgeRole::Wale) {
          cairo_set_source_rgba(cr, 0.1, 0.1, 0.1, 0.25);
          cairo_set_line_width(cr, 0.4);
        } else {
          cairo_set_source_rgba(cr, 0.1, 0.1, 0.1, 0.6);
          cairo_set_line_width(cr, 0.7);
        }
        cairo_stroke(cr);
      }
    }
    cairo_restore(cr);
  }
  // Legend, bottom left: the face types and the cut boundary.
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, std::max(10.0, panel_px / 45.0));
  const double swatch = std::max(10.0, panel_px / 40.0);
  double x = swatch;
  const double y = size - 2.0 * swatch;
  const std::pair<const char*, FaceType> types[] = {{"knit", FaceType::Knit},
                                                    {"increase", FaceType::Increase},
                                                    {"decrease", FaceType::Decrease},
                                                    {"short row", FaceType::ShortRow}};
  cairo_text_extents_t extents;
  for (const auto& [label, type] : types) {
    const std::array<double, 3> colour = type_colour(type);
    cairo_set_source_rgb(cr, colour[0], colour[1], colour[2]);
    cairo_rectangle(cr, x, y, 1.5 * swatch, swatch);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_move_to(cr, x + 2.0 * swatch, y + 0.85 * swatch);
    cairo_show_text(cr, label);
    cairo_text_extents(cr, label, &extents);
    x += 3.0 * swatch + extents.x_advance;
  }
  cairo_set_source_rgb(cr, 0.85, 0.05, 0.05);
  cairo_set_line_width(cr, 2.0);
  cairo_move_to(cr, x, y + 0.5 * swatch);
  cairo_line_to(cr, x + 1.5 * swatch, y + 0.5 * swatch);
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  cairo_move_to(cr, x + 2.0 * swatch, y + 0.85 * swatch);
  cairo_show_text(cr, "cut (edge of the sheet)");
  cairo_destroy(cr);
  cairo_surface_flush(surface);
  const std::string failure = knitout::write_file_atomically(png_path, [&](std::ostream& out) {
    if (cairo_surface_write_to_png_stream(surface, write_to_stream, &out) != CAIRO_STATUS_SUCCESS) {
      throw std::runtime_error("cairo could not encode the PNG");
    }
  });
  cairo_surface_destroy(surface);
  return failure;
}

namespace {

nlohmann::json lengths_json(const EdgeLengthStats& s, double target) {
  return {{"count", s.count},   {"target_mm", target}, {"mean_mm", s.mean_mm},
          {"min_mm", s.min_mm}, {"max_mm", s.max_mm},  {"within_15_percent", s.within_15_percent}};
}

}  // namespace

std::string merge_stitch_report(const std::string& dir, const StitchMeshReport& report) {
  const std::string path = (std::filesystem::path(dir) / "report.json").string();
  nlohmann::json root = nlohmann::json::object();
  if (std::filesystem::exists(path)) {
    std::ifstream in(path);
    try {
      root = nlohmann::json::parse(in);
    } catch (const nlohmann::json::exception& e) {
      return path + ": not JSON (" + e.what() + "); left as it is";
    }
    if (!root.is_object()) return path + ": not a JSON object; left as it is";
  }
  const StitchMeshFigures& f = report.figures;
  const double stitch_area = report.gauge.course_mm * report.gauge.wale_mm;
  root["stitch_mesh"] = {
      {"gauge",
       {{"needles_per_inch", report.gauge.needles_per_inch},
        {"course_mm", report.gauge.course_mm},
        {"wale_mm", report.gauge.wale_mm},
        {"from", report.gauge.source}}},
      {"faces",
       {{"total", f.faces},
        {"knit", f.knit},
        {"increase", f.increase},
        {"decrease", f.decrease},
        {"short_row", f.short_row}}},
      {"vertices", f.vertices},
      {"rows", report.stats.rows},
      {"strips", report.stats.strips},
      {"course_edges", lengths_json(f.course, report.gauge.course_mm)},
      {"wale_edges", lengths_json(f.wale, report.gauge.wale_mm)},
      {"cut_mesh_area_mm2", report.disc_area_mm2},
      {"expected_stitches", stitch_area > 0 ? report.disc_area_mm2 / stitch_area : 0.0},
      {"stability_rules",
       {{"edge_shaping", report.stability.edge_shaping},
        {"stacked_shaping", report.stability.stacked_shaping},
        {"opposed_shaping", report.stability.opposed_shaping},
        {"one_stitch_rows", report.stability.one_stitch_rows}}},
      {"saddles_split", report.stats.saddles_split},
      {"saddles_pinned", report.stats.saddles_pinned},
      {"lenses_glued", report.stats.lenses_skipped},
      {"bind_off_sides", report.stats.boundary_sides},
      {"sides_split_below", report.stats.sides_split_below},
      {"straighten_fits", report.stats.straighten_fits},
      {"label_deviation_deg", report.stats.label_deviation_deg},
      {"row_time_levelled", report.stats.row_time_levelled},
      {"tip_sides", report.stats.tip_sides},
      {"relax_sweeps", report.stats.relax_sweeps},
      {"relax_seconds", report.stats.relax_seconds},
      {"off_surface",
       {{"faces", report.off_surface.faces.size()},
        {"max_offset_mm", report.off_surface.max_offset_mm},
        {"tolerance_mm", report.off_surface.tolerance_mm}}},
      {"boundary_loops", f.boundary_loops},
      {"euler_characteristic", f.euler_characteristic},
      {"remesh_seconds", report.stats.total_seconds},
      {"seconds", report.seconds}};
  return knitout::write_file_atomically(path,
                                        [&](std::ostream& out) { out << root.dump(1) << "\n"; });
}

}  // namespace planner
