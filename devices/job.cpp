#include "devices/job.hpp"

#include <fstream>
#include <iterator>
#include <sstream>

#include "backends/dat/format.hpp"
#include "devices/file_view.hpp"
#include "knitout/parser.hpp"

namespace devices {
namespace {

std::string lower_extension(const std::string& name) {
  std::string ext = std::filesystem::path(name).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// Row 0 is the header and palette, then one row per raster row, as the
// DAT backend's reader finds them; its first error is the reason to refuse.
Result<std::vector<std::size_t>> split_dat(std::span<const std::uint8_t> bytes) {
  knitout::DiagnosticSink sink;
  const std::optional<dat::RunRows> rows = dat::scan_runs(bytes, "DAT", sink);
  if (!rows) {
    const knitout::Diagnostic& d = sink.diagnostics().front();
    return make_error(ErrorClass::InvalidArgument, "[" + d.code + "] " + d.message);
  }
  // The rows must give the file back byte for byte: nothing may follow them.
  if (rows->row_offsets.back() != bytes.size()) {
    return make_error(ErrorClass::InvalidArgument,
                      "DAT has " + std::to_string(bytes.size() - rows->row_offsets.back()) +
                          " bytes after its " + std::to_string(rows->height) + " raster rows");
  }
  std::vector<std::size_t> offsets{0};
  offsets.insert(offsets.end(), rows->row_offsets.begin(), rows->row_offsets.end());
  return offsets;
}

bool is_pass_op(knitout::Op op) {
  return op == knitout::Op::Knit || op == knitout::Op::Tuck || op == knitout::Op::Split ||
         op == knitout::Op::Miss;
}

Result<std::vector<std::size_t>> split_knitout(std::span<const std::uint8_t> bytes) {
  // Line start offsets, 1-based line numbers as the parser counts them.
  std::vector<std::size_t> line_start{0, 0};
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (bytes[i] == '\n' && i + 1 < bytes.size()) line_start.push_back(i + 1);
  }
  const std::size_t line_count = line_start.size() - 1;
  // Direction of each line's instruction: 0 none, 1 '+', 2 '-'; -1 = no instruction.
  std::vector<int> kind(line_count + 2, -1);
  SpanStreambuf view(bytes);
  std::istream in(&view);
  knitout::DiagnosticSink sink(1);
  knitout::Reader reader(in, "job", sink);
  knitout::Instruction instruction;
  std::size_t first_instruction_line = line_count + 1;
  while (reader.next(instruction)) {
    if (instruction.op == knitout::Op::Comment) continue;
    if (instruction.line == 0 || instruction.line > line_count) continue;
    first_instruction_line = std::min<std::size_t>(first_instruction_line, instruction.line);
    kind[instruction.line] = is_pass_op(instruction.op)
                                 ? (instruction.direction == knitout::Direction::Plus    ? 1
                                    : instruction.direction == knitout::Direction::Minus ? 2
                                                                                         : 0)
                                 : 0;
  }
  std::vector<std::size_t> offsets{0};
  if (first_instruction_line > line_count) {
    offsets.push_back(bytes.size());
    return offsets;
  }
  int pass_direction = 0;
  std::size_t row_start = 0;
  for (std::size_t line = first_instruction_line; line <= line_count; ++line) {
    const std::size_t start = line_start[line];
    const std::size_t end = line < line_count ? line_start[line + 1] : bytes.size();
    if (end - start > kMaxRowBytes) {
      return make_error(ErrorClass::InvalidArgument, "line " + std::to_string(line) +
                                                         " is longer than " +
                                                         std::to_string(kMaxRowBytes) + " bytes");
    }
    const int direction = kind[line] > 0 ? kind[line] : 0;
    bool boundary = line == first_instruction_line;
    if (direction != 0 && pass_direction != 0 && direction != pass_direction) boundary = true;
    if (end - row_start > kMaxRowBytes) boundary = true;
    if (boundary && start > offsets.back()) {
      offsets.push_back(start);
      row_start = start;
      pass_direction = 0;
    } else if (boundary) {
      row_start = start;
    }
    if (direction != 0) pass_direction = direction;
  }
  offsets.push_back(bytes.size());
  return offsets;
}

}  // namespace

std::span<const std::uint8_t> Job::row(std::uint32_t index) const {
  return std::span<const std::uint8_t>(bytes).subspan(
      row_offsets.at(index), row_offsets.at(index + 1) - row_offsets.at(index));
}

ManifestMessage Job::manifest() const {
  ManifestMessage m;
  m.format = format;
  m.size = bytes.size();
  m.rows = row_count();
  m.sha256 = sha256;
  m.name = name;
  return m;
}

JobFormat detect_format(const std::string& name, std::span<const std::uint8_t> bytes) {
  const std::string ext = lower_extension(name);
  if (ext == ".dat") return JobFormat::Dat;
  if (ext == ".k" || ext == ".knitout") return JobFormat::Knitout;
  static const std::string magic = ";!knitout-";
  if (bytes.size() >= magic.size() && std::equal(magic.begin(), magic.end(), bytes.begin())) {
    return JobFormat::Knitout;
  }
  return JobFormat::Unknown;
}

Result<std::vector<std::size_t>> split_rows(JobFormat format, std::span<const std::uint8_t> bytes) {
  if (bytes.empty()) return make_error(ErrorClass::InvalidArgument, "the job is empty");
  switch (format) {
    case JobFormat::Dat:
      return split_dat(bytes);
    case JobFormat::Knitout:
      return split_knitout(bytes);
    case JobFormat::Unknown:
      break;
  }
  return make_error(ErrorClass::InvalidArgument,
                    "not a DAT (.dat) or knitout (.k) job: cannot tell its rows");
}

namespace {

// Length of the UTF-8 sequence starting at text[at], or 0 when it is not a
// valid one (overlong forms, surrogates and code points past U+10FFFF are
// invalid).
std::size_t utf8_sequence(std::string_view text, std::size_t at) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned lead = byte(at);
  if (lead < 0x80) return 1;
  std::size_t length = 0;
  unsigned code = 0;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
    code = lead & 0x1F;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    code = lead & 0x0F;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    code = lead & 0x07;
  } else {
    return 0;
  }
  if (at + length > text.size()) return 0;
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(at + i) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(at + i) & 0x3F);
  }
  const unsigned smallest = length == 2 ? 0x80 : length == 3 ? 0x800 : 0x10000;
  if (code < smallest || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return length;
}

bool ends_with_ignoring_case(std::string_view text, std::string_view suffix) {
  if (text.size() < suffix.size()) return false;
  for (std::size_t i = 0; i < suffix.size(); ++i) {
    const char c = text[text.size() - suffix.size() + i];
    if (std::tolower(static_cast<unsigned char>(c)) != suffix[i]) return false;
  }
  return true;
}

}  // namespace

std::string job_name_problem(std::string_view name) {
  const auto refuse = [&](const std::string& why) {
    return "[J001] the job name '" + printable_name(name) + "' " + why;
  };
  if (name.empty()) return "[J001] the job has no name";
  if (name.size() > kMaxJobNameBytes) {
    return refuse("is " + std::to_string(name.size()) + " bytes long; a device stores names of " +
                  "at most " + std::to_string(kMaxJobNameBytes) +
                  " bytes (the files it derives from the name must fit the file system)");
  }
  for (std::size_t at = 0; at < name.size();) {
    const std::size_t length = utf8_sequence(name, at);
    if (length == 0) {
      return refuse("is not valid UTF-8 (byte " + std::to_string(at) + ")");
    }
    const unsigned char c = static_cast<unsigned char>(name[at]);
    if (c < 0x20 || c == 0x7F) return refuse("holds a control character");
    if (c == '/' || c == '\\') return refuse("names a folder; a plain file name is needed");
    if (std::string_view("\":*<>?|").find(static_cast<char>(c)) != std::string_view::npos) {
      return refuse("holds '" + std::string(1, static_cast<char>(c)) +
                    "', which a FAT-formatted stick cannot store");
    }
    at += length;
  }
  if (name.front() == '.') return refuse("is hidden (starts with a dot)");
  if (name.back() == ' ' || name.back() == '.') {
    return refuse("ends in a space or a dot, which a FAT-formatted stick drops");
  }
  for (const std::string_view suffix : {".manifest.json", ".part", ".knitlog"}) {
    if (ends_with_ignoring_case(name, suffix)) {
      return refuse("ends in '" + std::string(suffix) +
                    "', which the device uses for its own files");
    }
  }
  if (name.find(".tmp-") != std::string_view::npos) {
    return refuse("holds '.tmp-', which the device uses for its temporary files");
  }
  return {};
}

std::string printable_name(std::string_view name) {
  static const char* const kHex = "0123456789abcdef";
  std::string out;
  for (std::size_t at = 0; at < name.size();) {
    const std::size_t length = utf8_sequence(name, at);
    const unsigned char c = static_cast<unsigned char>(name[at]);
    if (length == 0 || c < 0x20 || c == 0x7F) {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 15];
      ++at;
    } else {
      out.append(name.substr(at, length));
      at += length;
    }
  }
  if (out.size() > 80) {
    // Cut at character boundaries: keep the start and the end.
    std::size_t head = 40;
    while (head > 0 && (static_cast<unsigned char>(out[head]) & 0xC0) == 0x80) --head;
    std::size_t tail = out.size() - 30;
    while (tail < out.size() && (static_cast<unsigned char>(out[tail]) & 0xC0) == 0x80) ++tail;
    out = out.substr(0, head) + "..." + out.substr(tail);
  }
  return out;
}

Result<Job> make_job(std::string name, Bytes bytes) {
  if (std::string problem = job_name_problem(name); !problem.empty()) {
    return make_error(ErrorClass::InvalidArgument, problem);
  }
  Job job;
  job.format = detect_format(name, bytes);
  auto offsets = split_rows(job.format, bytes);
  if (!offsets) return offsets.error();
  job.name = std::move(name);
  job.bytes = std::move(bytes);
  job.row_offsets = std::move(offsets.value());
  job.sha256 = sha256(job.bytes);
  return job;
}

Result<Job> load_job(const std::filesystem::path& path) {
  // One read into a buffer of the file's size: the job costs its size once.
  auto bytes = read_file(path);
  if (!bytes) return bytes.error();
  auto job = make_job(path.filename().string(), std::move(bytes.value()));
  if (!job) {
    Error e = job.error();
    e.message = path.string() + ": " + e.message;
    return e;
  }
  return job;
}

std::string check_knitout_syntax(const std::string& name, std::span<const std::uint8_t> bytes) {
  knitout::DiagnosticSink sink(20);
  knitout::parse_string(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()),
                        name, sink);
  for (const knitout::Diagnostic& d : sink.diagnostics()) {
    if (d.severity == knitout::Severity::Error) {
      return knitout::format(d) +
             (sink.error_count() > 1
                  ? " (and " + std::to_string(sink.error_count() - 1) + " more errors)"
                  : "");
    }
  }
  return {};
}

}  // namespace devices
