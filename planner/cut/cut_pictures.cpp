#include "planner/cut/cut_pictures.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "planner/common/index.hpp"
#include "planner/render/png.hpp"

namespace planner {

namespace {

struct View {
  double yaw_deg;
  double pitch_deg;
};

}  // namespace

std::string draw_cuts_3d(const CutMesh& cut, const std::string& png_path, int panel_px) {
  const HalfedgeMesh& q = cut.proxy;
  const int size = panel_px * 2;
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, size, size);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  Vec3 center = Vec3::Zero();
  for (int v = 0; v < q.num_vertices(); ++v) center += q.position(v);
  center /= std::max(1, q.num_vertices());
  double radius = 1e-9;
  for (int v = 0; v < q.num_vertices(); ++v)
    radius = std::max(radius, (q.position(v) - center).norm());
  const View views[4] = {{0, 20}, {90, 20}, {180, 20}, {270, 20}};
  const Vec3 light = Vec3(0.3, 0.5, 1.0).normalized();
  for (int panel = 0; panel < 4; ++panel) {
    const double yaw = views[panel].yaw_deg * M_PI / 180.0;
    const double pitch = views[panel].pitch_deg * M_PI / 180.0;
    // Rotate about y (yaw), then tilt about x (pitch); the camera looks down -z.
    auto transform = [&](const Vec3& p) {
      Vec3 r = p - center;
      const double x = std::cos(yaw) * r.x() + std::sin(yaw) * r.z();
      const double z = -std::sin(yaw) * r.x() + std::cos(yaw) * r.z();
      const double y2 = std::cos(pitch) * r.y() - std::sin(pitch) * z;
      const double z2 = std::sin(pitch) * r.y() + std::cos(pitch) * z;
      return Vec3(x, y2, z2);
    };
    std::vector<Vec3> projected(at(q.num_vertices()));
    for (int v = 0; v < q.num_vertices(); ++v) projected[at(v)] = transform(q.position(v));
    const double ox = (panel % 2) * panel_px + panel_px / 2.0;
    const double oy = (panel / 2) * panel_px + panel_px / 2.0;
    const double scale = 0.46 * panel_px / radius;
    auto to_px = [&](const Vec3& p) {
      return std::pair<double, double>{ox + scale * p.x(), oy - scale * p.y()};
    };
    std::vector<std::pair<double, int>> order;
    order.reserve(at(q.num_faces()));
    for (int f = 0; f < q.num_faces(); ++f) {
      double depth = 0.0;
      for (int i = 0; i < q.degree(f); ++i) depth += projected[at(q.from(q.face_start(f) + i))].z();
      order.emplace_back(depth / q.degree(f), f);
    }
    std::sort(order.begin(), order.end());
    cairo_save(cr);
    cairo_rectangle(cr, (panel % 2) * panel_px, (panel / 2) * panel_px, panel_px, panel_px);
    cairo_clip(cr);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    for (const auto& [depth, f] : order) {
      Vec3 n = Vec3::Zero();
      const int start = q.face_start(f);
      const int degree = q.degree(f);
      for (int i = 0; i < degree; ++i) {
        n += projected[at(q.from(start + i))].cross(projected[at(q.to(start + i))]);
      }
      if (n.norm() > 0) n.normalize();
      const bool front = n.z() > 0;
      const double shade = 0.35 + 0.6 * std::abs(n.dot(light));
      for (int i = 0; i < degree; ++i) {
        const auto [x, y] = to_px(projected[at(q.from(start + i))]);
        if (i == 0)
          cairo_move_to(cr, x, y);
        else
          cairo_line_to(cr, x, y);
      }
      cairo_close_path(cr);
      if (front)
        cairo_set_source_rgb(cr, 0.80 * shade, 0.84 * shade, 0.90 * shade);
      else
        cairo_set_source_rgb(cr, 0.45 * shade, 0.40 * shade, 0.40 * shade);
      cairo_fill_preserve(cr);
      cairo_set_source_rgba(cr, 0.1, 0.1, 0.1, 0.25);
      cairo_set_line_width(cr, 0.5);
      cairo_stroke(cr);
      for (int i = 0; i < degree; ++i) {
        const int h = start + i;
        const int e = q.edge(h);
        const bool boundary = q.twin(h) < 0;
        if (!boundary && !cut.cut_edge[at(e)]) continue;
        const auto [x0, y0] = to_px(projected[at(q.from(h))]);
        const auto [x1, y1] = to_px(projected[at(q.to(h))]);
        cairo_move_to(cr, x0, y0);
        cairo_line_to(cr, x1, y1);
        if (boundary)
          cairo_set_source_rgb(cr, 0.1, 0.3, 0.9);
        else
          cairo_set_source_rgb(cr, 0.85, 0.05, 0.05);
        cairo_set_line_width(cr, front ? 2.5 : 1.2);
        cairo_stroke(cr);
      }
    }
    cairo_restore(cr);
  }
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_set_line_width(cr, 1.0);
  cairo_move_to(cr, panel_px, 0);
  cairo_line_to(cr, panel_px, size);
  cairo_move_to(cr, 0, panel_px);
  cairo_line_to(cr, size, panel_px);
  cairo_stroke(cr);
  cairo_destroy(cr);
  cairo_surface_flush(surface);
  std::string failure = render::write_png_file(surface, png_path);
  cairo_surface_destroy(surface);
  return failure;
}

std::string draw_layout_2d(const CutMesh& cut, const std::string& png_path, int size_px) {
  const HalfedgeMesh& q = cut.proxy;
  int umin = 0, umax = 0, vmin = 0, vmax = 0;
  int max_count = 1;
  for (int f = 0; f < q.num_faces(); ++f) {
    umin = std::min(umin, cut.face_uv[at(f)][0]);
    umax = std::max(umax, cut.face_uv[at(f)][0]);
    vmin = std::min(vmin, cut.face_uv[at(f)][1]);
    vmax = std::max(vmax, cut.face_uv[at(f)][1]);
    max_count = std::max(max_count, cut.overlap_count[at(f)]);
  }
  const double span = std::max(umax - umin + 1, vmax - vmin + 1);
  const double margin = 10.0;
  const double cell = (size_px - 2 * margin) / span;
  const int width = static_cast<int>(std::ceil((umax - umin + 1) * cell + 2 * margin));
  const int height = static_cast<int>(std::ceil((vmax - vmin + 1) * cell + 2 * margin));
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  auto x_of = [&](double u) { return margin + (u - umin) * cell; };
  auto y_of = [&](double v) { return height - margin - (v - vmin) * cell; };
  // One fill per occupied cell, darker per layer (§4.2 overlap count).
  std::unordered_map<std::int64_t, int> drawn;
  for (int f = 0; f < q.num_faces(); ++f) {
    const auto& uv = cut.face_uv[at(f)];
    const std::int64_t key = (static_cast<std::int64_t>(uv[0]) << 32) ^ (uv[1] & 0xffffffff);
    if (!drawn.emplace(key, 1).second) continue;
    const int count = cut.overlap_count[at(f)];
    const double grey = count <= 1 ? 0.85 : std::max(0.15, 0.70 - 0.15 * (count - 2));
    cairo_set_source_rgb(cr, grey, grey, grey);
    cairo_rectangle(cr, x_of(uv[0]), y_of(uv[1] + 1), cell, cell);
    cairo_fill(cr);
  }
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_width(cr, std::clamp(cell * 0.25, 0.8, 3.0));
  for (int h = 0; h < q.num_halfedges(); ++h) {
    const bool boundary = q.twin(h) < 0;
    if (!boundary && !cut.cut_edge[at(q.edge(h))]) continue;
    const auto& uv = cut.face_uv[at(q.face(h))];
    const double u = uv[0];
    const double v = uv[1];
    // The side of the unit square a direction is traversed along, counter-clockwise.
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    switch (cut.direction[at(h)]) {
      case 0:
        x0 = u, y0 = v, x1 = u + 1, y1 = v;
        break;
      case 1:
        x0 = u + 1, y0 = v, x1 = u + 1, y1 = v + 1;
        break;
      case 2:
        x0 = u + 1, y0 = v + 1, x1 = u, y1 = v + 1;
        break;
      default:
        x0 = u, y0 = v + 1, x1 = u, y1 = v;
        break;
    }
    cairo_move_to(cr, x_of(x0), y_of(y0));
    cairo_line_to(cr, x_of(x1), y_of(y1));
    if (boundary)
      cairo_set_source_rgb(cr, 0.1, 0.3, 0.9);
    else
      cairo_set_source_rgb(cr, 0.85, 0.05, 0.05);
    cairo_stroke(cr);
  }
  cairo_destroy(cr);
  cairo_surface_flush(surface);
  std::string failure = render::write_png_file(surface, png_path);
  cairo_surface_destroy(surface);
  return failure;
}

}  // namespace planner
