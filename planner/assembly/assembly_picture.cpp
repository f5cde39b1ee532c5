#include "planner/assembly/assembly_picture.hpp"

#include <cairo.h>

#include <cstddef>
#include <vector>

#include "planner/assembly/assembly_canvas.hpp"
#include "planner/common/index.hpp"
#include "planner/render/four_views.hpp"

namespace planner::assembly {

namespace {

constexpr Rgb kGarment{0.96, 0.86, 0.58};
constexpr Rgb kWearer{0.62, 0.68, 0.78};

// The wearer, then the garment with its seams as marked sides. A garment worn
// over itself lies on its wearer: it and its seams are lifted a little
// towards the viewer so that they stay visible.
render::Scene scene_of(const Model& m, const std::optional<PolygonMesh>& wearer) {
  render::Scene scene;
  scene.ambient = 0.35;
  scene.diffuse = 0.65;
  scene.paints = {{kGarment, kGarment}, {kWearer, kWearer}};
  constexpr int kGarmentPaint = 0;
  constexpr int kWearerPaint = 1;
  constexpr int kSew = 0;
  constexpr int kLace = 1;
  if (wearer) {
    scene.positions = wearer->positions;
    for (const auto& face : wearer->faces) scene.faces.push_back({face, kWearerPaint, {}, 0});
  }
  const int offset = static_cast<int>(scene.positions.size());
  scene.positions.insert(scene.positions.end(), m.mesh.positions.begin(), m.mesh.positions.end());
  const double radius = render::fit_sphere(scene.positions, render::Fit::Box).radius;
  scene.line_styles = {{kSewColour, 1, 4.0, 4.0}, {kLaceColour, 1, 4.0, 4.0}};
  for (render::LineStyle& style : scene.line_styles) style.depth_bias = 0.02 * radius;
  for (std::size_t f = 0; f < m.mesh.faces.size(); ++f) {
    const StitchFace& face = m.mesh.faces[f];
    render::Scene::Face& out = scene.faces.emplace_back();
    out.paint = kGarmentPaint;
    out.depth_bias = 0.006 * radius;
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      out.corners.push_back(offset + static_cast<int>(face.vertices[i]));
      const auto seam = m.seam_of_side.find({static_cast<int>(f), static_cast<int>(i)});
      out.sides.push_back(seam == m.seam_of_side.end()     ? -1
                          : m.seams[at(seam->second)].lace ? kLace
                                                           : kSew);
    }
  }
  return scene;
}

}  // namespace

std::string draw_assembly_3d(const Model& m, const std::optional<PolygonMesh>& wearer,
                             const std::string& png_path) {
  constexpr int kPanel = 450;
  constexpr int kLegend = 36;
  render::Options options;
  options.panel_px = kPanel;
  options.strip_px = kLegend;
  options.fit = render::Fit::Box;
  options.depth_buffer = true;
  render::FourViews picture(options);
  picture.draw(scene_of(m, wearer));
  // Legend strip.
  cairo_t* cr = picture.cairo();
  const double y = 2 * kPanel + kLegend / 2.0;
  auto key = [&](double x, Rgb c, const char* label) {
    render::set_source(cr, c);
    cairo_rectangle(cr, x, y - 5, 30, 5);
    cairo_fill(cr);
    render::set_source(cr, kText);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 14);
    cairo_move_to(cr, x + 38, y + 2);
    cairo_show_text(cr, label);
  };
  key(20, kSewColour, "sew");
  key(130, kLaceColour, "lace");
  key(250, kGarment, "garment");
  if (wearer) key(390, kWearer, "wearer");
  const std::string failure = picture.write_png_file(png_path);
  return failure.empty() ? "" : "error: [A006] " + failure;
}

}  // namespace planner::assembly
