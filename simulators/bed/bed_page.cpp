#include "simulators/bed/bed_page.hpp"

#include "simulators/bed/web_assets.hpp"
#include "simulators/bed/web_page.hpp"

namespace bed {

void write_bed_page(std::ostream& out, const BedPageInput& input) {
  Page page;
  page.title = input.title;
  page.styles = {web_asset("page.css"), web_asset("bed_view.css")};
  page.scripts = {web_asset("common.js"), web_asset("bed_view.js"), web_asset("bed_page.js")};
  page.body = "<header class=\"wk-top\"><h1>" + html_escape(input.title) +
              "</h1><span class=\"wk-sub\">" + html_escape(input.subtitle) +
              "</span></header>\n<main id=\"bed-view\" class=\"bv-page\"></main>";
  page.data.push_back(PageData{"bed-timeline", input.timeline});
  if (input.source_text.size() <= kMaxSourceBytes) {
    page.data.push_back(PageData{"bed-source", std::string(input.source_text)});
  }
  write_page(out, page);
}

}  // namespace bed
