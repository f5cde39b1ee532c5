// Diagnostics: what every layer reports about bad user input.
//
// A diagnostic names its source (a file name or "<stdin>"), the 1-based line
// and column where the problem sits (0 when not known), a severity, a stable
// code (listed in docs/diagnostics.md) and a message. Diagnostics are
// collected, never thrown: bad input is not a bug.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>
#include <vector>

namespace knitout {

enum class Severity : std::uint8_t { Warning, Error };

std::string_view to_string(Severity severity);

struct Diagnostic {
  Severity severity = Severity::Error;
  std::string code;  // stable, e.g. "K010"
  std::string message;
  std::string source;
  std::uint32_t line = 0;    // 1-based; 0 = the file as a whole
  std::uint32_t column = 0;  // 1-based; 0 = not known

  bool operator==(const Diagnostic&) const = default;
};

// `FILE:LINE:COL: error: [CODE] message` (LINE and COL left out when 0).
std::string format(const Diagnostic& diagnostic);

// Collects diagnostics and counts them by severity. After `max_errors`
// errors it records one more error saying it stopped (code K099) and
// `saturated()` turns true; callers stop reading then.
class DiagnosticSink {
 public:
  explicit DiagnosticSink(std::size_t max_errors = 100) : max_errors_(max_errors) {}

  void report(Diagnostic diagnostic);
  void error(std::string_view source, std::uint32_t line, std::uint32_t column,
             std::string_view code, std::string message);
  void warning(std::string_view source, std::uint32_t line, std::uint32_t column,
               std::string_view code, std::string message);

  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }
  std::size_t error_count() const { return errors_; }
  std::size_t warning_count() const { return warnings_; }
  bool has_errors() const { return errors_ > 0; }
  bool saturated() const { return saturated_; }

  // Diagnostics sorted by (source, line, column), stable for equal keys.
  std::vector<Diagnostic> sorted() const;

 private:
  std::size_t max_errors_;
  std::vector<Diagnostic> diagnostics_;
  std::size_t errors_ = 0;
  std::size_t warnings_ = 0;
  bool saturated_ = false;
};

// Writes diagnostics one per line in the text form of `format`.
void print_text(std::ostream& out, const std::vector<Diagnostic>& diagnostics);
// Writes diagnostics as a JSON array of objects
// {"file","line","column","severity","code","message"}.
void print_json(std::ostream& out, const std::vector<Diagnostic>& diagnostics);
// JSON string literal with escapes, for writers that build JSON by hand.
std::string json_quote(std::string_view text);

}  // namespace knitout
