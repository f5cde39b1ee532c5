#include "planner/cut/cut_pictures.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "planner/common/index.hpp"
#include "planner/render/four_views.hpp"
#include "planner/render/png.hpp"

namespace planner {

std::string draw_cuts_3d(const CutMesh& cut, const std::string& png_path, int panel_px) {
  const HalfedgeMesh& q = cut.proxy;
  render::Scene scene;
  scene.positions = q.polygons().positions;
  scene.paints = {{{0.80, 0.84, 0.90}, {0.45, 0.40, 0.40}}};  // outside, inside
  constexpr int kBoundary = 0;
  constexpr int kCut = 1;
  scene.line_styles = {{{0.1, 0.3, 0.9}, 1, 2.5, 1.2}, {{0.85, 0.05, 0.05}, 1, 2.5, 1.2}};
  scene.outline = true;
  scene.outline_style = {{0.1, 0.1, 0.1}, 0.25, 0.5, 0.5};
  scene.faces.resize(at(q.num_faces()));
  for (int f = 0; f < q.num_faces(); ++f) {
    render::Scene::Face& face = scene.faces[at(f)];
    for (int i = 0; i < q.degree(f); ++i) {
      const int h = q.face_start(f) + i;
      face.corners.push_back(q.from(h));
      face.sides.push_back(q.twin(h) < 0 ? kBoundary : cut.cut_edge[at(q.edge(h))] ? kCut : -1);
    }
  }
  render::Options options;
  options.panel_px = panel_px;
  options.panel_lines = true;
  render::FourViews picture(options);
  picture.draw(scene);
  return picture.write_png_file(png_path);
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
