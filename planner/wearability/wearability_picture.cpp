#include "planner/wearability/wearability_picture.hpp"

#include <cairo.h>

#include <algorithm>
#include <cstddef>
#include <ostream>
#include <utility>

#include "planner/render/four_views.hpp"

namespace planner {

// A 3/4 view of the garment with its arcs coloured: green sewn, red laced,
// or — over several runs — from green to red by the probability of being
// laced (Fig. 18). Faces are drawn back to front and shaded by a head light;
// arcs are drawn over them, dashed where they face away from the viewer.
void draw_wearability(std::ostream& out, const CoverMesh& mesh,
                      const std::vector<double>& lace_share, const TrialOutcome* caught) {
  constexpr int kSize = 900;
  render::Scene scene;
  scene.positions = mesh.positions;
  scene.faces.reserve(mesh.faces.size());
  // A face whose centroid lies within the caught radius (at least one mean
  // edge length, so that a point still shows) of where the garment stays
  // caught takes the second paint. The trial's caught vertices had not come
  // off the wearer, so they lie near where the garment rests on it.
  double radius = 0;
  if (caught != nullptr) {
    double length = 0;
    std::size_t sides = 0;
    for (const auto& face : mesh.faces) {
      for (std::size_t i = 0; i < face.size(); ++i, ++sides) {
        length += (mesh.positions[static_cast<std::size_t>(face[i])] -
                   mesh.positions[static_cast<std::size_t>(face[(i + 1) % face.size()])])
                      .norm();
      }
    }
    radius = std::max(caught->caught_radius, sides > 0 ? length / static_cast<double>(sides) : 0);
  }
  int caught_faces = 0;
  for (const auto& face : mesh.faces) {
    int paint = 0;
    if (caught != nullptr && !face.empty()) {
      Vec3 centroid = Vec3::Zero();
      for (const int v : face) centroid += mesh.positions[static_cast<std::size_t>(v)];
      centroid /= static_cast<double>(face.size());
      if ((centroid - caught->caught_at).norm() <= radius) {
        paint = 1;
        ++caught_faces;
      }
    }
    scene.faces.push_back({face, paint, {}, 0});
  }
  // Shaded by a head light; thin grey outlines.
  scene.paints = {{{1, 1, 1.02}, {1, 1, 1.02}}, {{1, 0.62, 0.2}, {1, 0.62, 0.2}}};
  scene.light = render::Vec3(0, 0, 1);
  scene.ambient = 0.55;
  scene.diffuse = 0.4;
  scene.outline = true;
  scene.outline_style = {{0.45, 0.45, 0.45}, 1, 0.5, 0.5, false, false};
  for (std::size_t a = 0; a < mesh.arcs.size(); ++a) {
    const double t = std::clamp(a < lace_share.size() ? lace_share[a] : 1.0, 0.0, 1.0);
    scene.line_styles.push_back(
        {{0.15 + 0.7 * t, 0.6 * (1 - t) + 0.1, 0.2}, 1, 4, 2, true, false, 6});
    for (const auto& [u, v] : mesh.arcs[a].edges)
      scene.overlay.push_back({u, v, static_cast<int>(a)});
  }
  render::Options options;
  options.views = {render::View{0.6, 0.45}};
  options.columns = 1;
  options.panel_px = kSize;
  options.fit = render::Fit::ViewBox;
  render::FourViews picture(options);
  picture.draw(scene);
  cairo_t* cr = picture.cairo();
  // Legend, bottom left: sew, lace (with several runs the colour runs
  // between them with the share of runs that laced the arc), and what
  // dashes mean.
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 14);
  double x = 40;
  const std::pair<const char*, render::Rgb> entries[] = {{"sew", {0.15, 0.7, 0.2}},
                                                         {"lace", {0.85, 0.1, 0.2}}};
  for (const auto& [label, colour] : entries) {
    render::set_source(cr, colour);
    cairo_rectangle(cr, x, kSize - 36, 24, 16);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_move_to(cr, x + 30, kSize - 23);
    cairo_show_text(cr, label);
    x += 90;
  }
  if (caught_faces > 0) {
    cairo_set_source_rgb(cr, 1, 0.62, 0.2);
    cairo_rectangle(cr, x, kSize - 36, 24, 16);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_move_to(cr, x + 30, kSize - 23);
    cairo_show_text(cr, "caught on the wearer");
    x += 190;
  }
  cairo_move_to(cr, x, kSize - 23);
  cairo_show_text(cr, "dashed: on the far side");
  picture.write_png(out);
}

}  // namespace planner
