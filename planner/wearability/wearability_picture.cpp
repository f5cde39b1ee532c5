#include "planner/wearability/wearability_picture.hpp"

#include <cairo.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <ostream>
#include <utility>

#include "planner/render/png.hpp"

namespace planner {

// A 3/4 view of the garment with its arcs coloured: green sewn, red laced,
// or — over several runs — from green to red by the probability of being
// laced (Fig. 18). Faces are drawn back to front and shaded by a head light;
// arcs are drawn over them, dashed where they face away from the viewer.
void draw_wearability(std::ostream& out, const CoverMesh& mesh,
                      const std::vector<double>& lace_share) {
  constexpr int kSize = 900;
  const double yaw = 0.6, pitch = 0.45;
  const Eigen::Matrix3d view = (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()))
                                   .toRotationMatrix();
  std::vector<Eigen::Vector3d> p;
  Eigen::AlignedBox3d box;
  for (const auto& v : mesh.positions) {
    p.push_back(view * v);
    box.extend(p.back());
  }
  const double extent = std::max(box.sizes().x(), box.sizes().y());
  const double scale = (kSize - 80) / std::max(extent, 1e-300);
  auto screen_x = [&](const Eigen::Vector3d& q) { return 40 + (q.x() - box.min().x()) * scale; };
  auto screen_y = [&](const Eigen::Vector3d& q) {
    return kSize - 60 - (q.y() - box.min().y()) * scale;
  };

  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, kSize, kSize);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  std::vector<std::pair<double, std::size_t>> order;
  std::vector<double> facing(mesh.faces.size(), 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    double depth = 0;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < face.size(); ++i) {
      depth += p[face[i]].z();
      normal += p[face[i]].cross(p[face[(i + 1) % face.size()]]);
    }
    facing[f] = normal.norm() > 0 ? normal.normalized().z() : 0;
    order.push_back({depth / face.size(), f});
  }
  std::sort(order.begin(), order.end());  // far (negative z) first
  cairo_set_line_width(cr, 0.5);
  for (const auto& [depth, f] : order) {
    const auto& face = mesh.faces[f];
    cairo_move_to(cr, screen_x(p[face[0]]), screen_y(p[face[0]]));
    for (std::size_t i = 1; i < face.size(); ++i)
      cairo_line_to(cr, screen_x(p[face[i]]), screen_y(p[face[i]]));
    cairo_close_path(cr);
    const double shade = 0.55 + 0.4 * std::abs(facing[f]);
    cairo_set_source_rgb(cr, shade, shade, shade * 1.02);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.45, 0.45, 0.45);
    cairo_stroke(cr);
  }
  // Which side a vertex faces: average of its faces' facing.
  std::vector<double> vertex_facing(mesh.positions.size(), 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (int v : mesh.faces[f]) vertex_facing[v] += facing[f];
  }
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  for (std::size_t a = 0; a < mesh.arcs.size(); ++a) {
    const double t = std::clamp(a < lace_share.size() ? lace_share[a] : 1.0, 0.0, 1.0);
    for (const auto& [u, v] : mesh.arcs[a].edges) {
      const bool front = vertex_facing[u] + vertex_facing[v] >= 0;
      const double dash = 6;
      cairo_set_dash(cr, front ? nullptr : &dash, front ? 0 : 1, 0);
      cairo_set_line_width(cr, front ? 4 : 2);
      cairo_set_source_rgb(cr, 0.15 + 0.7 * t, 0.6 * (1 - t) + 0.1, 0.2);
      cairo_move_to(cr, screen_x(p[u]), screen_y(p[u]));
      cairo_line_to(cr, screen_x(p[v]), screen_y(p[v]));
      cairo_stroke(cr);
    }
  }
  cairo_set_dash(cr, nullptr, 0, 0);
  // Legend, bottom left: sew, lace (with several runs the colour runs
  // between them with the share of runs that laced the arc), and what
  // dashes mean.
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 14);
  double x = 40;
  const std::pair<const char*, std::array<double, 3>> entries[] = {{"sew", {0.15, 0.7, 0.2}},
                                                                   {"lace", {0.85, 0.1, 0.2}}};
  for (const auto& [label, colour] : entries) {
    cairo_set_source_rgb(cr, colour[0], colour[1], colour[2]);
    cairo_rectangle(cr, x, kSize - 36, 24, 16);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_move_to(cr, x + 30, kSize - 23);
    cairo_show_text(cr, label);
    x += 90;
  }
  cairo_move_to(cr, x, kSize - 23);
  cairo_show_text(cr, "dashed: on the far side");
  cairo_surface_flush(surface);
  cairo_destroy(cr);
  render::write_png(surface, out);
  cairo_surface_destroy(surface);
}

}  // namespace planner
