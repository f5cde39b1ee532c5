#include "planner/stitch_mesh/stitch_mesh_picture.hpp"

#include <cairo.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "planner/common/index.hpp"
#include "planner/render/four_views.hpp"

namespace planner {

namespace {

constexpr std::array<FaceType, 4> kTypes = {FaceType::Knit, FaceType::Increase, FaceType::Decrease,
                                            FaceType::ShortRow};

render::Rgb type_colour(FaceType type) {
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
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  for (const StitchFace& face : mesh.faces) {
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      ++directed[{face.vertices[i], face.vertices[(i + 1) % face.vertices.size()]}];
    }
  }
  render::Scene scene;
  scene.positions = mesh.positions;
  for (FaceType type : kTypes) {
    const render::Rgb colour = type_colour(type);
    scene.paints.push_back({colour, colour, 0.6});
  }
  scene.ambient = 0.45;
  scene.diffuse = 0.55;
  constexpr int kBoundary = 0;
  constexpr int kWale = 1;
  constexpr int kCourse = 2;
  scene.line_styles = {{{0.85, 0.05, 0.05}, 1, 2.0, 1.0, false},
                       {{0.1, 0.1, 0.1}, 0.25, 0.4, 0.4, false},
                       {{0.1, 0.1, 0.1}, 0.6, 0.7, 0.7, false}};
  scene.faces.reserve(mesh.faces.size());
  for (const StitchFace& face : mesh.faces) {
    render::Scene::Face& out = scene.faces.emplace_back();
    out.paint =
        static_cast<int>(std::find(kTypes.begin(), kTypes.end(), face.type) - kTypes.begin());
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t a = face.vertices[i];
      const std::uint32_t b = face.vertices[(i + 1) % n];
      out.corners.push_back(static_cast<int>(a));
      out.sides.push_back(directed.find({b, a}) == directed.end() ? kBoundary
                          : face.roles[i] == EdgeRole::Wale       ? kWale
                                                                  : kCourse);
    }
  }
  render::Options options;
  options.panel_px = panel_px;
  render::FourViews picture(options);
  picture.draw(scene);
  const int size = picture.height();
  cairo_t* cr = picture.cairo();
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
    render::set_source(cr, type_colour(type));
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
  return picture.write_png_file(png_path);
}

}  // namespace planner
