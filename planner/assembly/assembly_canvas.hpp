// Where the assembly guide's pages are drawn (internal to planner/assembly/):
// one small canvas interface with two back ends, SVG text (numbers stay text,
// so they can be searched) and Cairo (PDF, PNG). Page coordinates are points,
// y down, on an A4 landscape page.
#pragma once

#include <cairo.h>

#include <sstream>
#include <string>
#include <vector>

#include "planner/render/colour.hpp"

namespace planner::assembly {

using render::Rgb;

struct P2 {
  double x = 0;
  double y = 0;
};

// The guide's colours, on the pages and in the 3D picture.
inline constexpr Rgb kSewColour{0.10, 0.35, 0.80};
inline constexpr Rgb kLaceColour{0.85, 0.15, 0.15};
inline constexpr Rgb kEdgeColour{0.15, 0.15, 0.15};
inline constexpr Rgb kFabric{0.91, 0.89, 0.84};
inline constexpr Rgb kText{0.1, 0.1, 0.1};
inline constexpr Rgb kWhite{1, 1, 1};

constexpr double kPageW = 842;  // A4 landscape, points
constexpr double kPageH = 595;
constexpr double kMargin = 30;

enum class Anchor { Start, Middle, End };

// `cls` names the SVG class of what is drawn (the Cairo back end ignores it).
class Canvas {
 public:
  virtual ~Canvas() = default;
  virtual void next_page() = 0;
  virtual void fill_polygons(const std::vector<std::vector<P2>>& polygons, Rgb fill) = 0;
  virtual void polyline(const std::vector<P2>& points, Rgb colour, double width, bool dashed,
                        const char* cls) = 0;
  virtual void circle(P2 centre, double radius, Rgb fill, Rgb stroke, double width) = 0;
  virtual void text(P2 at, const std::string& s, double size, Rgb colour, Anchor anchor, bool bold,
                    const char* cls) = 0;
};

// Pages are stacked top to bottom in one SVG document, each in a <g
// class="page">.
class SvgCanvas final : public Canvas {
 public:
  explicit SvgCanvas(int pages);
  void next_page() override;
  void fill_polygons(const std::vector<std::vector<P2>>& polygons, Rgb fill) override;
  void polyline(const std::vector<P2>& points, Rgb colour, double width, bool dashed,
                const char* cls) override;
  void circle(P2 c, double radius, Rgb fill, Rgb stroke, double width) override;
  void text(P2 p, const std::string& s, double size, Rgb colour, Anchor anchor, bool bold,
            const char* cls) override;
  std::string document() const;

 private:
  void open_page();
  int pages_ = 1;
  int page_ = 0;
  std::ostringstream body_;
};

class CairoCanvas final : public Canvas {
 public:
  // only_page >= 0: draw that page only (0-based), onto a single-page
  // surface such as a PNG image.
  explicit CairoCanvas(cairo_t* cr, int only_page = -1) : cr_(cr), only_(only_page) {}
  void next_page() override;
  void fill_polygons(const std::vector<std::vector<P2>>& polygons, Rgb fill) override;
  void polyline(const std::vector<P2>& points, Rgb colour, double width, bool dashed,
                const char*) override;
  void circle(P2 c, double radius, Rgb fill, Rgb stroke, double width) override;
  void text(P2 p, const std::string& s, double size, Rgb colour, Anchor anchor, bool bold,
            const char*) override;

 private:
  bool skip() const { return only_ >= 0 && page_ != only_; }
  cairo_t* cr_;
  int only_ = -1;
  int page_ = 0;
};

}  // namespace planner::assembly
