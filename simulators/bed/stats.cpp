#include "simulators/bed/stats.hpp"

#include <cstdio>
#include <ostream>

#include "knitout/diagnostic.hpp"

namespace bed {

namespace {

std::string fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

constexpr knitout::Op kCountedOps[] = {
    knitout::Op::In,      knitout::Op::Inhook, knitout::Op::Releasehook, knitout::Op::Out,
    knitout::Op::Outhook, knitout::Op::Stitch, knitout::Op::Rack,        knitout::Op::Knit,
    knitout::Op::Tuck,    knitout::Op::Split,  knitout::Op::Drop,        knitout::Op::Amiss,
    knitout::Op::Xfer,    knitout::Op::Miss,   knitout::Op::Pause,       knitout::Op::Extension};

std::string op_label(knitout::Op op) {
  if (op == knitout::Op::Extension) return "x-*";
  return std::string(knitout::op_name(op));
}

std::string duration(double seconds) {
  const long total = static_cast<long>(seconds + 0.5);
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%ld:%02ld:%02ld", total / 3600, (total / 60) % 60,
                total % 60);
  return buffer;
}

}  // namespace

void write_stats_text(std::ostream& out, const Stats& s, const std::string& source,
                      const std::string& machine) {
  out << source << " on " << machine << "\n";
  out << "  lines                " << s.lines << "\n";
  out << "  instructions         " << s.instructions << "\n";
  for (knitout::Op op : kCountedOps) {
    const auto n = s.by_op[static_cast<std::size_t>(op)];
    if (n == 0) continue;
    std::string label = op_label(op);
    label.resize(19, ' ');
    out << "    " << label << n << "\n";
  }
  out << "  loops made           " << s.loops_made << "\n";
  out << "  transfers            " << s.transfers << " (" << s.loops_transferred
      << " loops moved)\n";
  out << "  racking changes      " << s.racks << "\n";
  out << "  largest stack        " << s.largest_stack;
  if (s.largest_stack > 0) {
    out << " loops (" << s.largest_stack_needle << ", line " << s.largest_stack_line << ")";
  }
  out << "\n";
  out << "  bed span             " << s.bed_span() << " needles";
  if (s.has_span) out << " (slots " << s.min_slot << " to " << s.max_slot << ")";
  out << "\n";
  out << "  carriers used        " << s.carriers.size() << "\n";
  for (const CarrierStats& c : s.carriers) {
    out << "    carrier " << c.name << ": " << c.loops << " loops, yarn " << fixed(c.yarn_m, 2)
        << " m, longest float " << fixed(c.longest_float_pitches, 2) << " needles\n";
  }
  out << "  sweeps (estimated)   " << s.sweeps << " (" << s.knit_sweeps << " knit, "
      << s.transfer_sweeps << " transfer, " << s.drop_sweeps << " drop)\n";
  out << "  DAT passes           "
      << (s.dat_passes ? std::to_string(*s.dat_passes) : std::string("not computed")) << "\n";
  out << "  estimated time       " << duration(s.estimated_time_s) << " ("
      << fixed(s.estimated_time_s, 1) << " s)\n";
  out << "  diagnostics          " << s.errors << " errors, " << s.warnings << " warnings\n";
}

void write_stats_json(std::ostream& out, const Stats& s, const std::string& source,
                      const std::string& machine) {
  out << "{\n  \"file\": " << knitout::json_quote(source)
      << ",\n  \"machine\": " << knitout::json_quote(machine) << ",\n  \"lines\": " << s.lines
      << ",\n  \"instructions\": " << s.instructions << ",\n  \"by_op\": {";
  bool first = true;
  for (knitout::Op op : kCountedOps) {
    out << (first ? "" : ", ") << knitout::json_quote(op_label(op)) << ": "
        << s.by_op[static_cast<std::size_t>(op)];
    first = false;
  }
  out << "},\n  \"loops_made\": " << s.loops_made << ",\n  \"transfers\": " << s.transfers
      << ",\n  \"loops_transferred\": " << s.loops_transferred << ",\n  \"racks\": " << s.racks
      << ",\n  \"largest_stack\": " << s.largest_stack
      << ",\n  \"largest_stack_needle\": " << knitout::json_quote(s.largest_stack_needle)
      << ",\n  \"largest_stack_line\": " << s.largest_stack_line
      << ",\n  \"bed_span\": " << s.bed_span();
  if (s.has_span) {
    out << ",\n  \"min_slot\": " << s.min_slot << ",\n  \"max_slot\": " << s.max_slot;
  }
  out << ",\n  \"carriers\": [";
  first = true;
  for (const CarrierStats& c : s.carriers) {
    out << (first ? "\n" : ",\n") << "    {\"name\": " << knitout::json_quote(c.name)
        << ", \"loops\": " << c.loops << ", \"float_needles\": " << fixed(c.float_pitches, 2)
        << ", \"longest_float_needles\": " << fixed(c.longest_float_pitches, 2)
        << ", \"yarn_m\": " << fixed(c.yarn_m, 3) << "}";
    first = false;
  }
  out << (first ? "]" : "\n  ]") << ",\n  \"sweeps\": " << s.sweeps
      << ",\n  \"knit_sweeps\": " << s.knit_sweeps
      << ",\n  \"transfer_sweeps\": " << s.transfer_sweeps
      << ",\n  \"drop_sweeps\": " << s.drop_sweeps
      << ",\n  \"sweep_needles\": " << fixed(s.sweep_needles, 1) << ",\n  \"dat_passes\": "
      << (s.dat_passes ? std::to_string(*s.dat_passes) : std::string("null"))
      << ",\n  \"estimated_time_s\": " << fixed(s.estimated_time_s, 1)
      << ",\n  \"errors\": " << s.errors << ",\n  \"warnings\": " << s.warnings << "\n}\n";
}

}  // namespace bed
