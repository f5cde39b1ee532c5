// One self-contained HTML page: style, scripts and data inline, so that it
// works offline from file:// with no server and nothing fetched. The bed
// view page (simulate --html) and the plan page (index.html) are written
// through it.
#pragma once

#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace bed {

// A block of data the page's scripts read with wk.dataBytes(id) or
// wk.dataJson(id) (web/common.js).
struct PageData {
  std::string id;
  std::string bytes;  // written gzip-compressed and base64-encoded
};

struct Page {
  std::string title;
  std::vector<std::string_view> styles;   // CSS texts, in order
  std::vector<std::string_view> scripts;  // JavaScript texts, in order
  std::string body;                       // HTML of <body> before the scripts
  std::vector<PageData> data;
};

// `bytes` gzip-compressed (zlib's deflate at level 6), then base64-encoded.
std::string gzip_base64(std::string_view bytes);

// `text` escaped for HTML text and attribute values (knitout::xml_escape).
std::string html_escape(std::string_view text);

// Writes the page as one HTML document.
void write_page(std::ostream& out, const Page& page);

}  // namespace bed
