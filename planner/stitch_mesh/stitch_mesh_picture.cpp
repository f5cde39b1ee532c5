#include "planner/stitch_mesh/stitch_mesh_picture.hpp"

#include <cairo.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <utility>

#include "planner/common/index.hpp"
#include "planner/render/png.hpp"

namespace planner {

using Vec3 = Eigen::Vector3d;

namespace {

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
  const std::string failure = render::write_png_file(surface, png_path);
  cairo_surface_destroy(surface);
  return failure;
}

}  // namespace planner
