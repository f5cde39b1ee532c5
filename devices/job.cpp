#include "devices/job.hpp"

#include <fstream>
#include <iterator>
#include <sstream>

#include "backends/dat/format.hpp"
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
  std::string text(bytes.begin(), bytes.end());
  std::istringstream in(text);
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

bool valid_job_name(std::string_view name) {
  if (name.empty() || name.size() > 255 || name[0] == '.') return false;
  for (char c : name) {
    if (c == '/' || c == '\\' || static_cast<unsigned char>(c) < 0x20 || c == 0x7F) return false;
  }
  return true;
}

Result<Job> make_job(std::string name, Bytes bytes) {
  if (!valid_job_name(name)) {
    return make_error(ErrorClass::InvalidArgument,
                      "'" + name + "' cannot name a job on a device (a plain file name is needed)");
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
  std::ifstream in(path, std::ios::binary);
  if (!in) return os_error("cannot open " + path.string());
  Bytes bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return os_error("cannot read " + path.string());
  auto job = make_job(path.filename().string(), std::move(bytes));
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
