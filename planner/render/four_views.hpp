// The planner's 3D pictures (cuts-3d.png, stitch-mesh.png, wearability.png,
// assembly-3d.png): one renderer for all of them. A scene of polygons and
// lines is seen orthographically from a list of views, by default the four
// sides (front, right, back, left, each from 20 degrees above) in a 2 x 2
// grid of square panels. The pictures differ only in their scenes (colours,
// line styles, light) and options, not in code.
//
// What hides what is decided one of two ways:
// - painter's order (the default): vector drawing with Cairo, antialiased;
//   per panel the faces far to near (by the mean depth of their corners),
//   every face filled, then outlined, then its own marked sides stroked, so
//   that nearer faces hide them; the overlay lines last, over every face.
//   Right for one surface; wrong where surfaces cross or lie within a face's
//   size of each other.
// - a depth buffer (Options::depth_buffer): every face rasterised pixel by
//   pixel as a fan of triangles, each shaded by its own normal, then the
//   marked sides as round dots along them, all depth-tested (the overlay
//   lines over everything), without antialiasing, outlines or dashes. Right
//   for a garment worn over its wearer (or over itself), where painter's
//   order fails; `depth_bias` lifts the garment and its seams just in front
//   of the wearer.
#pragma once

#include <cairo.h>

#include <Eigen/Core>
#include <iosfwd>
#include <string>
#include <vector>

#include "planner/render/colour.hpp"

namespace planner::render {

using Vec3 = Eigen::Vector3d;

// A direction to look from: the scene is turned `yaw` radians about its up
// axis (y), then tilted `pitch` radians about x, and seen along -z.
struct View {
  double yaw = 0;
  double pitch = 0;
  static View degrees(double yaw_deg, double pitch_deg);
};

// Front, right, back and left, each from 20 degrees above.
std::vector<View> four_views();

// `p` turned into `view`: x to the right, y up, z towards the viewer.
Vec3 turn(const View& view, const Vec3& p);

// How a line is stroked. Widths are pixels; `width` on a face turned towards
// the viewer (or an overlay line in front), `back_width` otherwise.
struct LineStyle {
  Rgb colour;
  double alpha = 1;
  double width = 1;
  double back_width = 1;
  bool round_caps = true;   // else butt caps
  bool round_joins = true;  // else mitred joins
  double back_dash = 0;     // overlay lines at the back: dashes this long (0: solid)
  double depth_bias = 0;    // depth buffer only: towards the viewer, scene units
};

// How a face is filled: `front` or `back` (the side the viewer sees) times the
// shade, ambient + diffuse * |normal . light|, dimmed by `back_dim` on the back.
struct Paint {
  Rgb front;
  Rgb back;
  double back_dim = 1;
};

struct Scene {
  struct Face {
    std::vector<int> corners;  // into `positions`, in order
    int paint = 0;             // into `paints`
    // Per side (from corner i to corner i + 1) a style in `line_styles`, or
    // -1; empty when no side is stroked.
    std::vector<int> sides;
    // Towards the viewer (scene units): added to the face's depth when
    // sorting, or to every pixel's depth in the depth buffer.
    double depth_bias = 0;
  };
  struct Segment {
    int a = 0;
    int b = 0;
    int style = 0;  // into `line_styles`
  };

  std::vector<Vec3> positions;
  std::vector<Face> faces;
  std::vector<Paint> paints;
  std::vector<LineStyle> line_styles;
  // Lines drawn over every face, in order. One is at the back when the faces
  // around its ends are turned away from the viewer (their normals' z summed).
  std::vector<Segment> overlay;

  Vec3 light = Vec3(0.3, 0.5, 1.0).normalized();
  double ambient = 0.35;
  double diffuse = 0.6;
  bool outline = false;  // stroke every face's outline with `outline_style`
  LineStyle outline_style;
};

// How the scene fills a panel.
enum class Fit {
  // Every view centred on the centroid of the positions, the farthest
  // position 0.46 panel away from it: one scale for every view.
  Centroid,
  // The same around the centre of the positions' box and its half diagonal.
  Box,
  // The view's own box of the turned positions fills the panel less a
  // margin of `margin_px` around and `bottom_px` below.
  ViewBox,
};

struct Options {
  std::vector<View> views = four_views();
  int columns = 2;
  int panel_px = 600;
  Fit fit = Fit::Centroid;
  double margin_px = 40;      // Fit::ViewBox only
  double bottom_px = 60;      // Fit::ViewBox only
  int strip_px = 0;           // a white strip below the panels (a legend goes there)
  bool panel_lines = false;   // thin grey lines between the panels
  bool depth_buffer = false;  // decide visibility per pixel (see the top of this file)
};

// The sphere Fit::Centroid or Fit::Box fits into every panel (for Fit::ViewBox:
// the origin and a radius of 1e-9).
struct Sphere {
  Vec3 centre = Vec3::Zero();
  double radius = 1e-9;
};
Sphere fit_sphere(const std::vector<Vec3>& positions, Fit fit);

// A white picture of the panels; draw() draws a scene into them. cairo()
// draws anything else (a legend); the PNG is written at the end.
class FourViews {
 public:
  explicit FourViews(Options options);
  ~FourViews();
  FourViews(const FourViews&) = delete;
  FourViews& operator=(const FourViews&) = delete;

  void draw(const Scene& scene);

  cairo_t* cairo() const { return cr_; }
  int width() const { return width_; }
  int height() const { return height_; }

  // The picture as PNG (png.hpp): to a stream (throws std::runtime_error), or
  // atomically to a file (returns "" or the failure).
  void write_png(std::ostream& out) const;
  std::string write_png_file(const std::string& path) const;

 private:
  void draw_panel(const Scene& scene, int panel, const Sphere& sphere);

  Options options_;
  int rows_ = 1;
  int width_ = 0;
  int height_ = 0;
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
};

}  // namespace planner::render
