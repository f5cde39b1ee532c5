// The knitout parser.
//
// `Reader` streams a knitout file: it reads the magic line and header block
// up front, then hands out one Instruction per non-blank line, holding only
// the current line in memory. `parse` collects a whole Program.
//
// Syntax problems become diagnostics (codes K001-K099, docs/diagnostics.md)
// naming the source, line and column of the offending token; the line is
// skipped and reading goes on, so one pass reports every error (up to the
// sink's cap). Semantics (carrier life cycle, racking limits, ...) are the
// needle-bed virtual machine's business, not the parser's.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "knitout/diagnostic.hpp"
#include "knitout/program.hpp"

namespace knitout {

class Reader {
 public:
  // Reads the magic line and headers of `in` at once. `source` names the
  // input in diagnostics.
  Reader(std::istream& in, std::string source, DiagnosticSink& sink);
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  int version() const { return version_; }
  bool has_magic() const { return has_magic_; }
  const std::vector<Header>& headers() const { return headers_; }
  // Carrier names seen so far (the Carriers header's first, in order).
  const CarrierTable& carriers() const { return carriers_; }
  CarrierTable take_carriers() { return std::move(carriers_); }
  const std::string& source() const { return source_; }

  // Reads the next instruction into `out`. Returns false at the end of the
  // input, or once the sink has stopped taking errors. Lines with errors are
  // reported and skipped.
  bool next(Instruction& out);
  // Text belonging to the instruction `next` returned last; valid until the
  // next call to `next`.
  std::string_view comment() const { return comment_; }
  std::string_view text() const { return text_; }

  std::uint64_t lines_read() const { return line_number_; }

 private:
  class LineSource;

  bool read_line();
  void read_header_block();
  bool parse_line(Instruction& out);
  void parse_carrier_header(std::string_view value, std::uint32_t column);

  std::unique_ptr<LineSource> lines_;
  std::string source_;
  DiagnosticSink& sink_;
  int version_ = kKnownVersion;
  bool has_magic_ = false;
  std::vector<Header> headers_;
  CarrierTable carriers_;
  std::string_view line_;
  std::uint32_t line_number_ = 0;
  bool pending_line_ = false;  // line_ read by the header block, not yet parsed
  bool warned_crlf_ = false;
  std::string_view comment_;
  std::string_view text_;
  std::string text_buffer_;
  std::vector<std::string> warned_extensions_;
};

Program parse(std::istream& in, std::string_view source, DiagnosticSink& sink);
Program parse_string(std::string_view text, std::string_view source, DiagnosticSink& sink);
// Reads a file; a file that cannot be opened is an error diagnostic (K090)
// and an empty Program.
Program parse_file(const std::string& path, DiagnosticSink& sink);

}  // namespace knitout
