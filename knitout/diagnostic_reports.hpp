// Diagnostics of several files as the reports CI systems read: JUnit XML
// (one test suite per file, one case for the file and one per diagnostic)
// and GitHub workflow commands (::error file=F,line=L::message).
#pragma once

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "knitout/diagnostic.hpp"

namespace knitout {

// What checking one file found.
struct FileDiagnostics {
  std::string path;
  std::vector<Diagnostic> diagnostics;
  std::size_t errors = 0;
  std::size_t warnings = 0;
  std::uint64_t instructions = 0;

  // With `werror`, warnings fail the file too.
  bool fails(bool werror) const { return errors > 0 || (werror && warnings > 0); }
};

// `text` with & < > " ' escaped and control characters other than tab and
// newline replaced by '?': safe in XML 1.0 and in HTML text and attributes.
std::string xml_escape(std::string_view text);

// `machine` names the profile the files were checked on.
void print_junit(std::ostream& out, const std::vector<FileDiagnostics>& results, bool werror,
                 const std::string& machine);
void print_github(std::ostream& out, const std::vector<FileDiagnostics>& results, bool werror);

}  // namespace knitout
