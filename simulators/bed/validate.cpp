#include "simulators/bed/validate.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <optional>

#include "knitout/parser.hpp"

namespace bed {

namespace {

// The parser interns the names of the `;;Carriers:` header(s) before any
// instruction's, so they are the first ids of the table; nullopt when there
// is no such header.
std::optional<std::size_t> header_carrier_count(const std::vector<knitout::Header>& headers,
                                                const knitout::CarrierTable& table) {
  std::vector<std::string_view> names;
  bool has = false;
  for (const knitout::Header& header : headers) {
    if (header.key != "Carriers") continue;
    has = true;
    const std::string& v = header.value;
    std::size_t i = 0;
    while (i < v.size()) {
      while (i < v.size() && (v[i] == ' ' || v[i] == '\t' || v[i] == ',' || v[i] == ';')) ++i;
      const std::size_t start = i;
      while (i < v.size() && v[i] != ' ' && v[i] != '\t' && v[i] != ',' && v[i] != ';') ++i;
      const std::string_view name(v.data() + start, i - start);
      if (i > start && std::find(names.begin(), names.end(), name) == names.end()) {
        names.push_back(name);
      }
    }
  }
  if (!has) return std::nullopt;
  return std::min(names.size(), table.size());
}

void count_diagnostics(Stats& stats, const knitout::DiagnosticSink& sink) {
  stats.errors = sink.error_count();
  stats.warnings = sink.warning_count();
}

}  // namespace

Stats validate(const knitout::Program& program, const MachineProfile& profile,
               knitout::DiagnosticSink& sink, std::string_view source, MachineOptions options) {
  Machine machine(profile, sink, std::string(source), program.carriers,
                  header_carrier_count(program.headers, program.carriers), options);
  machine.check_headers(program.headers);
  std::uint32_t last_line = 0;
  for (const knitout::Instruction& instruction : program.instructions) {
    if (sink.saturated()) break;
    machine.step(instruction);
    last_line = instruction.line;
  }
  machine.finish(last_line);
  Stats stats = machine.stats();
  count_diagnostics(stats, sink);
  return stats;
}

Stats validate_stream(std::istream& in, std::string_view source, const MachineProfile& profile,
                      knitout::DiagnosticSink& sink, MachineOptions options) {
  knitout::Reader reader(in, std::string(source), sink);
  std::optional<std::size_t> header_carriers;
  for (const knitout::Header& header : reader.headers()) {
    if (header.key == "Carriers") header_carriers = reader.carriers().size();
  }
  Machine machine(profile, sink, std::string(source), reader.carriers(), header_carriers, options);
  machine.check_headers(reader.headers());
  knitout::Instruction instruction;
  while (reader.next(instruction)) machine.step(instruction);
  machine.finish(static_cast<std::uint32_t>(reader.lines_read()));
  Stats stats = machine.stats();
  count_diagnostics(stats, sink);
  return stats;
}

Stats validate_file(const std::string& path, const MachineProfile& profile,
                    knitout::DiagnosticSink& sink, MachineOptions options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    sink.error(path, 0, 0, "K090", std::string("cannot open file: ") + std::strerror(errno));
    Stats stats;
    count_diagnostics(stats, sink);
    return stats;
  }
  return validate_stream(in, path, profile, sink, options);
}

}  // namespace bed
