#include "simulators/bed/bed_view.hpp"

#include <cairo-svg.h>
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <ostream>

#include "knitout/output_file.hpp"
#include "knitout/writer.hpp"

#if defined(__SANITIZE_ADDRESS__)
// Sanitizer builds only: fontconfig, which cairo's text drawing loads, keeps
// process-lifetime caches that LeakSanitizer reports at exit. They are the
// library's, not ours; every wearknit allocation is still checked.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libfontconfig.so\n";
}
#endif

namespace bed {

namespace {

struct Rgb {
  double r, g, b;
};

// Ten well-separated colours (carriers 1-10 on the default machine).
constexpr Rgb kPalette[] = {{0.12, 0.47, 0.71}, {0.89, 0.10, 0.11}, {0.20, 0.63, 0.17},
                            {1.00, 0.50, 0.00}, {0.42, 0.24, 0.60}, {0.65, 0.34, 0.16},
                            {0.97, 0.51, 0.75}, {0.40, 0.40, 0.40}, {0.74, 0.74, 0.13},
                            {0.09, 0.75, 0.81}};
constexpr int kPaletteSize = sizeof kPalette / sizeof kPalette[0];

Rgb colour_of(std::uint8_t code, std::uint8_t count) {
  Rgb c = kPalette[(code - 1) % kPaletteSize];
  if (count > 1) {  // stacked loops: darker
    const double f = count > 2 ? 0.55 : 0.75;
    c = {c.r * f, c.g * f, c.b * f};
  }
  return c;
}

cairo_status_t write_to_stream(void* closure, const unsigned char* data, unsigned int length) {
  auto* out = static_cast<std::ostream*>(closure);
  out->write(reinterpret_cast<const char*>(data), length);
  return *out ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

}  // namespace

void BedView::sweep_ended(const Machine& machine, std::uint32_t line) {
  if (machine.min_slot() > machine.max_slot()) return;
  // Back needles sit `shift` slots away from their front partners; the
  // sampled range is capped so absurdly wide programs (possible on the
  // unlimited generic profile) cannot exhaust memory.
  const std::int64_t shift = static_cast<std::int64_t>(
      std::min(std::fabs(std::floor(machine.racking())), static_cast<double>(kMaxNeedles)));
  const std::int64_t low = std::max<std::int64_t>(std::int64_t{machine.min_slot()} - shift,
                                                  std::numeric_limits<int>::min());
  const std::int64_t high =
      std::min<std::int64_t>({std::int64_t{machine.max_slot()} + shift, low + kMaxNeedles - 1,
                              std::numeric_limits<int>::max()});
  Row row;
  row.min_slot = static_cast<int>(low);
  const int count = static_cast<int>(high - low + 1);
  row.front.assign(static_cast<std::size_t>(count), 0);
  row.back.assign(static_cast<std::size_t>(count), 0);
  row.front_count.assign(static_cast<std::size_t>(count), 0);
  row.back_count.assign(static_cast<std::size_t>(count), 0);
  for (int i = 0; i < count; ++i) {
    for (int b = 0; b < 2; ++b) {
      const knitout::Needle needle{b == 0 ? knitout::Bed::Front : knitout::Bed::Back,
                                   row.min_slot + i};
      auto loops = machine.loops_on(needle);
      if (loops.empty()) continue;
      const knitout::CarrierList& yarn = machine.yarn(loops.back().yarn);
      const std::uint8_t code =
          static_cast<std::uint8_t>(yarn.empty() ? 1 : std::min<int>(yarn[0] + 1, 255));
      const std::uint8_t held = static_cast<std::uint8_t>(std::min<std::size_t>(loops.size(), 255));
      (b == 0 ? row.front : row.back)[static_cast<std::size_t>(i)] = code;
      (b == 0 ? row.front_count : row.back_count)[static_cast<std::size_t>(i)] = held;
    }
  }
  row.transfers.swap(pending_transfers_);
  pending_transfers_.clear();
  row.racking = machine.racking();
  row.racked = pending_rack_;
  pending_rack_ = false;
  row.line = line;
  rows_.push_back(std::move(row));
}

void BedView::loops_moved(knitout::Needle from, knitout::Needle /*to*/, int /*count*/,
                          std::uint32_t /*line*/) {
  if (pending_transfers_.size() < 4096) pending_transfers_.push_back(from.index);
}

void BedView::racked(double /*racking*/, std::uint32_t /*line*/) {
  pending_rack_ = true;
}

std::string BedView::write(const std::string& path, const Machine& machine,
                           const std::string& title) const {
  const bool svg = std::filesystem::path(path).extension() == ".svg";
  // Needle range over all samples.
  int lo = 0;
  int hi = -1;
  for (const Row& row : rows_) {
    const int row_hi = row.min_slot + static_cast<int>(row.front.size()) - 1;
    if (lo > hi) {
      lo = row.min_slot;
      hi = row_hi;
    } else {
      lo = std::min(lo, row.min_slot);
      hi = std::max(hi, row_hi);
    }
  }
  if (std::int64_t{hi} - lo + 1 > kMaxNeedles) hi = lo + kMaxNeedles - 1;
  // Trim needles that never hold a loop at the edges.
  auto column_used = [&](int needle) {
    for (const Row& row : rows_) {
      const int i = needle - row.min_slot;
      if (i < 0 || i >= static_cast<int>(row.front.size())) continue;
      if (row.front[static_cast<std::size_t>(i)] || row.back[static_cast<std::size_t>(i)]) {
        return true;
      }
    }
    return false;
  };
  while (lo < hi && !column_used(lo)) ++lo;
  while (hi > lo && !column_used(hi)) --hi;
  if (lo > hi) {
    lo = 0;
    hi = 0;
  }
  const int needles = hi - lo + 1;
  const int merge = std::max<int>(1, static_cast<int>((rows_.size() + kMaxRows - 1) / kMaxRows));
  const int pixel_rows = std::max<int>(1, static_cast<int>((rows_.size() + merge - 1) / merge));

  // Whole pixels per cell, so cells tile without seams.
  const double cell_w = std::clamp(std::floor(700.0 / needles), 1.0, 10.0);
  const double cell_h = std::clamp(std::floor(1000.0 / pixel_rows), 1.0, 8.0);
  const double panel_w = cell_w * needles;
  const double plot_h = cell_h * pixel_rows;
  // The strip left of the front bed holding the transfer and racking marks.
  constexpr double kMarkStrip = 16;
  constexpr double kTransferMark = 15;  // x of the transfer mark, left of the plot
  constexpr double kRackMark = 8;
  const double left = 96;
  const double gap = 40;
  const double top = 56;
  const double bottom = 48;
  const double legend_w = 190;
  const double width = std::ceil(left + 2 * panel_w + gap + 20 + legend_w);
  const double height = std::ceil(top + plot_h + bottom);

  std::string failure;
  std::string result = knitout::write_file_atomically(path, [&](std::ostream& out) {
    cairo_surface_t* surface =
        svg ? cairo_svg_surface_create_for_stream(write_to_stream, &out, width, height)
            : cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(width),
                                         static_cast<int>(height));
    cairo_t* cr = cairo_create(surface);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);

    auto text = [&](double x, double y, const std::string& s, double size, bool right = false,
                    bool centre = false) {
      cairo_set_font_size(cr, size);
      cairo_text_extents_t extents;
      cairo_text_extents(cr, s.c_str(), &extents);
      double tx = x;
      if (right) tx = x - extents.x_advance;
      if (centre) tx = x - extents.x_advance / 2;
      cairo_move_to(cr, tx, y);
      cairo_show_text(cr, s.c_str());
    };

    cairo_set_source_rgb(cr, 0, 0, 0);
    text(left, 20, "bed view: " + title + " on " + machine.profile().name, 14);
    text(left, 38,
         std::to_string(rows_.size()) + " sweeps, time runs upward" +
             (merge > 1 ? " (" + std::to_string(merge) + " sweeps per pixel row)" : ""),
         11);

    const double panel_x[2] = {left, left + panel_w + gap};
    const char* panel_name[2] = {"front bed", "back bed"};
    for (int b = 0; b < 2; ++b) {
      cairo_set_source_rgb(cr, 0.95, 0.95, 0.95);
      cairo_rectangle(cr, panel_x[b], top, panel_w, plot_h);
      cairo_fill(cr);
    }
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
    // Cells. Row r of the picture (counted from the bottom) merges samples
    // [r*merge, (r+1)*merge): a needle shows the last sample that held loops.
    // Runs of equal cells are drawn as one rectangle (small SVG files).
    std::vector<std::uint8_t> codes(static_cast<std::size_t>(needles));
    std::vector<std::uint8_t> shades(static_cast<std::size_t>(needles));
    for (int r = 0; r < pixel_rows; ++r) {
      const double y = top + plot_h - (r + 1) * cell_h;
      for (int b = 0; b < 2; ++b) {
        for (int n = 0; n < needles; ++n) {
          std::uint8_t code = 0;
          std::uint8_t count = 0;
          for (int k = r * merge;
               k < std::min<int>((r + 1) * merge, static_cast<int>(rows_.size())); ++k) {
            const Row& row = rows_[static_cast<std::size_t>(k)];
            const int i = lo + n - row.min_slot;
            if (i < 0 || i >= static_cast<int>(row.front.size())) continue;
            const auto& cells = b == 0 ? row.front : row.back;
            const auto& counts = b == 0 ? row.front_count : row.back_count;
            if (cells[static_cast<std::size_t>(i)] != 0) {
              code = cells[static_cast<std::size_t>(i)];
              count = counts[static_cast<std::size_t>(i)];
            }
          }
          codes[static_cast<std::size_t>(n)] = code;
          shades[static_cast<std::size_t>(n)] = std::min<std::uint8_t>(count, 3);
        }
        for (int n = 0; n < needles;) {
          const std::uint8_t code = codes[static_cast<std::size_t>(n)];
          const std::uint8_t shade = shades[static_cast<std::size_t>(n)];
          int end = n + 1;
          while (end < needles && codes[static_cast<std::size_t>(end)] == code &&
                 shades[static_cast<std::size_t>(end)] == shade) {
            ++end;
          }
          if (code != 0) {
            const Rgb c = colour_of(code, shade);
            cairo_set_source_rgb(cr, c.r, c.g, c.b);
            cairo_rectangle(cr, panel_x[b] + n * cell_w, y, (end - n) * cell_w, cell_h);
            cairo_fill(cr);
          }
          n = end;
        }
      }
    }
    // Transfer passes (grey) and racking changes (red) as short ticks in a
    // strip left of the front bed, so that the fabric stays what one sees
    // first; a pixel row merging several sweeps is marked when any of them is.
    for (int r = 0; r < pixel_rows; ++r) {
      const double y = top + plot_h - (r + 1) * cell_h;
      bool racked = false;
      bool transfers = false;
      for (int k = r * merge; k < std::min<int>((r + 1) * merge, static_cast<int>(rows_.size()));
           ++k) {
        const Row& row = rows_[static_cast<std::size_t>(k)];
        racked |= row.racked;
        transfers |= !row.transfers.empty();
      }
      // A pixel apart when rows are tall enough, so that marked sweeps stay countable.
      const double tick_h = cell_h >= 3 ? cell_h - 1 : cell_h;
      if (transfers) {
        cairo_set_source_rgb(cr, 0.45, 0.48, 0.55);
        cairo_rectangle(cr, left - kTransferMark, y, 5, tick_h);
        cairo_fill(cr);
      }
      if (racked) {
        cairo_set_source_rgb(cr, 0.85, 0.1, 0.1);
        cairo_rectangle(cr, left - kRackMark, y + cell_h - tick_h, 6, tick_h);
        cairo_fill(cr);
      }
    }
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_DEFAULT);
    // Frames and axes.
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1);
    const int step = needles <= 120 ? 10 : needles <= 600 ? 50 : 100;
    for (int b = 0; b < 2; ++b) {
      cairo_rectangle(cr, panel_x[b] + 0.5, top + 0.5, panel_w, plot_h);
      cairo_stroke(cr);
      text(panel_x[b] + panel_w / 2, top + plot_h + 40,
           std::string(panel_name[b]) + " (needle number)", 12, false, true);
      for (int n = (lo / step) * step; n <= hi; n += step) {
        if (n < lo) continue;
        const double x = panel_x[b] + (n - lo + 0.5) * cell_w;
        cairo_move_to(cr, x, top + plot_h);
        cairo_line_to(cr, x, top + plot_h + 5);
        cairo_stroke(cr);
        text(x, top + plot_h + 18, std::to_string(n), 10, false, true);
      }
    }
    // Time axis: source line at the end of a sweep, every ~60 pixels.
    text(4, top - 6, "source line", 10);
    const int label_every = std::max(1, static_cast<int>(std::ceil(60.0 / cell_h)));
    for (int r = 0; r < pixel_rows; r += label_every) {
      const std::size_t k =
          std::min(rows_.size() - 1, static_cast<std::size_t>(r) * static_cast<std::size_t>(merge));
      if (rows_.empty()) break;
      const double y = top + plot_h - r * cell_h;
      cairo_move_to(cr, left - kMarkStrip - 5, y);
      cairo_line_to(cr, left - kMarkStrip, y);
      cairo_stroke(cr);
      text(left - kMarkStrip - 8, y + 4, std::to_string(rows_[k].line), 10, true);
    }
    // Legend.
    const double lx = left + 2 * panel_w + gap + 20;
    double ly = top + 12;
    text(lx, ly, "carriers (top loop)", 11);
    ly += 16;
    std::vector<bool> seen(256, false);
    for (const Row& row : rows_) {
      for (auto c : row.front) seen[c] = true;
      for (auto c : row.back) seen[c] = true;
    }
    for (int code = 1; code < 256; ++code) {
      if (!seen[static_cast<std::size_t>(code)]) continue;
      const Rgb c = colour_of(static_cast<std::uint8_t>(code), 1);
      cairo_set_source_rgb(cr, c.r, c.g, c.b);
      cairo_rectangle(cr, lx, ly - 9, 12, 10);
      cairo_fill(cr);
      cairo_set_source_rgb(cr, 0, 0, 0);
      const auto id = static_cast<knitout::CarrierId>(code - 1);
      text(lx + 18, ly,
           "carrier " + (id < machine.carrier_names().size() ? machine.carrier_names().name(id)
                                                             : std::to_string(code - 1)),
           11);
      ly += 16;
    }
    ly += 8;
    const Rgb dark = colour_of(1, 3);
    cairo_set_source_rgb(cr, dark.r, dark.g, dark.b);
    cairo_rectangle(cr, lx, ly - 9, 12, 10);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(lx + 18, ly, "darker: 2+ loops held", 11);
    ly += 16;
    cairo_set_source_rgb(cr, 0.45, 0.48, 0.55);
    cairo_rectangle(cr, lx + 2, ly - 5, 5, 2);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(lx + 18, ly, "transfers (left margin)", 11);
    ly += 16;
    cairo_set_source_rgb(cr, 0.85, 0.1, 0.1);
    cairo_rectangle(cr, lx + 2, ly - 5, 6, 2);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(lx + 18, ly, "racking change (left margin)", 11);
    ly += 16;
    text(lx, ly, "racking at end: " + knitout::format_number(machine.racking()), 11);

    cairo_destroy(cr);
    if (svg) {
      cairo_surface_finish(surface);
    } else {
      const cairo_status_t status =
          cairo_surface_write_to_png_stream(surface, write_to_stream, &out);
      if (status != CAIRO_STATUS_SUCCESS) failure = cairo_status_to_string(status);
    }
    if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
      failure = cairo_status_to_string(cairo_surface_status(surface));
    }
    cairo_surface_destroy(surface);
    if (!failure.empty()) out.setstate(std::ios::failbit);  // keep the old file, if any
  });
  if (!result.empty()) return result;
  if (!failure.empty()) return path + ": " + failure;
  return {};
}

}  // namespace bed
