#include "simulators/bed/knit_graph.hpp"

#include <ostream>
#include <stdexcept>

namespace bed {

void KnitGraph::loop_made(const LoopEvent& event) {
  // The machine numbers loops 0, 1, 2, ... in the order it makes them.
  if (event.id != loops_.size()) throw std::logic_error("KnitGraph: loop ids are not dense");
  Loop loop;
  loop.id = event.id;
  loop.kind = event.kind;
  loop.needle = event.needle;
  loop.yarn = event.yarn;
  loop.line = event.line;
  loop.parents_begin = static_cast<std::uint32_t>(parents_.size());
  loop.parents_count = static_cast<std::uint32_t>(event.parents.size());
  for (const LiveLoop& parent : event.parents) parents_.push_back(parent.id);
  loops_.push_back(loop);
}

void KnitGraph::loops_dropped(knitout::Needle /*needle*/, std::span<const LiveLoop> loops,
                              std::uint32_t line) {
  for (const LiveLoop& loop : loops) {
    if (loop.id < loops_.size()) loops_[loop.id].dropped_line = line;
  }
}

void KnitGraph::write_json(std::ostream& out, const Machine& machine) const {
  const knitout::CarrierTable& names = machine.carrier_names();
  out << "{\n  \"machine\": " << knitout::json_quote(machine.profile().name)
      << ",\n  \"carriers\": [";
  for (std::size_t i = 0; i < names.size(); ++i) {
    out << (i ? ", " : "") << knitout::json_quote(names.name(static_cast<knitout::CarrierId>(i)));
  }
  out << "],\n  \"carrier_sets\": [";
  for (std::size_t y = 0; y < machine.yarn_count(); ++y) {
    out << (y ? ", " : "") << "[";
    const knitout::CarrierList& carriers = machine.yarn(static_cast<std::uint16_t>(y));
    for (std::size_t i = 0; i < carriers.size(); ++i) {
      out << (i ? ", " : "") << knitout::json_quote(names.name(carriers[i]));
    }
    out << "]";
  }
  // Yarn order: each carrier's loops in the order it made them (a plated
  // loop belongs to the yarn of every carrier that made it).
  std::vector<std::vector<LoopId>> order(names.size());
  for (const Loop& loop : loops_) {
    for (knitout::CarrierId id : machine.yarn(loop.yarn)) order[id].push_back(loop.id);
  }
  out << "],\n  \"yarns\": [";
  bool first = true;
  for (std::size_t c = 0; c < order.size(); ++c) {
    if (order[c].empty()) continue;
    out << (first ? "\n" : ",\n") << "    {\"carrier\": "
        << knitout::json_quote(names.name(static_cast<knitout::CarrierId>(c))) << ", \"loops\": [";
    for (std::size_t i = 0; i < order[c].size(); ++i) out << (i ? ", " : "") << order[c][i];
    out << "]}";
    first = false;
  }
  out << (first ? "]" : "\n  ]") << ",\n  \"loops\": [";
  for (std::size_t i = 0; i < loops_.size(); ++i) {
    const Loop& loop = loops_[i];
    out << (i ? ",\n" : "\n") << "    {\"id\": " << loop.id << ", \"kind\": \""
        << loop_kind_name(loop.kind) << "\", \"needle\": \"" << knitout::to_string(loop.needle)
        << "\", \"line\": " << loop.line << ", \"carriers\": " << loop.yarn << ", \"parents\": [";
    for (std::uint32_t p = 0; p < loop.parents_count; ++p) {
      out << (p ? ", " : "") << parents_[loop.parents_begin + p];
    }
    out << "], \"dropped_line\": " << loop.dropped_line << "}";
  }
  out << (loops_.empty() ? "]" : "\n  ]") << "\n}\n";
}

}  // namespace bed
