// The HTML bed view of one knitout program (wearknit simulate --html): one
// self-contained page (web_page.hpp) holding the program's BedTimeline and
// its source text, drawn by web/bed_view.js with needles across, sweeps up,
// a scrubber over the sweeps, zoom, and the source line under the pointer.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <string_view>

namespace bed {

struct BedPageInput {
  std::string title;     // shown at the top and as the page title
  std::string subtitle;  // one line under it (machine, figures)
  std::string timeline;  // BedTimeline::serialize
  // The program's text, for the source line under the pointer; left out of
  // the page (the page shows line numbers only) when longer than
  // kMaxSourceBytes.
  std::string_view source_text;
};

// Longer sources are not embedded: they would make the page slow to open.
inline constexpr std::size_t kMaxSourceBytes = 256u << 20;

// Writes the page. The scripts read the data blocks "bed-timeline" and
// "bed-source" (absent when the source is left out).
void write_bed_page(std::ostream& out, const BedPageInput& input);

}  // namespace bed
