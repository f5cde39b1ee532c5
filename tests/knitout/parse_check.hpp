// The property the parser fuzzer checks on every input, shared with the
// replay test: parsing never crashes; when the input has no errors, its
// canonical form reads back to the same program without errors and is a
// fixed point of the writer. Returns "" or what went wrong.
#pragma once

#include <string>
#include <string_view>

#include "knitout/parser.hpp"
#include "knitout/writer.hpp"

namespace knitout {

inline std::string check_parse_round_trip(std::string_view data) {
  DiagnosticSink sink;
  const Program program = parse_string(data, "fuzz.k", sink);
  for (const Diagnostic& d : sink.diagnostics()) {
    if (d.line > 0 && d.message.empty()) return "diagnostic without a message";
  }
  if (sink.has_errors()) return "";
  const std::string once = write_to_string(program);
  DiagnosticSink again_sink;
  const Program again = parse_string(once, "fuzz.k", again_sink);
  if (again_sink.has_errors()) {
    return "canonical form has errors: " + format(again_sink.diagnostics().front());
  }
  if (!(again == program)) return "canonical form reads back to a different program";
  if (write_to_string(again) != once) return "canonical form is not a fixed point";
  return "";
}

}  // namespace knitout
