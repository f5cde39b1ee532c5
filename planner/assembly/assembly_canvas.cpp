#include "planner/assembly/assembly_canvas.hpp"

#include <cmath>
#include <cstdio>

namespace planner::assembly {

namespace {

std::string hex(Rgb c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", static_cast<int>(std::lround(c.r * 255)),
                static_cast<int>(std::lround(c.g * 255)), static_cast<int>(std::lround(c.b * 255)));
  return buf;
}

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

}  // namespace

SvgCanvas::SvgCanvas(int pages) : pages_(pages) {
  body_ << std::fixed;
  body_.precision(2);
  open_page();
}

void SvgCanvas::next_page() {
  body_ << "</g>\n";
  ++page_;
  open_page();
}

void SvgCanvas::fill_polygons(const std::vector<std::vector<P2>>& polygons, Rgb fill) {
  if (polygons.empty()) return;
  body_ << "<path fill=\"" << hex(fill) << "\" d=\"";
  for (const auto& poly : polygons) {
    for (std::size_t i = 0; i < poly.size(); ++i)
      body_ << (i == 0 ? "M" : "L") << poly[i].x << ' ' << poly[i].y << ' ';
    body_ << "Z ";
  }
  body_ << "\"/>\n";
}

void SvgCanvas::polyline(const std::vector<P2>& points, Rgb colour, double width, bool dashed,
                         const char* cls) {
  if (points.size() < 2) return;
  body_ << "<polyline class=\"" << cls << "\" fill=\"none\" stroke=\"" << hex(colour)
        << "\" stroke-width=\"" << width << "\" stroke-linecap=\"round\"";
  if (dashed) body_ << " stroke-dasharray=\"5 3\"";
  body_ << " points=\"";
  for (const P2& p : points) body_ << p.x << ',' << p.y << ' ';
  body_ << "\"/>\n";
}

void SvgCanvas::circle(P2 c, double radius, Rgb fill, Rgb stroke, double width) {
  body_ << "<circle cx=\"" << c.x << "\" cy=\"" << c.y << "\" r=\"" << radius << "\" fill=\""
        << hex(fill) << "\" stroke=\"" << hex(stroke) << "\" stroke-width=\"" << width << "\"/>\n";
}

void SvgCanvas::text(P2 p, const std::string& s, double size, Rgb colour, Anchor anchor, bool bold,
                     const char* cls) {
  body_ << "<text class=\"" << cls << "\" x=\"" << p.x << "\" y=\"" << p.y
        << "\" font-family=\"sans-serif\" font-size=\"" << size << "\" fill=\"" << hex(colour)
        << '"';
  if (bold) body_ << " font-weight=\"bold\"";
  if (anchor != Anchor::Start)
    body_ << " text-anchor=\"" << (anchor == Anchor::Middle ? "middle" : "end") << '"';
  body_ << '>' << escape(s) << "</text>\n";
}

std::string SvgCanvas::document() const {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kPageW << "pt\" height=\""
      << kPageH * pages_ << "pt\" viewBox=\"0 0 " << kPageW << ' ' << kPageH * pages_ << "\">\n"
      << body_.str() << "</g>\n</svg>\n";
  return out.str();
}

void SvgCanvas::open_page() {
  body_ << "<g class=\"page\" transform=\"translate(0 " << kPageH * page_ << ")\">\n"
        << "<rect width=\"" << kPageW << "\" height=\"" << kPageH
        << "\" fill=\"#ffffff\" stroke=\"#bbbbbb\"/>\n";
}

void CairoCanvas::next_page() {
  ++page_;
  if (only_ < 0) cairo_show_page(cr_);
}

void CairoCanvas::fill_polygons(const std::vector<std::vector<P2>>& polygons, Rgb fill) {
  if (skip()) return;
  for (const auto& poly : polygons) {
    for (std::size_t i = 0; i < poly.size(); ++i)
      (i == 0 ? cairo_move_to : cairo_line_to)(cr_, poly[i].x, poly[i].y);
    cairo_close_path(cr_);
  }
  render::set_source(cr_, fill);
  cairo_fill(cr_);
}

void CairoCanvas::polyline(const std::vector<P2>& points, Rgb colour, double width, bool dashed,
                           const char*) {
  if (skip() || points.size() < 2) return;
  for (std::size_t i = 0; i < points.size(); ++i)
    (i == 0 ? cairo_move_to : cairo_line_to)(cr_, points[i].x, points[i].y);
  render::set_source(cr_, colour);
  cairo_set_line_width(cr_, width);
  cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
  const double dash[2] = {5, 3};
  cairo_set_dash(cr_, dash, dashed ? 2 : 0, 0);
  cairo_stroke(cr_);
  cairo_set_dash(cr_, dash, 0, 0);
}

void CairoCanvas::circle(P2 c, double radius, Rgb fill, Rgb stroke, double width) {
  if (skip()) return;
  cairo_new_path(cr_);
  cairo_arc(cr_, c.x, c.y, radius, 0, 2 * M_PI);
  render::set_source(cr_, fill);
  cairo_fill_preserve(cr_);
  render::set_source(cr_, stroke);
  cairo_set_line_width(cr_, width);
  cairo_stroke(cr_);
}

void CairoCanvas::text(P2 p, const std::string& s, double size, Rgb colour, Anchor anchor,
                       bool bold, const char*) {
  if (skip()) return;
  cairo_select_font_face(cr_, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr_, size);
  cairo_text_extents_t ext;
  cairo_text_extents(cr_, s.c_str(), &ext);
  double x = p.x;
  if (anchor == Anchor::Middle) x -= ext.x_advance / 2;
  if (anchor == Anchor::End) x -= ext.x_advance;
  cairo_move_to(cr_, x, p.y);
  render::set_source(cr_, colour);
  cairo_show_text(cr_, s.c_str());
  cairo_new_path(cr_);
}

}  // namespace planner::assembly
