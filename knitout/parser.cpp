#include "knitout/parser.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <istream>
#include <sstream>

namespace knitout {

// Reads lines from a stream in large blocks; a line is a view into the block
// (or, when it straddles blocks, into a reused buffer), so reading allocates
// nothing per line once the buffers have grown.
class Reader::LineSource {
 public:
  explicit LineSource(std::istream& in) : in_(in), block_(1 << 16) {}

  bool next(std::string_view& line) {
    long_line_.clear();
    bool straddling = false;
    for (;;) {
      if (pos_ == end_) {
        if (!refill()) {
          if (!straddling) return false;
          line = long_line_;
          return true;
        }
      }
      const char* start = block_.data() + pos_;
      const std::size_t available = end_ - pos_;
      const void* newline = std::memchr(start, '\n', available);
      if (newline != nullptr) {
        const std::size_t length = static_cast<const char*>(newline) - start;
        pos_ += length + 1;
        if (!straddling) {
          line = std::string_view(start, length);
        } else {
          long_line_.append(start, length);
          line = long_line_;
        }
        return true;
      }
      long_line_.append(start, available);
      straddling = true;
      pos_ = end_;
    }
  }

 private:
  bool refill() {
    if (!in_) return false;
    in_.read(block_.data(), static_cast<std::streamsize>(block_.size()));
    end_ = static_cast<std::size_t>(in_.gcount());
    pos_ = 0;
    return end_ > 0;
  }

  std::istream& in_;
  std::vector<char> block_;
  std::size_t pos_ = 0;
  std::size_t end_ = 0;
  std::string long_line_;
};

namespace {

constexpr std::size_t kMaxTokens = 24;
constexpr std::size_t kMaxQuoted = 40;

struct Token {
  std::string_view text;
  std::uint32_t column;  // 1-based
};

struct Tokens {
  std::array<Token, kMaxTokens> items;
  std::size_t count = 0;
  bool overflow = false;
  std::uint32_t overflow_column = 0;  // the first token past the limit
};

bool is_blank(char c) {
  return c == ' ' || c == '\t';
}

// Position of the first control character other than tab, or npos. Knitout
// is text; a stray carriage return or NUL inside a line could not survive a
// round trip through the writer.
std::size_t find_control(std::string_view line) {
  for (std::size_t i = 0; i < line.size(); ++i) {
    const auto c = static_cast<unsigned char>(line[i]);
    if ((c < 0x20 && c != '\t') || c == 0x7f) return i;
  }
  return std::string_view::npos;
}

void tokenize(std::string_view code, Tokens& tokens) {
  tokens.count = 0;
  tokens.overflow = false;
  std::size_t i = 0;
  while (i < code.size()) {
    while (i < code.size() && is_blank(code[i])) ++i;
    if (i == code.size()) break;
    const std::size_t start = i;
    while (i < code.size() && !is_blank(code[i])) ++i;
    if (tokens.count == kMaxTokens) {
      tokens.overflow = true;
      tokens.overflow_column = static_cast<std::uint32_t>(start + 1);
      return;
    }
    tokens.items[tokens.count++] = {code.substr(start, i - start),
                                    static_cast<std::uint32_t>(start + 1)};
  }
}

// A token as it appears in a message: quoted, long ones shortened.
std::string quote(std::string_view token) {
  std::string out = "'";
  const std::string_view shown = token.substr(0, kMaxQuoted);
  for (char c : shown) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02X", static_cast<unsigned>(u));
      out += escaped;
    } else {
      out += c;
    }
  }
  if (token.size() > kMaxQuoted) out += "...";
  out += '\'';
  return out;
}

std::optional<Needle> parse_needle(std::string_view token) {
  Needle needle;
  std::size_t i = 0;
  if (token.empty()) return std::nullopt;
  if (token[0] == 'f') {
    needle.bed = Bed::Front;
  } else if (token[0] == 'b') {
    needle.bed = Bed::Back;
  } else {
    return std::nullopt;
  }
  i = 1;
  if (i < token.size() && token[i] == 's') {
    needle.bed = needle.bed == Bed::Front ? Bed::FrontSlider : Bed::BackSlider;
    ++i;
  }
  std::string_view digits = token.substr(i);
  if (digits.empty()) return std::nullopt;
  const char* first = digits.data();
  const char* last = digits.data() + digits.size();
  if (*first == '-' && digits.size() == 1) return std::nullopt;
  if (*first != '-' && (*first < '0' || *first > '9')) return std::nullopt;
  auto result = std::from_chars(first, last, needle.index);
  if (result.ec != std::errc() || result.ptr != last) return std::nullopt;
  return needle;
}

// Decimal numbers as knitout writes them: [+-]digits[.digits][e[+-]digits].
std::optional<double> parse_number(std::string_view token) {
  std::size_t i = 0;
  if (i < token.size() && (token[i] == '+' || token[i] == '-')) ++i;
  const std::size_t mantissa = i;
  bool digits = false;
  while (i < token.size() && token[i] >= '0' && token[i] <= '9') ++i, digits = true;
  if (i < token.size() && token[i] == '.') {
    ++i;
    while (i < token.size() && token[i] >= '0' && token[i] <= '9') ++i, digits = true;
  }
  if (!digits) return std::nullopt;
  if (i < token.size() && (token[i] == 'e' || token[i] == 'E')) {
    ++i;
    if (i < token.size() && (token[i] == '+' || token[i] == '-')) ++i;
    bool exponent = false;
    while (i < token.size() && token[i] >= '0' && token[i] <= '9') ++i, exponent = true;
    if (!exponent) return std::nullopt;
  }
  if (i != token.size()) return std::nullopt;
  double value = 0;
  const char* first = token.data() + mantissa;
  auto result = std::from_chars(first, token.data() + token.size(), value);
  if (result.ec != std::errc()) return std::nullopt;
  if (token[0] == '-') value = -value;
  return value;
}

std::optional<std::int64_t> parse_unsigned(std::string_view token) {
  std::int64_t value = 0;
  if (token.empty() || token[0] < '0' || token[0] > '9') return std::nullopt;
  auto result = std::from_chars(token.data(), token.data() + token.size(), value);
  if (result.ec != std::errc() || result.ptr != token.data() + token.size()) {
    return std::nullopt;
  }
  return value;
}

bool is_hex_colour(std::string_view token) {
  if (token.size() != 7 || token[0] != '#') return false;
  for (char c : token.substr(1)) {
    const bool hex = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
    if (!hex) return false;
  }
  return true;
}

}  // namespace

Reader::Reader(std::istream& in, std::string source, DiagnosticSink& sink)
    : lines_(std::make_unique<LineSource>(in)), source_(std::move(source)), sink_(sink) {
  read_header_block();
}

Reader::~Reader() = default;

bool Reader::read_line() {
  if (!lines_->next(line_)) return false;
  ++line_number_;
  if (!line_.empty() && line_.back() == '\r') {
    line_.remove_suffix(1);
    if (!warned_crlf_) {
      warned_crlf_ = true;
      sink_.warning(source_, line_number_, 0, "K003",
                    "CRLF line ending; knitout lines end with LF (reported once per file)");
    }
  }
  return true;
}

void Reader::parse_carrier_header(std::string_view value, std::uint32_t column) {
  // Rails are separated by spaces; `,` joins carriers on one rail and `;`
  // splits a rail into left and right (knitout spec, Carriers header).
  std::size_t i = 0;
  while (i < value.size()) {
    while (i < value.size() && (is_blank(value[i]) || value[i] == ',' || value[i] == ';')) ++i;
    const std::size_t start = i;
    while (i < value.size() && !is_blank(value[i]) && value[i] != ',' && value[i] != ';') ++i;
    if (i > start && !carriers_.intern(value.substr(start, i - start))) {
      sink_.error(source_, line_number_, column + static_cast<std::uint32_t>(start), "K017",
                  "too many carrier names (at most " + std::to_string(kMaxCarrierNames) + ")");
      return;
    }
  }
}

void Reader::read_header_block() {
  if (!read_line()) {
    sink_.warning(source_, 0, 0, "K001", "empty file: no knitout magic line ';!knitout-N'");
    return;
  }
  constexpr std::string_view kMagic = ";!knitout-";
  if (line_.substr(0, kMagic.size()) == kMagic) {
    std::string_view rest = line_.substr(kMagic.size());
    while (!rest.empty() && is_blank(rest.back())) rest.remove_suffix(1);
    auto number = parse_unsigned(rest);
    if (!number || *number > 1000000) {
      sink_.error(source_, line_number_, static_cast<std::uint32_t>(kMagic.size() + 1), "K005",
                  "malformed magic line: version " + quote(rest) + " is not a whole number");
    } else {
      version_ = static_cast<int>(*number);
      if (version_ > kKnownVersion) {
        sink_.warning(source_, line_number_, static_cast<std::uint32_t>(kMagic.size() + 1), "K002",
                      "file is knitout version " + std::to_string(version_) +
                          "; wearknit knows versions up to " + std::to_string(kKnownVersion));
      }
    }
    has_magic_ = true;
    if (!read_line()) {
      sink_.warning(source_, line_number_, 0, "K032", "no ';;Carriers:' header");
      return;
    }
  } else {
    sink_.warning(source_, 1, 1, "K001",
                  "missing magic line ';!knitout-N' (file starts with " + quote(line_) +
                      "); reading as knitout version " + std::to_string(kKnownVersion));
  }

  // Header lines: `;;Key: value` until the first line that is not `;;...`.
  for (;;) {
    if (line_.substr(0, 2) != ";;") break;
    if (find_control(line_) != std::string_view::npos) break;  // reported as a line
    const std::string_view body = line_.substr(2);
    const std::size_t colon = body.find(": ");
    if (colon == std::string_view::npos) {
      sink_.warning(source_, line_number_, 1, "K030",
                    "header line without ': ' ends the header block; it and any later ';;' "
                    "lines are comments");
      break;
    }
    Header header{std::string(body.substr(0, colon)), std::string(body.substr(colon + 2)),
                  line_number_};
    for (const Header& earlier : headers_) {
      if (earlier.key == header.key) {
        sink_.warning(source_, line_number_, 3, "K031",
                      "header '" + header.key + "' given again (line " +
                          std::to_string(earlier.line) + "); the last value wins");
        break;
      }
    }
    if (header.key == "Carriers") {
      parse_carrier_header(header.value, static_cast<std::uint32_t>(colon + 5));
    }
    headers_.push_back(std::move(header));
    if (!read_line()) {
      line_ = {};
      break;
    }
  }
  bool has_carriers = false;
  for (const Header& header : headers_) has_carriers |= header.key == "Carriers";
  if (!has_carriers) {
    sink_.warning(source_, line_number_, 0, "K032",
                  "no ';;Carriers:' header; carriers are named by their first use");
  }
  pending_line_ = line_.data() != nullptr;
}

bool Reader::next(Instruction& out) {
  for (;;) {
    if (sink_.saturated()) return false;
    if (pending_line_) {
      pending_line_ = false;
    } else if (!read_line()) {
      return false;
    }
    if (parse_line(out)) return true;
  }
}

// Parses line_ into `out`; false for blank lines and lines with errors.
bool Reader::parse_line(Instruction& out) {
  const std::uint32_t ln = line_number_;
  if (const std::size_t at = find_control(line_); at != std::string_view::npos) {
    char code_point[8];
    std::snprintf(code_point, sizeof code_point, "0x%02X",
                  static_cast<unsigned>(static_cast<unsigned char>(line_[at])));
    sink_.error(source_, ln, static_cast<std::uint32_t>(at + 1), "K004",
                line_[at] == '\0'
                    ? std::string("NUL byte in line; knitout is text")
                    : std::string("control character ") + code_point + " in line; knitout is text");
    return false;
  }
  std::string_view code = line_;
  comment_ = {};
  text_ = {};
  out = Instruction{};
  out.line = ln;
  bool has_comment = false;
  if (const std::size_t semicolon = line_.find(';'); semicolon != std::string_view::npos) {
    code = line_.substr(0, semicolon);
    comment_ = line_.substr(semicolon + 1);
    has_comment = true;
  }
  Tokens tokens;
  tokenize(code, tokens);
  if (tokens.count == 0) {
    if (!has_comment) return false;  // blank line
    out.op = Op::Comment;
    out.comment = 0;
    return true;
  }
  if (has_comment) out.comment = 0;  // the caller stores comment_ and renumbers
  auto error = [&](std::uint32_t column, std::string_view code_id, std::string message) {
    sink_.error(source_, ln, column, code_id, std::move(message));
    return false;
  };
  const Token& opcode = tokens.items[0];
  const std::uint32_t end_column = static_cast<std::uint32_t>(code.size() + 1);
  if (tokens.overflow) {
    return error(tokens.overflow_column, "K014",
                 "too many arguments for " + quote(opcode.text) + " (more than " +
                     std::to_string(kMaxTokens - 1) + ")");
  }

  std::size_t at = 1;  // next argument token
  auto missing = [&](std::string_view what) {
    return error(end_column, "K013", "missing " + std::string(what) + " for " + quote(opcode.text));
  };
  auto take_direction = [&]() -> bool {
    if (at >= tokens.count) return missing("direction ('+' or '-')");
    const Token& t = tokens.items[at++];
    if (t.text == "+") {
      out.direction = Direction::Plus;
    } else if (t.text == "-") {
      out.direction = Direction::Minus;
    } else {
      return error(t.column, "K012",
                   "invalid direction " + quote(t.text) + "; expected '+' or '-'");
    }
    return true;
  };
  auto take_needle = [&](Needle& needle) -> bool {
    if (at >= tokens.count) return missing("needle");
    const Token& t = tokens.items[at++];
    auto parsed = parse_needle(t.text);
    if (!parsed) {
      return error(
          t.column, "K011",
          "invalid needle " + quote(t.text) + "; expected f, b, fs or bs followed by an integer");
    }
    needle = *parsed;
    return true;
  };
  auto take_carriers = [&]() -> bool {
    for (; at < tokens.count; ++at) {
      const Token& t = tokens.items[at];
      if (t.text.find(',') != std::string_view::npos) {
        return error(t.column, "K016",
                     "invalid carrier name " + quote(t.text) + "; names hold no ',' or ';'");
      }
      auto id = carriers_.intern(t.text);
      if (!id) {
        return error(t.column, "K017",
                     "too many carrier names (at most " + std::to_string(kMaxCarrierNames) + ")");
      }
      if (out.carriers.contains(*id)) {
        return error(t.column, "K018", "carrier " + quote(t.text) + " named twice");
      }
      if (!out.carriers.push_back(*id)) {
        return error(t.column, "K017",
                     "too many carriers in one instruction (at most " +
                         std::to_string(kMaxCarriersPerInstruction) + ")");
      }
    }
    return true;
  };
  auto no_more = [&]() -> bool {
    if (at < tokens.count) {
      const Token& t = tokens.items[at];
      return error(t.column, "K014",
                   "unexpected argument " + quote(t.text) + " for " + quote(opcode.text));
    }
    return true;
  };
  auto take_number = [&](double& value, std::string_view what) -> bool {
    if (at >= tokens.count) return missing(what);
    const Token& t = tokens.items[at++];
    auto parsed = parse_number(t.text);
    if (!parsed) {
      return error(t.column, "K015", std::string(what) + " " + quote(t.text) + " is not a number");
    }
    value = *parsed;
    return true;
  };

  if (opcode.text.substr(0, 2) == "x-") {
    out.op = Op::Extension;
    out.extension = extension_from_name(opcode.text);
    switch (out.extension) {
      case Extension::PresserMode: {
        if (at >= tokens.count) return missing("mode (on, off or auto)");
        const Token& t = tokens.items[at++];
        if (t.text == "on") {
          out.value[0] = static_cast<double>(PresserMode::On);
        } else if (t.text == "off") {
          out.value[0] = static_cast<double>(PresserMode::Off);
        } else if (t.text == "auto") {
          out.value[0] = static_cast<double>(PresserMode::Auto);
        } else {
          return error(t.column, "K021",
                       "x-presser-mode takes on, off or auto, not " + quote(t.text));
        }
        return no_more();
      }
      case Extension::VisColor: {
        if (at >= tokens.count) return missing("colour (#RRGGBB)");
        const Token& t = tokens.items[at++];
        if (!is_hex_colour(t.text)) {
          return error(t.column, "K021",
                       "x-vis-color takes a colour #RRGGBB, not " + quote(t.text));
        }
        text_ = t.text;
        out.text = 0;
        if (at >= tokens.count) return missing("carrier");
        return take_carriers();
      }
      case Extension::Unknown: {
        if (std::find(warned_extensions_.begin(), warned_extensions_.end(), opcode.text) ==
            warned_extensions_.end()) {
          warned_extensions_.emplace_back(opcode.text);
          sink_.warning(source_, ln, opcode.column, "K020",
                        "unknown extension " + quote(opcode.text) +
                            " kept as written (reported once per file)");
        }
        text_buffer_.clear();
        for (std::size_t i = 0; i < tokens.count; ++i) {
          if (i > 0) text_buffer_ += ' ';
          text_buffer_.append(tokens.items[i].text);
        }
        text_ = text_buffer_;
        out.text = 0;
        return true;
      }
      default: {
        if (at >= tokens.count) return missing("number");
        const Token& t = tokens.items[at++];
        auto value = parse_unsigned(t.text);
        if (!value || *value > 1000000) {
          return error(t.column, "K021",
                       std::string(extension_name(out.extension)) +
                           " takes one non-negative integer, not " + quote(t.text));
        }
        out.value[0] = static_cast<double>(*value);
        return no_more();
      }
    }
  }

  auto op = op_from_name(opcode.text);
  if (!op) return error(opcode.column, "K010", "unknown operation " + quote(opcode.text));
  out.op = *op;
  switch (out.op) {
    case Op::In:
    case Op::Inhook:
    case Op::Releasehook:
    case Op::Out:
    case Op::Outhook:
      if (at >= tokens.count) return missing("carriers");
      return take_carriers();
    case Op::Stitch:
      return take_number(out.value[0], "leading value") &&
             take_number(out.value[1], "stitch value") && no_more();
    case Op::Rack:
      return take_number(out.value[0], "racking") && no_more();
    case Op::Knit:
    case Op::Tuck:
    case Op::Miss:
      return take_direction() && take_needle(out.needle) && take_carriers();
    case Op::Split:
      return take_direction() && take_needle(out.needle) && take_needle(out.needle2) &&
             take_carriers();
    case Op::Drop:
    case Op::Amiss:
      return take_needle(out.needle) && no_more();
    case Op::Xfer:
      return take_needle(out.needle) && take_needle(out.needle2) && no_more();
    case Op::Pause:
      return no_more();
    case Op::Comment:
    case Op::Extension:
      break;
  }
  return false;
}

Program parse(std::istream& in, std::string_view source, DiagnosticSink& sink) {
  Reader reader(in, std::string(source), sink);
  Program program;
  program.version = reader.version();
  program.has_magic = reader.has_magic();
  program.headers = reader.headers();
  Instruction instruction;
  while (reader.next(instruction)) {
    if (instruction.comment != kNoText) instruction.comment = program.add_text(reader.comment());
    if (instruction.text != kNoText) instruction.text = program.add_text(reader.text());
    program.instructions.push_back(instruction);
  }
  program.carriers = reader.take_carriers();
  return program;
}

Program parse_string(std::string_view text, std::string_view source, DiagnosticSink& sink) {
  std::istringstream in{std::string(text)};
  return parse(in, source, sink);
}

Program parse_file(const std::string& path, DiagnosticSink& sink) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    sink.error(path, 0, 0, "K090", std::string("cannot open file: ") + std::strerror(errno));
    return Program{};
  }
  return parse(in, path, sink);
}

}  // namespace knitout
