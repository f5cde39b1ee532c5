#include "planner/stitch_mesh/gauge.hpp"

#include <charconv>
#include <cmath>
#include <optional>
#include <utility>

namespace planner {
namespace {

std::optional<double> number(std::string_view text) {
  double value = 0;
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value) || value <= 0) return std::nullopt;
  return value;
}

// "AxB" -> (A, B), both positive numbers.
std::optional<std::pair<double, double>> pair(std::string_view text) {
  const std::size_t x = text.find('x');
  if (x == std::string_view::npos) return std::nullopt;
  auto a = number(text.substr(0, x));
  auto b = number(text.substr(x + 1));
  if (!a || !b) return std::nullopt;
  return std::make_pair(*a, *b);
}

}  // namespace

std::string parse_swatch(std::string_view text, StitchGauge& gauge) {
  const std::size_t colon = text.find(':');
  const std::string wanted =
      "`" + std::string(text) +
      "` is not STITCHESxROWS:WIDTHxHEIGHT_MM with positive numbers (e.g. 40x40:42x115)";
  if (colon == std::string_view::npos) return wanted;
  auto counts = pair(text.substr(0, colon));
  auto size = pair(text.substr(colon + 1));
  if (!counts || !size) return wanted;
  gauge.course_mm = size->first / counts->first;
  gauge.wale_mm = size->second / counts->second;
  gauge.source = "swatch " + std::string(text);
  return {};
}

std::string parse_stitch_mm(std::string_view text, StitchGauge& gauge) {
  auto size = pair(text);
  if (!size) {
    return "`" + std::string(text) +
           "` is not COURSExWALE in mm with positive numbers (e.g. 1.05x2.875)";
  }
  gauge.course_mm = size->first;
  gauge.wale_mm = size->second;
  gauge.source = "stitch-mm " + std::string(text);
  return {};
}

std::string check_gauge(const StitchGauge& gauge) {
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(gauge.needles_per_inch)) return "the gauge (needles per inch) must be positive";
  if (!positive(gauge.course_mm) || !positive(gauge.wale_mm)) {
    return "the stitch size must be positive";
  }
  return {};
}

}  // namespace planner
