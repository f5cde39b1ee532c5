#include "planner/assembly/assembly.hpp"

#include <cairo-pdf.h>
#include <cairo.h>

#include <cmath>
#include <optional>
#include <ostream>
#include <stdexcept>

#include "knitout/output_file.hpp"
#include "planner/assembly/assembly_canvas.hpp"
#include "planner/assembly/assembly_model.hpp"
#include "planner/assembly/assembly_page_layout.hpp"
#include "planner/assembly/assembly_pages.hpp"
#include "planner/assembly/assembly_picture.hpp"
#include "planner/render/png.hpp"
#include "planner/wearability/wearability_io.hpp"

namespace planner {

namespace {

namespace fs = std::filesystem;
using assembly::CairoCanvas;
using assembly::Failure;
using assembly::kPageH;
using assembly::kPageW;
using assembly::Model;
using assembly::PageLayout;

struct Guide {
  Model model;
  std::optional<PolygonMesh> wearer;
  PageLayout pages;
};

// Reads the folder and lays out the pages; throws Failure.
void prepare(Guide& g, const fs::path& plan_dir, const std::string& wearer_path,
             std::optional<double> wearer_mm_per_unit) {
  assembly::load(g.model, plan_dir);
  if (!wearer_path.empty()) {
    knitout::DiagnosticSink sink;
    g.wearer = read_stage_mesh(wearer_path, sink);
    if (!g.wearer)
      assembly::fail(wearer_path, "A005",
                     "the wearer cannot be read: " + assembly::first_error(sink));
    const double factor = wearer_mm_per_unit.value_or(g.model.garment_mm_per_unit);
    for (Vec3& p : g.wearer->positions) p *= factor;
  }
  g.pages = assembly::lay_out_pages(
      g.model, "Assembly guide: " + fs::absolute(plan_dir).lexically_normal().filename().string());
}

cairo_status_t write_to_stream(void* closure, const unsigned char* bytes, unsigned int length) {
  auto* o = static_cast<std::ostream*>(closure);
  o->write(reinterpret_cast<const char*>(bytes), static_cast<std::streamsize>(length));
  return *o ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

// The pages as PDF, to `out`; throws std::runtime_error when cairo fails.
void write_pdf(std::ostream& out, const Model& m, const PageLayout& pages) {
  cairo_surface_t* surface =
      cairo_pdf_surface_create_for_stream(write_to_stream, &out, kPageW, kPageH);
  cairo_t* cr = cairo_create(surface);
  CairoCanvas pdf(cr);
  assembly::draw_pages(pdf, m, pages);
  cairo_show_page(cr);
  cairo_destroy(cr);
  cairo_surface_finish(surface);
  const cairo_status_t status = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(std::string("cairo: ") + cairo_status_to_string(status));
}

}  // namespace

std::string write_assembly_guide(const fs::path& plan_dir, const std::string& wearer_path,
                                 AssemblySummary* summary,
                                 std::optional<double> wearer_mm_per_unit) {
  Guide g;
  try {
    prepare(g, plan_dir, wearer_path, wearer_mm_per_unit);
  } catch (const Failure& e) {
    return e.what();
  } catch (const std::logic_error& e) {
    // A broken invariant of the guide's own code: said loudly, never a crash of the caller.
    return plan_dir.string() + ": internal error: " + e.what();
  }
  const Model& m = g.model;
  assembly::SvgCanvas svg(g.pages.pages());
  assembly::draw_pages(svg, m, g.pages);
  const std::string svg_text = svg.document();

  std::string failure = knitout::write_file_atomically(
      (plan_dir / "assembly.pdf").string(), [&](std::ostream& out) { write_pdf(out, m, g.pages); });
  if (!failure.empty()) return "error: [A006] " + failure;
  failure = knitout::write_file_atomically((plan_dir / "assembly.svg").string(),
                                           [&](std::ostream& out) { out << svg_text; });
  if (!failure.empty()) return "error: [A006] " + failure;
  failure = assembly::draw_assembly_3d(m, g.wearer, (plan_dir / "assembly-3d.png").string());
  if (!failure.empty()) return failure;

  if (summary) {
    summary->pieces = static_cast<int>(m.layouts.size());
    summary->seams = m.numbered;
    summary->parts = static_cast<int>(m.seams.size());
    summary->sewn = m.sewn;
    summary->laced = m.numbered - m.sewn;
    for (const assembly::Seam& s : m.seams)
      (s.lace ? summary->laced_mm : summary->sewn_mm) += 0.5 * (s.stretch_mm[0] + s.stretch_mm[1]);
    summary->arcs = static_cast<int>(m.arcs.size());
    summary->pdf_pages = g.pages.pages();
  }
  return "";
}

std::string write_assembly_page_png(const fs::path& plan_dir, int page, const std::string& png_path,
                                    double pixels_per_point) {
  Guide g;
  try {
    prepare(g, plan_dir, "", std::nullopt);
  } catch (const Failure& e) {
    return e.what();
  }
  const int pages = g.pages.pages();
  if (page < 1 || page > pages)
    return png_path + ": error: [A006] the guide has pages 1 to " + std::to_string(pages) +
           ", not " + std::to_string(page);
  const int w = static_cast<int>(std::lround(kPageW * pixels_per_point));
  const int h = static_cast<int>(std::lround(kPageH * pixels_per_point));
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_scale(cr, pixels_per_point, pixels_per_point);
  CairoCanvas canvas(cr, page - 1);
  assembly::draw_pages(canvas, g.model, g.pages);
  cairo_destroy(cr);
  const std::string failure = render::write_png_file(surface, png_path);
  cairo_surface_destroy(surface);
  return failure.empty() ? "" : "error: [A006] " + failure;
}

}  // namespace planner
