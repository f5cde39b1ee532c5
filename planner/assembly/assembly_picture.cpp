#include "planner/assembly/assembly_picture.hpp"

#include <cairo.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "planner/assembly/assembly_canvas.hpp"
#include "planner/common/index.hpp"
#include "planner/render/png.hpp"

namespace planner::assembly {

std::string draw_assembly_3d(const Model& m, const std::optional<PolygonMesh>& wearer,
                             const std::string& png_path) {
  constexpr int kPanel = 450;
  constexpr int kLegend = 36;
  const int width = 2 * kPanel;
  const int height = 2 * kPanel + kLegend;
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(surface);
    return png_path + ": error: [A006] cairo could not make the picture";
  }
  cairo_surface_flush(surface);
  unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  std::fill(data, data + static_cast<std::ptrdiff_t>(stride) * height, 255);

  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  auto grow = [&](const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const auto& p : m.mesh.positions) grow(p);
  if (wearer) {
    for (const auto& p : wearer->positions) grow(p);
  }
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * (hi - lo).norm(), 1e-9);
  const Eigen::Vector3d light = Eigen::Vector3d(0.3, 0.5, 1.0).normalized();

  const double yaws[4] = {0, 90, 180, 270};
  std::vector<float> depth(static_cast<std::size_t>(kPanel) * kPanel);
  for (int panel = 0; panel < 4; ++panel) {
    const double yaw = yaws[panel] * M_PI / 180;
    const double pitch = 20 * M_PI / 180;
    const Eigen::Matrix3d rot = (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()) *
                                 Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()))
                                    .toRotationMatrix();
    const double scale = 0.46 * kPanel / radius;
    const int ox = (panel % 2) * kPanel;
    const int oy = (panel / 2) * kPanel;
    auto project = [&](const Eigen::Vector3d& p) {
      const Eigen::Vector3d q = rot * (p - centre);
      return Eigen::Vector3d(kPanel / 2.0 + q.x() * scale, kPanel / 2.0 - q.y() * scale,
                             q.z() * scale);
    };
    std::fill(depth.begin(), depth.end(), -std::numeric_limits<float>::infinity());
    auto put = [&](int x, int y, double z, Rgb c) {
      if (x < 0 || y < 0 || x >= kPanel || y >= kPanel) return;
      float& d = depth[static_cast<std::size_t>(y) * kPanel + static_cast<std::size_t>(x)];
      if (z < d) return;
      d = static_cast<float>(z);
      unsigned char* px = data + static_cast<std::ptrdiff_t>(oy + y) * stride + (ox + x) * 4;
      px[0] = static_cast<unsigned char>(std::lround(c.b * 255));
      px[1] = static_cast<unsigned char>(std::lround(c.g * 255));
      px[2] = static_cast<unsigned char>(std::lround(c.r * 255));
    };
    auto triangle = [&](const Eigen::Vector3d& a3, const Eigen::Vector3d& b3,
                        const Eigen::Vector3d& c3, Rgb base, double bias) {
      Eigen::Vector3d n = (b3 - a3).cross(c3 - a3);
      if (n.norm() == 0) return;
      n = rot * n.normalized();
      const double shade = 0.35 + 0.65 * std::abs(n.dot(light));
      const Rgb col{base.r * shade, base.g * shade, base.b * shade};
      const Eigen::Vector3d a = project(a3), b = project(b3), c = project(c3);
      const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
      if (std::abs(area) < 1e-12) return;
      const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
      const int x1 =
          std::min(kPanel - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
      const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
      const int y1 =
          std::min(kPanel - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const double px = x + 0.5, py = y + 0.5;
          const double w0 = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
          const double w1 = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
          const double w2 = 1 - w0 - w1;
          if (w0 < 0 || w1 < 0 || w2 < 0) continue;
          put(x, y, w0 * a.z() + w1 * b.z() + w2 * c.z() + bias, col);
        }
      }
    };
    auto segment = [&](const Eigen::Vector3d& a3, const Eigen::Vector3d& b3, Rgb col,
                       double half_width, double bias) {
      const Eigen::Vector3d a = project(a3), b = project(b3);
      const int steps = std::max(1, static_cast<int>(std::ceil((b - a).head<2>().norm())));
      const int r = static_cast<int>(std::ceil(half_width));
      for (int k = 0; k <= steps; ++k) {
        const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(k) / steps);
        for (int dy = -r; dy <= r; ++dy) {
          for (int dx = -r; dx <= r; ++dx) {
            if (dx * dx + dy * dy > half_width * half_width + 0.25) continue;
            put(static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy, p.z() + bias, col);
          }
        }
      }
    };
    const double unit = scale * radius;  // depth units per radius
    if (wearer) {
      for (const auto& face : wearer->faces) {
        for (std::size_t k = 1; k + 1 < face.size(); ++k)
          triangle(wearer->positions[at(face[0])], wearer->positions[at(face[k])],
                   wearer->positions[at(face[k + 1])], {0.62, 0.68, 0.78}, 0);
      }
    }
    for (const StitchFace& face : m.mesh.faces) {
      for (std::size_t k = 1; k + 1 < face.vertices.size(); ++k)
        triangle(m.mesh.positions[face.vertices[0]], m.mesh.positions[face.vertices[k]],
                 m.mesh.positions[face.vertices[k + 1]], {0.96, 0.86, 0.58}, 0.006 * unit);
    }
    for (const Seam& seam : m.seams) {
      for (const auto& sides : seam.sides) {
        for (const SideRef& s : sides) {
          const auto v = side_vertices(m, s);
          segment(m.mesh.positions[v[0]], m.mesh.positions[v[1]],
                  seam.lace ? kLaceColour : kSewColour, 2.0, 0.02 * unit);
        }
      }
    }
  }
  cairo_surface_mark_dirty(surface);
  cairo_t* cr = cairo_create(surface);
  // Legend strip.
  const double y = 2 * kPanel + kLegend / 2.0;
  auto key = [&](double x, Rgb c, const char* label) {
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_rectangle(cr, x, y - 5, 30, 5);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, kText.r, kText.g, kText.b);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 14);
    cairo_move_to(cr, x + 38, y + 2);
    cairo_show_text(cr, label);
  };
  key(20, kSewColour, "sew");
  key(130, kLaceColour, "lace");
  key(250, {0.96, 0.86, 0.58}, "garment");
  if (wearer) key(390, {0.62, 0.68, 0.78}, "wearer");
  cairo_destroy(cr);
  const std::string failure = render::write_png_file(surface, png_path);
  cairo_surface_destroy(surface);
  return failure.empty() ? "" : "error: [A006] " + failure;
}

}  // namespace planner::assembly
