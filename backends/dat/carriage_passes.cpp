// The carriage passes of a program as `wearknit simulate` reports them
// (passes.hpp: summarize, carriage_passes, write_carriage_passes_*).
#include <algorithm>
#include <ostream>

#include "backends/dat/passes.hpp"
#include "knitout/writer.hpp"

namespace dat {

using knitout::Direction;
using knitout::format_number;

std::vector<CarriagePass> summarize(const PassList& list) {
  std::vector<CarriagePass> result;
  result.reserve(list.passes.size());
  for (const Pass& pass : list.passes) {
    CarriagePass summary;
    summary.type = pass.type;
    summary.direction = pass.direction;
    for (std::uint8_t c : pass.carriers) summary.carriers.push_back(std::to_string(c));
    summary.racking = pass.racking;
    summary.slots = pass.entry_count;
    summary.line = pass.line;
    result.push_back(std::move(summary));
  }
  return result;
}

std::optional<std::vector<CarriagePass>> carriage_passes(const knitout::Program& program,
                                                         std::string source,
                                                         knitout::DiagnosticSink& sink,
                                                         const Profile& profile) {
  auto list = form_passes(program, std::move(source), sink, profile);
  if (!list) return std::nullopt;
  return summarize(*list);
}

namespace {

std::string direction_text(Direction direction) {
  return direction == Direction::None ? "none" : std::string(1, knitout::direction_char(direction));
}

}  // namespace

void write_carriage_passes_text(std::ostream& out, const std::vector<CarriagePass>& passes,
                                bool each_pass) {
  constexpr std::array<PassType, 7> kTypes = {PassType::KnitTuck,       PassType::AMiss,
                                              PassType::Split,          PassType::SplitViaSliders,
                                              PassType::Xfer,           PassType::XferToSliders,
                                              PassType::XferFromSliders};
  out << "carriage passes: " << passes.size();
  std::string counts;
  for (PassType type : kTypes) {
    const auto n = std::count_if(passes.begin(), passes.end(),
                                 [&](const CarriagePass& p) { return p.type == type; });
    if (n == 0) continue;
    if (!counts.empty()) counts += ", ";
    counts += std::to_string(n) + " " + std::string(pass_type_name(type));
  }
  if (!counts.empty()) out << " (" << counts << ")";
  out << '\n';
  if (!each_pass) return;
  std::size_t number = 0;
  for (const CarriagePass& pass : passes) {
    out << "  pass " << ++number << " (line " << pass.line
        << "): " << direction_text(pass.direction) << " carriers";
    if (pass.carriers.empty()) out << " -";
    for (const std::string& c : pass.carriers) out << ' ' << c;
    out << " racking " << format_number(pass.racking) << ' ' << pass_type_name(pass.type) << ", "
        << pass.slots << (pass.slots == 1 ? " slot" : " slots") << '\n';
  }
}

void write_carriage_passes_json(std::ostream& out, const std::vector<CarriagePass>& passes) {
  out << "{\"count\": " << passes.size() << ", \"passes\": [";
  bool first = true;
  for (const CarriagePass& pass : passes) {
    out << (first ? "" : ", ") << "{\"type\": " << knitout::json_quote(pass_type_name(pass.type))
        << ", \"direction\": " << knitout::json_quote(direction_text(pass.direction))
        << ", \"carriers\": [";
    for (std::size_t i = 0; i < pass.carriers.size(); ++i) {
      out << (i == 0 ? "" : ", ") << knitout::json_quote(pass.carriers[i]);
    }
    out << "], \"racking\": " << format_number(pass.racking) << ", \"slots\": " << pass.slots
        << ", \"line\": " << pass.line << "}";
    first = false;
  }
  out << "]}";
}

}  // namespace dat
