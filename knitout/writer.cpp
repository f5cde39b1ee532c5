#include "knitout/writer.hpp"

#include <charconv>
#include <ostream>

namespace knitout {

std::string format_number(double value) {
  if (value == 0) value = 0;  // no "-0"
  char buffer[64];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

namespace {

void append_carriers(std::string& out, const CarrierTable& table, const CarrierList& carriers) {
  for (CarrierId id : carriers) {
    out += ' ';
    out += table.name(id);
  }
}

void append_needle(std::string& out, Needle needle) {
  out += ' ';
  out += to_string(needle);
}

}  // namespace

void append_instruction(std::string& out, const CarrierTable& carriers, const Instruction& in,
                        std::string_view comment, std::string_view text) {
  const std::size_t start = out.size();
  switch (in.op) {
    case Op::Comment:
      break;
    case Op::In:
    case Op::Inhook:
    case Op::Releasehook:
    case Op::Out:
    case Op::Outhook:
      out += op_name(in.op);
      append_carriers(out, carriers, in.carriers);
      break;
    case Op::Stitch:
      out += "stitch ";
      out += format_number(in.value[0]);
      out += ' ';
      out += format_number(in.value[1]);
      break;
    case Op::Rack:
      out += "rack ";
      out += format_number(in.value[0]);
      break;
    case Op::Knit:
    case Op::Tuck:
    case Op::Miss:
      out += op_name(in.op);
      out += ' ';
      out += direction_char(in.direction);
      append_needle(out, in.needle);
      append_carriers(out, carriers, in.carriers);
      break;
    case Op::Split:
      out += "split ";
      out += direction_char(in.direction);
      append_needle(out, in.needle);
      append_needle(out, in.needle2);
      append_carriers(out, carriers, in.carriers);
      break;
    case Op::Drop:
    case Op::Amiss:
      out += op_name(in.op);
      append_needle(out, in.needle);
      break;
    case Op::Xfer:
      out += "xfer";
      append_needle(out, in.needle);
      append_needle(out, in.needle2);
      break;
    case Op::Pause:
      out += "pause";
      break;
    case Op::Extension:
      switch (in.extension) {
        case Extension::PresserMode:
          out += extension_name(in.extension);
          out += ' ';
          out += presser_mode_name(static_cast<PresserMode>(in.value[0]));
          break;
        case Extension::VisColor:
          out += extension_name(in.extension);
          out += ' ';
          out += text;
          append_carriers(out, carriers, in.carriers);
          break;
        case Extension::Unknown:
        case Extension::None:
          out += text;
          break;
        default:
          out += extension_name(in.extension);
          out += ' ';
          out += format_number(in.value[0]);
          break;
      }
      break;
  }
  if (in.comment != kNoText) {
    if (out.size() != start) out += ' ';
    out += ';';
    out += comment;
  }
}

void write(std::ostream& out, const Program& program) {
  std::string buffer;
  buffer.reserve(1 << 16);
  buffer += ";!knitout-";
  buffer += std::to_string(program.version);
  buffer += '\n';
  for (const Header& header : program.headers) {
    buffer += ";;";
    buffer += header.key;
    buffer += ": ";
    buffer += header.value;
    buffer += '\n';
  }
  bool in_header_zone = true;
  for (const Instruction& instruction : program.instructions) {
    const std::size_t line_start = buffer.size();
    append_instruction(buffer, program.carriers, instruction, program.comment(instruction),
                       program.text(instruction));
    // A comment line starting with ';' right after the headers would read
    // back as a header line (or end the header block); a leading space keeps
    // it a comment with the same text.
    if (in_header_zone && instruction.op == Op::Comment &&
        buffer.compare(line_start, 2, ";;") == 0) {
      buffer.insert(line_start, 1, ' ');
    }
    in_header_zone = false;
    buffer += '\n';
    if (buffer.size() > (1 << 16)) {
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

std::string write_to_string(const Program& program) {
  std::string out;
  struct StringBuf : std::streambuf {
    std::string* target;
    std::streamsize xsputn(const char* s, std::streamsize n) override {
      target->append(s, static_cast<std::size_t>(n));
      return n;
    }
    int_type overflow(int_type c) override {
      if (c != traits_type::eof()) target->push_back(static_cast<char>(c));
      return c;
    }
  } buf;
  buf.target = &out;
  std::ostream stream(&buf);
  write(stream, program);
  return out;
}

}  // namespace knitout
