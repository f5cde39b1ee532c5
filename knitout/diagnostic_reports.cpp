// Diagnostics as CI reports: JUnit XML and GitHub workflow commands
// (diagnostic_reports.hpp).
#include "knitout/diagnostic_reports.hpp"

#include <ostream>

namespace knitout {

namespace {

// GitHub workflow commands: data escapes %, CR, LF; properties also : and ,.
std::string github_escape(std::string_view text, bool property) {
  std::string out;
  for (char c : text) {
    if (c == '%') {
      out += "%25";
    } else if (c == '\r') {
      out += "%0D";
    } else if (c == '\n') {
      out += "%0A";
    } else if (property && c == ':') {
      out += "%3A";
    } else if (property && c == ',') {
      out += "%2C";
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

std::string xml_escape(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        // Control characters other than tab and newline are not allowed in XML 1.0.
        if (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') {
          out += '?';
        } else {
          out += c;
        }
    }
  }
  return out;
}

void print_github(std::ostream& out, const std::vector<FileDiagnostics>& results, bool werror) {
  for (const FileDiagnostics& r : results) {
    for (const Diagnostic& d : r.diagnostics) {
      const bool error = d.severity == Severity::Error || werror;
      out << (error ? "::error" : "::warning") << " file=" << github_escape(d.source, true);
      if (d.line > 0) out << ",line=" << d.line;
      if (d.column > 0) out << ",col=" << d.column;
      out << "::" << github_escape("[" + d.code + "] " + d.message, false) << "\n";
    }
  }
}

void print_junit(std::ostream& out, const std::vector<FileDiagnostics>& results, bool werror,
                 const std::string& machine) {
  std::size_t tests = 0;
  std::size_t failures = 0;
  for (const FileDiagnostics& r : results) {
    tests += 1 + r.diagnostics.size();
    for (const Diagnostic& d : r.diagnostics) {
      failures += d.severity == Severity::Error || werror ? 1 : 0;
    }
    failures += r.fails(werror) ? 1 : 0;
  }
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<testsuites name=\"wearknit validate\" tests=\"" << tests << "\" failures=\"" << failures
      << "\">\n";
  for (const FileDiagnostics& r : results) {
    std::size_t suite_failures = r.fails(werror) ? 1 : 0;
    for (const Diagnostic& d : r.diagnostics) {
      suite_failures += d.severity == Severity::Error || werror ? 1 : 0;
    }
    out << "  <testsuite name=\"" << xml_escape(r.path) << "\" tests=\"" << 1 + r.diagnostics.size()
        << "\" failures=\"" << suite_failures << "\">\n";
    // One case for the file as a whole, then one per diagnostic carrying its
    // file and line, so CI reports show each where it belongs.
    out << "    <testcase classname=\"wearknit.validate\" name=\""
        << xml_escape(r.path + " validates on " + machine) << "\" file=\"" << xml_escape(r.path)
        << "\">";
    if (r.fails(werror)) {
      out << "\n      <failure message=\"" << r.errors << " errors, " << r.warnings
          << " warnings\" type=\"invalid\"/>\n    ";
    }
    out << "</testcase>\n";
    for (const Diagnostic& d : r.diagnostics) {
      const bool error = d.severity == Severity::Error || werror;
      out << "    <testcase classname=\"wearknit.validate." << xml_escape(d.code) << "\" name=\""
          << xml_escape(format(d)) << "\" file=\"" << xml_escape(d.source) << "\" line=\"" << d.line
          << "\">\n";
      if (error) {
        out << "      <failure message=\"" << xml_escape("[" + d.code + "] " + d.message)
            << "\" type=\"" << to_string(d.severity) << "\">" << xml_escape(format(d))
            << "</failure>\n";
      } else {
        out << "      <system-out>" << xml_escape(format(d)) << "</system-out>\n";
      }
      out << "    </testcase>\n";
    }
    out << "  </testsuite>\n";
  }
  out << "</testsuites>\n";
}

}  // namespace knitout
