#include "planner/render/four_views.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <utility>

#include "planner/common/index.hpp"
#include "planner/render/png.hpp"

namespace planner::render {

namespace {

// One panel's view of the scene: the turned positions and where they land.
struct Projection {
  std::vector<Vec3> turned;
  // The image pixel of the view's point (min_x, min_y): the centre of the
  // fitted sphere, or for Fit::ViewBox the lower left of the view's box.
  double ox = 0;
  double oy = 0;
  double min_x = 0;
  double min_y = 0;
  double scale = 1;  // pixels per scene unit

  void move(cairo_t* cr, int v, bool first) const {
    const Vec3& p = turned[at(v)];
    const double x = ox + scale * (p.x() - min_x);
    const double y = oy - scale * (p.y() - min_y);
    (first ? cairo_move_to : cairo_line_to)(cr, x, y);
  }
};

void stroke(cairo_t* cr, const LineStyle& style, double width) {
  set_source(cr, style.colour, style.alpha);
  cairo_set_line_width(cr, width);
  cairo_set_line_cap(cr, style.round_caps ? CAIRO_LINE_CAP_ROUND : CAIRO_LINE_CAP_BUTT);
  cairo_set_line_join(cr, style.round_joins ? CAIRO_LINE_JOIN_ROUND : CAIRO_LINE_JOIN_MITER);
  cairo_stroke(cr);
}

// The face's normal in the view (Newell's sum over its sides), unit length
// unless the face has no area.
Vec3 view_normal(const Scene::Face& face, const Projection& pr) {
  Vec3 n = Vec3::Zero();
  const std::size_t count = face.corners.size();
  for (std::size_t i = 0; i < count; ++i)
    n += pr.turned[at(face.corners[i])].cross(pr.turned[at(face.corners[(i + 1) % count])]);
  if (n.norm() > 0) n.normalize();
  return n;
}

// Far faces first.
std::vector<std::pair<double, std::size_t>> painter_order(const Scene& scene,
                                                          const Projection& pr) {
  std::vector<std::pair<double, std::size_t>> order;
  order.reserve(scene.faces.size());
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    const Scene::Face& face = scene.faces[f];
    double depth = 0;
    for (int v : face.corners) depth += pr.turned[at(v)].z();
    order.emplace_back(depth / static_cast<double>(face.corners.size()) + face.depth_bias, f);
  }
  std::sort(order.begin(), order.end());
  return order;
}

void draw_face(cairo_t* cr, const Scene& scene, const Scene::Face& face, const Vec3& normal,
               const Projection& pr) {
  const bool front = normal.z() > 0;
  const Paint& paint = scene.paints[at(face.paint)];
  const double shade = (scene.ambient + scene.diffuse * std::abs(normal.dot(scene.light))) *
                       (front ? 1.0 : paint.back_dim);
  const std::size_t count = face.corners.size();
  for (std::size_t i = 0; i < count; ++i) pr.move(cr, face.corners[i], i == 0);
  cairo_close_path(cr);
  set_source(cr, scaled(front ? paint.front : paint.back, shade));
  if (scene.outline) {
    cairo_fill_preserve(cr);
    stroke(cr, scene.outline_style, scene.outline_style.width);
  } else {
    cairo_fill(cr);
  }
  for (std::size_t i = 0; i < face.sides.size() && i < count; ++i) {
    if (face.sides[i] < 0) continue;
    const LineStyle& style = scene.line_styles[at(face.sides[i])];
    pr.move(cr, face.corners[i], true);
    pr.move(cr, face.corners[(i + 1) % count], false);
    stroke(cr, style, front ? style.width : style.back_width);
  }
}

// The overlay lines; `facing` holds every face's normal z in the view.
void draw_overlay(cairo_t* cr, const Scene& scene, const std::vector<double>& facing,
                  const Projection& pr) {
  std::vector<double> vertex_facing(scene.positions.size(), 0);
  for (std::size_t f = 0; f < scene.faces.size(); ++f) {
    for (int v : scene.faces[f].corners) vertex_facing[at(v)] += facing[f];
  }
  for (const Scene::Segment& s : scene.overlay) {
    const LineStyle& style = scene.line_styles[at(s.style)];
    const bool front = vertex_facing[at(s.a)] + vertex_facing[at(s.b)] >= 0;
    const bool dashed = !front && style.back_dash > 0;
    cairo_set_dash(cr, dashed ? &style.back_dash : nullptr, dashed ? 1 : 0, 0);
    pr.move(cr, s.a, true);
    pr.move(cr, s.b, false);
    stroke(cr, style, front ? style.width : style.back_width);
  }
  cairo_set_dash(cr, nullptr, 0, 0);
}

// Options::depth_buffer: one panel drawn straight into the image's pixels,
// every pixel keeping the colour of the nearest thing drawn on it.
class DepthBuffer {
 public:
  DepthBuffer(cairo_surface_t* surface, int left, int top, int size)
      : data_(cairo_image_surface_get_data(surface)),
        stride_(cairo_image_surface_get_stride(surface)),
        left_(left),
        top_(top),
        size_(size),
        depth_(at(size) * at(size), -std::numeric_limits<float>::infinity()) {}

  void draw(const Scene& scene, const View& view, const Projection& pr) {
    // Panel pixels and depth in pixels.
    std::vector<Vec3> q;
    q.reserve(pr.turned.size());
    const double x0 = pr.ox - left_;
    const double y0 = pr.oy - top_;
    for (const Vec3& t : pr.turned)
      q.emplace_back(x0 + (t.x() - pr.min_x) * pr.scale, y0 - (t.y() - pr.min_y) * pr.scale,
                     t.z() * pr.scale);
    for (const Scene::Face& face : scene.faces) {
      const Paint& paint = scene.paints[at(face.paint)];
      const Vec3& a = scene.positions[at(face.corners[0])];
      for (std::size_t k = 1; k + 1 < face.corners.size(); ++k) {
        const Vec3& b = scene.positions[at(face.corners[k])];
        const Vec3& c = scene.positions[at(face.corners[k + 1])];
        Vec3 n = (b - a).cross(c - a);
        if (n.norm() == 0) continue;
        n = turn(view, n.normalized());
        const bool front = n.z() > 0;
        const double shade = (scene.ambient + scene.diffuse * std::abs(n.dot(scene.light))) *
                             (front ? 1.0 : paint.back_dim);
        triangle(q[at(face.corners[0])], q[at(face.corners[k])], q[at(face.corners[k + 1])],
                 scaled(front ? paint.front : paint.back, shade), face.depth_bias * pr.scale);
      }
    }
    // The marked sides style by style: at equal depth a later style wins.
    for (std::size_t s = 0; s < scene.line_styles.size(); ++s) {
      const LineStyle& style = scene.line_styles[s];
      for (const Scene::Face& face : scene.faces) {
        const std::size_t count = face.corners.size();
        for (std::size_t i = 0; i < face.sides.size() && i < count; ++i) {
          if (face.sides[i] != static_cast<int>(s)) continue;
          segment(q[at(face.corners[i])], q[at(face.corners[(i + 1) % count])], style.colour,
                  style.width / 2, style.depth_bias * pr.scale);
        }
      }
    }
    // The overlay lines over everything.
    for (const Scene::Segment& seg : scene.overlay) {
      const LineStyle& style = scene.line_styles[at(seg.style)];
      segment(q[at(seg.a)], q[at(seg.b)], style.colour, style.width / 2,
              std::numeric_limits<double>::infinity());
    }
  }

 private:
  void put(int x, int y, double z, Rgb c) {
    if (x < 0 || y < 0 || x >= size_ || y >= size_) return;
    float& d = depth_[at(y) * at(size_) + at(x)];
    if (z < d) return;
    d = static_cast<float>(z);
    unsigned char* px = data_ + static_cast<std::ptrdiff_t>(top_ + y) * stride_ + (left_ + x) * 4;
    px[0] = static_cast<unsigned char>(std::lround(c.b * 255));
    px[1] = static_cast<unsigned char>(std::lround(c.g * 255));
    px[2] = static_cast<unsigned char>(std::lround(c.r * 255));
  }

  // Every pixel whose centre is inside the triangle.
  void triangle(const Vec3& a, const Vec3& b, const Vec3& c, Rgb colour, double bias) {
    const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
    if (std::abs(area) < 1e-12) return;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
    const int x1 =
        std::min(size_ - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
    const int y1 =
        std::min(size_ - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const double px = x + 0.5, py = y + 0.5;
        const double w0 = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
        const double w1 = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
        const double w2 = 1 - w0 - w1;
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        put(x, y, w0 * a.z() + w1 * b.z() + w2 * c.z() + bias, colour);
      }
    }
  }

  // Round dots of radius `half_width` every pixel along the segment.
  void segment(const Vec3& a, const Vec3& b, Rgb colour, double half_width, double bias) {
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).head<2>().norm())));
    const int r = static_cast<int>(std::ceil(half_width));
    for (int k = 0; k <= steps; ++k) {
      const Vec3 p = a + (b - a) * (static_cast<double>(k) / steps);
      for (int dy = -r; dy <= r; ++dy) {
        for (int dx = -r; dx <= r; ++dx) {
          if (dx * dx + dy * dy > half_width * half_width + 0.25) continue;
          put(static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy, p.z() + bias, colour);
        }
      }
    }
  }

  unsigned char* data_;
  int stride_;
  int left_;
  int top_;
  int size_;
  std::vector<float> depth_;
};

}  // namespace

View View::degrees(double yaw_deg, double pitch_deg) {
  return {yaw_deg * M_PI / 180.0, pitch_deg * M_PI / 180.0};
}

std::vector<View> four_views() {
  return {View::degrees(0, 20), View::degrees(90, 20), View::degrees(180, 20),
          View::degrees(270, 20)};
}

Vec3 turn(const View& view, const Vec3& p) {
  // About y (yaw), then about x (pitch).
  const double x = std::cos(view.yaw) * p.x() + std::sin(view.yaw) * p.z();
  const double z = -std::sin(view.yaw) * p.x() + std::cos(view.yaw) * p.z();
  return Vec3(x, std::cos(view.pitch) * p.y() - std::sin(view.pitch) * z,
              std::sin(view.pitch) * p.y() + std::cos(view.pitch) * z);
}

Sphere fit_sphere(const std::vector<Vec3>& positions, Fit fit) {
  Sphere out;
  if (fit == Fit::Centroid) {
    for (const Vec3& p : positions) out.centre += p;
    out.centre /= static_cast<double>(std::max<std::size_t>(1, positions.size()));
    for (const Vec3& p : positions) out.radius = std::max(out.radius, (p - out.centre).norm());
  } else if (fit == Fit::Box && !positions.empty()) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 hi = -lo;
    for (const Vec3& p : positions) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    out.centre = 0.5 * (lo + hi);
    out.radius = std::max(0.5 * (hi - lo).norm(), 1e-9);
  }
  return out;
}

FourViews::FourViews(Options options) : options_(std::move(options)) {
  const int panels = static_cast<int>(options_.views.size());
  if (options_.columns < 1 || options_.panel_px < 1 || panels < 1)
    throw std::logic_error("FourViews: no panel to draw");
  rows_ = (panels + options_.columns - 1) / options_.columns;
  width_ = std::min(panels, options_.columns) * options_.panel_px;
  height_ = rows_ * options_.panel_px + options_.strip_px;
  surface_ = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width_, height_);
  cr_ = cairo_create(surface_);
  cairo_set_source_rgb(cr_, 1, 1, 1);
  cairo_paint(cr_);
}

FourViews::~FourViews() {
  cairo_destroy(cr_);
  cairo_surface_destroy(surface_);
}

void FourViews::draw(const Scene& scene) {
  const Sphere sphere = fit_sphere(scene.positions, options_.fit);
  for (int panel = 0; panel < static_cast<int>(options_.views.size()); ++panel)
    draw_panel(scene, panel, sphere);
  if (options_.panel_lines) {
    cairo_set_source_rgb(cr_, 0.6, 0.6, 0.6);
    cairo_set_line_width(cr_, 1.0);
    cairo_set_line_cap(cr_, CAIRO_LINE_CAP_BUTT);
    const int panels_h = rows_ * options_.panel_px;
    for (int c = 1; c < options_.columns; ++c) {
      cairo_move_to(cr_, c * options_.panel_px, 0);
      cairo_line_to(cr_, c * options_.panel_px, panels_h);
    }
    for (int r = 1; r < rows_; ++r) {
      cairo_move_to(cr_, 0, r * options_.panel_px);
      cairo_line_to(cr_, width_, r * options_.panel_px);
    }
    cairo_stroke(cr_);
  }
}

void FourViews::draw_panel(const Scene& scene, int panel, const Sphere& sphere) {
  const View& view = options_.views[at(panel)];
  const int px = options_.panel_px;
  const int left = (panel % options_.columns) * px;
  const int top = (panel / options_.columns) * px;
  Projection pr;
  pr.turned.reserve(scene.positions.size());
  for (const Vec3& p : scene.positions) pr.turned.push_back(turn(view, p - sphere.centre));
  if (options_.fit == Fit::ViewBox) {
    Eigen::AlignedBox3d box;
    for (const Vec3& q : pr.turned) box.extend(q);
    const double extent = std::max(box.sizes().x(), box.sizes().y());
    pr.scale = (px - 2 * options_.margin_px) / std::max(extent, 1e-300);
    pr.min_x = box.min().x();
    pr.min_y = box.min().y();
    pr.ox = left + options_.margin_px;
    pr.oy = top + px - options_.bottom_px;
  } else {
    pr.scale = 0.46 * px / sphere.radius;
    pr.ox = left + px / 2.0;
    pr.oy = top + px / 2.0;
  }
  if (options_.depth_buffer) {
    cairo_surface_flush(surface_);
    DepthBuffer buffer(surface_, left, top, px);
    buffer.draw(scene, view, pr);
    cairo_surface_mark_dirty(surface_);
    return;
  }
  cairo_save(cr_);
  cairo_rectangle(cr_, left, top, px, px);
  cairo_clip(cr_);
  std::vector<double> facing(scene.faces.size(), 0);
  for (const auto& [depth, f] : painter_order(scene, pr)) {
    const Vec3 normal = view_normal(scene.faces[f], pr);
    facing[f] = normal.z();
    draw_face(cr_, scene, scene.faces[f], normal, pr);
  }
  if (!scene.overlay.empty()) draw_overlay(cr_, scene, facing, pr);
  cairo_restore(cr_);
}

void FourViews::write_png(std::ostream& out) const {
  render::write_png(surface_, out);
}

std::string FourViews::write_png_file(const std::string& path) const {
  return render::write_png_file(surface_, path);
}

}  // namespace planner::render
