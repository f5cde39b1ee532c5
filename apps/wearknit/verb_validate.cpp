// wearknit validate: run every instruction of knitout files through the
// needle-bed virtual machine and report what would go wrong, where.
#include <filesystem>
#include <iostream>
#include <ostream>
#include <string>
#include <vector>

#include "apps/wearknit/cli.hpp"
#include "simulators/bed/profile.hpp"
#include "simulators/bed/validate.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

namespace {

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

struct FileResult {
  std::string path;
  std::vector<knitout::Diagnostic> diagnostics;
  std::size_t errors = 0;
  std::size_t warnings = 0;
  std::uint64_t instructions = 0;
};

bool fails(const FileResult& r, bool werror) {
  return r.errors > 0 || (werror && r.warnings > 0);
}

void print_github(std::ostream& out, const std::vector<FileResult>& results, bool werror) {
  for (const FileResult& r : results) {
    for (const knitout::Diagnostic& d : r.diagnostics) {
      const bool error = d.severity == knitout::Severity::Error || werror;
      out << (error ? "::error" : "::warning") << " file=" << github_escape(d.source, true);
      if (d.line > 0) out << ",line=" << d.line;
      if (d.column > 0) out << ",col=" << d.column;
      out << "::" << github_escape("[" + d.code + "] " + d.message, false) << "\n";
    }
  }
}

void print_junit(std::ostream& out, const std::vector<FileResult>& results, bool werror,
                 const std::string& machine) {
  std::size_t tests = 0;
  std::size_t failures = 0;
  for (const FileResult& r : results) {
    tests += 1 + r.diagnostics.size();
    for (const knitout::Diagnostic& d : r.diagnostics) {
      failures += d.severity == knitout::Severity::Error || werror ? 1 : 0;
    }
    failures += fails(r, werror) ? 1 : 0;
  }
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<testsuites name=\"wearknit validate\" tests=\"" << tests << "\" failures=\"" << failures
      << "\">\n";
  for (const FileResult& r : results) {
    std::size_t suite_failures = fails(r, werror) ? 1 : 0;
    for (const knitout::Diagnostic& d : r.diagnostics) {
      suite_failures += d.severity == knitout::Severity::Error || werror ? 1 : 0;
    }
    out << "  <testsuite name=\"" << xml_escape(r.path) << "\" tests=\"" << 1 + r.diagnostics.size()
        << "\" failures=\"" << suite_failures << "\">\n";
    // One case for the file as a whole, then one per diagnostic carrying its
    // file and line, so CI reports show each where it belongs.
    out << "    <testcase classname=\"wearknit.validate\" name=\""
        << xml_escape(r.path + " validates on " + machine) << "\" file=\"" << xml_escape(r.path)
        << "\">";
    if (fails(r, werror)) {
      out << "\n      <failure message=\"" << r.errors << " errors, " << r.warnings
          << " warnings\" type=\"invalid\"/>\n    ";
    }
    out << "</testcase>\n";
    for (const knitout::Diagnostic& d : r.diagnostics) {
      const bool error = d.severity == knitout::Severity::Error || werror;
      out << "    <testcase classname=\"wearknit.validate." << xml_escape(d.code) << "\" name=\""
          << xml_escape(knitout::format(d)) << "\" file=\"" << xml_escape(d.source) << "\" line=\""
          << d.line << "\">\n";
      if (error) {
        out << "      <failure message=\"" << xml_escape("[" + d.code + "] " + d.message)
            << "\" type=\"" << knitout::to_string(d.severity) << "\">"
            << xml_escape(knitout::format(d)) << "</failure>\n";
      } else {
        out << "      <system-out>" << xml_escape(knitout::format(d)) << "</system-out>\n";
      }
      out << "    </testcase>\n";
    }
    out << "  </testsuite>\n";
  }
  out << "</testsuites>\n";
}

}  // namespace

int run_validate(const std::vector<std::string>& args, Context& context) {
  std::vector<std::string> inputs;
  std::string machine_name;
  std::string format_name;
  std::size_t max_repeats = 20;
  po::options_description options("options");
  options.add_options()("input", po::value<std::vector<std::string>>(&inputs)->required(),
                        "knitout files ('-' reads stdin)")(
      "machine,m", po::value<std::string>(&machine_name)->default_value("swg091n2"),
      ("machine profile: " + bed::profile_names()).c_str())(
      "werror", "treat warnings as errors (exit 1 when there are any)")(
      "format", po::value<std::string>(&format_name)->default_value("text"),
      "diagnostics as text (stderr), json, junit or github (stdout)")("json",
                                                                      "same as --format json")(
      "max-repeats", po::value<std::size_t>(&max_repeats)->default_value(20),
      "show at most this many warnings of one code per file (0 = all)");
  po::positional_options_description positional;
  positional.add("input", -1);
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("validate"), options, positional, values, context)) {
    return *code;
  }
  auto format = parse_diagnostic_format(values.count("json") ? "json" : format_name);
  if (!format) {
    context.err << "wearknit validate: --format takes text, json, junit or github, not '"
                << format_name << "'\n";
    return kExitUsage;
  }
  const bed::MachineProfile* profile = bed::find_profile(machine_name);
  if (profile == nullptr) {
    context.err << "wearknit validate: unknown machine '" << machine_name
                << "'; known machines: " << bed::profile_names() << "\n";
    return kExitUsage;
  }
  const bool werror = values.count("werror") != 0;

  std::vector<FileResult> results;
  bool io_error = false;
  for (const std::string& input : inputs) {
    knitout::DiagnosticSink sink;
    bed::MachineOptions machine_options;
    machine_options.max_repeats = max_repeats;
    bed::Stats stats;
    FileResult result;
    result.path = input == "-" ? "<stdin>" : input;
    if (input == "-") {
      stats = bed::validate_stream(std::cin, result.path, *profile, sink, machine_options);
    } else {
      if (!std::filesystem::is_regular_file(input)) {
        context.err << input << ": error: cannot open file (not a regular file)\n";
        io_error = true;
        continue;
      }
      stats = bed::validate_file(input, *profile, sink, machine_options);
      for (const knitout::Diagnostic& d : sink.diagnostics()) io_error |= d.code == "K090";
    }
    result.diagnostics = sink.sorted();
    result.errors = sink.error_count();
    result.warnings = sink.warning_count();
    result.instructions = stats.instructions;
    results.push_back(std::move(result));
  }

  bool any_failure = false;
  std::vector<knitout::Diagnostic> all;
  for (const FileResult& r : results) {
    any_failure |= fails(r, werror);
    all.insert(all.end(), r.diagnostics.begin(), r.diagnostics.end());
  }
  switch (*format) {
    case DiagnosticFormat::Text:
      knitout::print_text(context.err, all);
      for (const FileResult& r : results) {
        context.out << r.path << ": " << (fails(r, werror) ? "INVALID" : "valid") << " on "
                    << profile->name << " (" << r.instructions << " instructions, " << r.errors
                    << " errors, " << r.warnings << " warnings)\n";
      }
      break;
    case DiagnosticFormat::Json:
      knitout::print_json(context.out, all);
      break;
    case DiagnosticFormat::Junit:
      print_junit(context.out, results, werror, profile->name);
      break;
    case DiagnosticFormat::Github:
      print_github(context.out, results, werror);
      break;
  }
  if (io_error) return kExitUsage;
  return any_failure ? kExitInvalid : kExitOk;
}

}  // namespace wearknit::cli
