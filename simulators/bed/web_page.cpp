#include "simulators/bed/web_page.hpp"

#include <zlib.h>

#include <array>
#include <cstdint>
#include <stdexcept>

#include "knitout/diagnostic_reports.hpp"

namespace bed {

namespace {

std::string gzip(std::string_view bytes) {
  z_stream stream{};
  // 15 + 16: a gzip header and trailer around the deflate stream.
  if (deflateInit2(&stream, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
    throw std::runtime_error("gzip: deflateInit2 failed");
  }
  std::string out;
  out.resize(deflateBound(&stream, static_cast<uLong>(bytes.size())) + 32);
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  stream.avail_in = static_cast<uInt>(bytes.size());
  stream.next_out = reinterpret_cast<Bytef*>(out.data());
  stream.avail_out = static_cast<uInt>(out.size());
  const int result = deflate(&stream, Z_FINISH);
  const auto written = stream.total_out;
  deflateEnd(&stream);
  if (result != Z_STREAM_END) throw std::runtime_error("gzip: deflate did not finish");
  out.resize(written);
  return out;
}

std::string base64(std::string_view bytes) {
  static constexpr char kDigits[] =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4 + bytes.size() / 57 + 1);
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16 |
                            static_cast<std::uint8_t>(bytes[i + 1]) << 8 |
                            static_cast<std::uint8_t>(bytes[i + 2]);
    out += kDigits[v >> 18];
    out += kDigits[(v >> 12) & 63];
    out += kDigits[(v >> 6) & 63];
    out += kDigits[v & 63];
    if ((i / 3 + 1) % 19 == 0) out += '\n';  // lines of 76 characters
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    std::uint32_t v = static_cast<std::uint8_t>(bytes[i]) << 16;
    if (rest == 2) v |= static_cast<std::uint8_t>(bytes[i + 1]) << 8;
    out += kDigits[v >> 18];
    out += kDigits[(v >> 12) & 63];
    out += rest == 2 ? kDigits[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

// A script or style must not close its own element early.
void check_inline(std::string_view text, std::string_view closing) {
  if (text.find(closing) != std::string_view::npos) {
    throw std::logic_error("web page: an inline text contains " + std::string(closing));
  }
}

}  // namespace

std::string gzip_base64(std::string_view bytes) {
  return base64(gzip(bytes));
}

std::string html_escape(std::string_view text) {
  return knitout::xml_escape(text);
}

void write_page(std::ostream& out, const Page& page) {
  out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
      << "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; "
         "script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data: blob:; "
         "connect-src data: blob:\">\n"
      << "<title>" << html_escape(page.title) << "</title>\n";
  for (const std::string_view style : page.styles) {
    check_inline(style, "</style");
    out << "<style>\n" << style << "</style>\n";
  }
  out << "</head>\n<body>\n" << page.body << "\n";
  for (const PageData& data : page.data) {
    out << "<script type=\"application/octet-stream\" id=\"" << html_escape(data.id) << "\">\n"
        << gzip_base64(data.bytes) << "\n</script>\n";
  }
  for (const std::string_view script : page.scripts) {
    check_inline(script, "</script");
    out << "<script>\n" << script << "</script>\n";
  }
  out << "</body>\n</html>\n";
}

}  // namespace bed
