#include "knitout/diagnostic.hpp"

#include <algorithm>
#include <cstdio>
#include <ostream>

namespace knitout {

std::string_view to_string(Severity severity) {
  return severity == Severity::Error ? "error" : "warning";
}

std::string format(const Diagnostic& d) {
  std::string out = d.source.empty() ? std::string("<input>") : d.source;
  if (d.line > 0) {
    out += ':';
    out += std::to_string(d.line);
    if (d.column > 0) {
      out += ':';
      out += std::to_string(d.column);
    }
  }
  out += ": ";
  out += to_string(d.severity);
  out += ": [";
  out += d.code;
  out += "] ";
  out += d.message;
  return out;
}

void DiagnosticSink::report(Diagnostic diagnostic) {
  if (saturated_) return;
  if (diagnostic.severity == Severity::Error) {
    if (errors_ >= max_errors_) {
      saturated_ = true;
      diagnostic.code = "K099";
      diagnostic.message =
          "too many errors (" + std::to_string(max_errors_) + "); stopped reading here";
      diagnostic.column = 0;
    }
    ++errors_;
  } else {
    ++warnings_;
  }
  diagnostics_.push_back(std::move(diagnostic));
}

void DiagnosticSink::error(std::string_view source, std::uint32_t line, std::uint32_t column,
                           std::string_view code, std::string message) {
  report(Diagnostic{Severity::Error, std::string(code), std::move(message), std::string(source),
                    line, column});
}

void DiagnosticSink::warning(std::string_view source, std::uint32_t line, std::uint32_t column,
                             std::string_view code, std::string message) {
  report(Diagnostic{Severity::Warning, std::string(code), std::move(message), std::string(source),
                    line, column});
}

std::vector<Diagnostic> DiagnosticSink::sorted() const {
  std::vector<Diagnostic> out = diagnostics_;
  std::stable_sort(out.begin(), out.end(), [](const Diagnostic& a, const Diagnostic& b) {
    if (a.source != b.source) return a.source < b.source;
    if (a.line != b.line) return a.line < b.line;
    return a.column < b.column;
  });
  return out;
}

void print_text(std::ostream& out, const std::vector<Diagnostic>& diagnostics) {
  for (const Diagnostic& d : diagnostics) out << format(d) << '\n';
}

std::string json_quote(std::string_view text) {
  std::string out;
  out.reserve(text.size() + 2);
  out += '"';
  for (char c : text) {
    const auto u = static_cast<unsigned char>(c);
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (u < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", u);
          out += buffer;
        } else {
          out += c;
        }
    }
  }
  out += '"';
  return out;
}

void print_json(std::ostream& out, const std::vector<Diagnostic>& diagnostics) {
  out << '[';
  bool first = true;
  for (const Diagnostic& d : diagnostics) {
    out << (first ? "\n  " : ",\n  ");
    first = false;
    out << "{\"file\": " << json_quote(d.source) << ", \"line\": " << d.line
        << ", \"column\": " << d.column << ", \"severity\": \"" << to_string(d.severity)
        << "\", \"code\": " << json_quote(d.code) << ", \"message\": " << json_quote(d.message)
        << '}';
  }
  out << (first ? "]\n" : "\n]\n");
}

}  // namespace knitout
