// wearknit dat-info: read a DAT back, print what it holds, draw it.
#include <algorithm>
#include <map>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "backends/dat/format.hpp"
#include "backends/dat/png.hpp"
#include "backends/dat/reader.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

namespace {

// "knit-front x20 (slots 0-19), miss x1 (slot 20)": ops grouped by colour in
// order of first appearance.
std::string describe_ops(const dat::DecodedPass& pass) {
  struct Group {
    std::uint8_t colour;
    int count;
    int first;
    int last;
  };
  std::vector<Group> groups;
  for (const auto& [column, colour] : pass.ops) {
    const auto wanted = colour;
    auto found = std::find_if(groups.begin(), groups.end(),
                              [wanted](const Group& g) { return g.colour == wanted; });
    if (found == groups.end()) {
      groups.push_back({colour, 1, column, column});
    } else {
      ++found->count;
      found->last = column;
    }
  }
  std::string text;
  for (const Group& g : groups) {
    if (!text.empty()) text += ", ";
    text += dat::colour_name(g.colour) + " x" + std::to_string(g.count);
    text += g.first == g.last
                ? " (slot " + std::to_string(g.first) + ")"
                : " (slots " + std::to_string(g.first) + "-" + std::to_string(g.last) + ")";
  }
  return text.empty() ? "no ops" : text;
}

std::string racking_text(double racking) {
  std::string text = std::to_string(racking);
  while (text.back() == '0') text.pop_back();
  if (text.back() == '.') text.pop_back();
  return text;
}

}  // namespace

int run_dat_info(const std::vector<std::string>& args, Context& context) {
  std::string input;
  std::string png;
  int scale = 4;
  po::options_description options("options");
  options.add_options()("input", po::value<std::string>(&input)->required(), "the DAT file")(
      "passes", "print every pass: direction, carriers, racking, stitch, speed, options, ops")(
      "png", po::value<std::string>(&png), "draw the raster with the file's palette")(
      "scale", po::value<int>(&scale)->default_value(4), "PNG pixels per raster pixel (1-64)");
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("dat-info"), options, positional, values, context)) {
    return *code;
  }
  const bool want_passes = values.count("passes") != 0;

  knitout::DiagnosticSink sink;
  bool ok = false;
  const std::vector<std::uint8_t> bytes = dat::read_bytes(input, sink, ok);
  if (!ok) {
    print_diagnostics(context, sink.diagnostics(), DiagnosticFormat::Text);
    return kExitUsage;
  }
  // A picture too large to draw is refused from the header's sizes, before
  // the raster is decoded.
  if (const auto size = dat::declared_size(bytes); !png.empty() && size) {
    const std::string failure = dat::png_size_problem(size->first, size->second, scale);
    if (!failure.empty()) {
      context.err << "wearknit dat-info: " << input << ": " << failure << '\n';
      return kExitUsage;
    }
  }
  const dat::Raster raster = dat::decode(bytes, input, sink);
  if (sink.has_errors()) {
    print_diagnostics(context, sink.diagnostics(), DiagnosticFormat::Text);
    return kExitInvalid;
  }
  // A raster that is valid DAT but not laid out as this backend writes it
  // still has dimensions and a picture; only --passes needs the layout.
  knitout::DiagnosticSink layout_sink;
  const auto layout = dat::read_layout(raster, input, layout_sink);
  print_diagnostics(context, sink.diagnostics(), DiagnosticFormat::Text);

  context.out << input << ": " << raster.width << " x " << raster.height << " raster";
  if (layout) {
    context.out << ", " << layout->slots << " needle slots, " << layout->passes.size()
                << " passes, position " << layout->position;
  }
  context.out << '\n';
  int status = kExitOk;
  if (want_passes) {
    if (!layout) {
      print_diagnostics(context, layout_sink.diagnostics(), DiagnosticFormat::Text);
      status = kExitInvalid;
    } else {
      int number = 0;
      for (const dat::DecodedPass& pass : layout->passes) {
        ++number;
        context.out << "pass " << number << " (row " << pass.row << "): "
                    << (pass.direction == knitout::Direction::None
                            ? std::string("none")
                            : std::string(1, knitout::direction_char(pass.direction)))
                    << " carriers " << dat::carrier_code_text(pass.carriers()) << " racking "
                    << racking_text(pass.racking) << " stitch " << pass.stitch() << " speed "
                    << pass.speed();
        // Every other option line that is set, by name.
        for (int o = 1; o <= 20; ++o) {
          const auto u = static_cast<std::size_t>(o);
          const bool shown_left = o == 2 || o == 3 || o == 4 || o == 5;
          const bool shown_right = o == 3 || o == 6 || o == 9;
          if (!shown_left && pass.left[u] != 0) {
            context.out << " L" << o << "=" << static_cast<int>(pass.left[u]);
          }
          if (!shown_right && pass.right[u] != 0) {
            context.out << " R" << o << "=" << static_cast<int>(pass.right[u]);
          }
        }
        context.out << ": " << describe_ops(pass) << '\n';
      }
    }
  }
  if (!png.empty()) {
    const std::string failure = dat::write_png_file(png, raster, scale);
    if (!failure.empty()) {
      context.err << "wearknit dat-info: " << failure << '\n';
      return kExitUsage;
    }
  }
  return status;
}

}  // namespace wearknit::cli
