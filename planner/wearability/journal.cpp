#include "planner/wearability/journal.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "knitout/output_file.hpp"

namespace planner {

namespace {

constexpr const char* kMagic = "wearknit wearability journal 3 ";

std::string hex(std::uint64_t value) {
  std::ostringstream out;
  out << std::hex << std::setw(16) << std::setfill('0') << value;
  return out.str();
}

bool read_hex(std::istream& in, std::uint64_t& value) {
  std::string text;
  if (!(in >> text) || text.size() != 16) return false;
  value = 0;
  for (char c : text) {
    int digit;
    if (c >= '0' && c <= '9') {
      digit = c - '0';
    } else if (c >= 'a' && c <= 'f') {
      digit = c - 'a' + 10;
    } else {
      return false;
    }
    value = (value << 4) | static_cast<std::uint64_t>(digit);
  }
  return true;
}

bool read_flag(std::istream& in, bool& flag) {
  int value;
  if (!(in >> value) || (value != 0 && value != 1)) return false;
  flag = value == 1;
  return true;
}

std::string header(std::uint64_t context) {
  return kMagic + hex(context);
}

}  // namespace

std::string journal_line(std::uint64_t key, const TestResult& result) {
  std::ostringstream out;
  out << hex(key) << ' ' << (result.wearable ? 1 : 0) << ' ' << result.steps << ' '
      << result.projections << ' ' << result.trials.size();
  out << std::setprecision(17);
  for (const TrialOutcome& t : result.trials) {
    out << ' ' << hex(t.seed) << ' ' << (t.success ? 1 : 0) << ' ' << t.steps << ' '
        << (t.stalled ? 1 : 0) << ' ' << t.min_distance << ' ' << t.caught << ' ' << t.caught_at.x()
        << ' ' << t.caught_at.y() << ' ' << t.caught_at.z() << ' ' << t.caught_radius << ' '
        << t.cloth_vertices;
  }
  out << ' ' << result.openings.size();
  for (const double opening : result.openings) out << ' ' << opening;
  const std::string body = out.str();
  return body + ' ' + hex(fingerprint(body));
}

std::optional<std::pair<std::uint64_t, TestResult>> parse_journal_line(const std::string& line) {
  // The last word is the fingerprint of the rest: a line cut short or
  // changed in any way does not match it.
  const std::size_t space = line.rfind(' ');
  if (space == std::string::npos) return std::nullopt;
  std::istringstream check(line.substr(space + 1));
  std::uint64_t sum;
  if (!read_hex(check, sum) || sum != fingerprint(std::string_view(line).substr(0, space))) {
    return std::nullopt;
  }
  std::istringstream in(line.substr(0, space));
  std::uint64_t key;
  TestResult result;
  std::size_t trials;
  if (!read_hex(in, key) || !read_flag(in, result.wearable) || !(in >> result.steps) ||
      !(in >> result.projections) || !(in >> trials) || trials > 1'000'000) {
    return std::nullopt;
  }
  result.trials.resize(trials);
  for (TrialOutcome& t : result.trials) {
    if (!read_hex(in, t.seed) || !read_flag(in, t.success) || !(in >> t.steps) ||
        !read_flag(in, t.stalled) || !(in >> t.min_distance) || !(in >> t.caught) ||
        !(in >> t.caught_at.x() >> t.caught_at.y() >> t.caught_at.z()) ||
        !(in >> t.caught_radius >> t.cloth_vertices)) {
      return std::nullopt;
    }
  }
  std::size_t openings;
  if (!(in >> openings) || openings > 1'000'000) return std::nullopt;
  result.openings.resize(openings);
  for (double& opening : result.openings) {
    if (!(in >> opening)) return std::nullopt;
  }
  std::string rest;
  if (in >> rest) return std::nullopt;
  return std::make_pair(key, std::move(result));
}

TestJournal::TestJournal(std::string path, std::uint64_t context, bool fresh)
    : path_(std::move(path)), context_(context) {
  std::ifstream in(path_, std::ios::binary);
  std::string content;
  if (in && !fresh) {
    std::ostringstream buffer;
    buffer << in.rdbuf();
    content = buffer.str();
  }
  std::istringstream lines(content);
  std::string line;
  // Only lines ended by a newline were written whole.
  const bool same_context = std::getline(lines, line) && line == header(context_);
  std::string kept = header(context_) + '\n';
  if (same_context) {
    std::size_t start = static_cast<std::size_t>(lines.tellg());
    while (start < content.size()) {
      const std::size_t end = content.find('\n', start);
      if (end == std::string::npos) {
        ++skipped_;
        break;
      }
      line = content.substr(start, end - start);
      start = end + 1;
      auto parsed = parse_journal_line(line);
      if (!parsed) {
        ++skipped_;
        continue;
      }
      if (tests_.emplace(parsed->first, std::move(parsed->second)).second) {
        ++loaded_;
        kept += line + '\n';
      }
    }
  }
  error_ = knitout::write_file_atomically(path_, [&](std::ostream& out) { out << kept; });
  if (!error_.empty()) return;
  file_ = std::fopen(path_.c_str(), "ab");
  if (file_ == nullptr) error_ = path_ + ": cannot append: " + std::strerror(errno);
}

TestJournal::~TestJournal() {
  if (file_ != nullptr) std::fclose(file_);
}

std::optional<TestResult> TestJournal::find(std::uint64_t key) {
  const auto it = tests_.find(key);
  if (it == tests_.end()) return std::nullopt;
  return it->second;
}

void TestJournal::add(std::uint64_t key, const TestResult& result) {
  tests_.emplace(key, result);
  if (file_ == nullptr) return;
  const std::string line = journal_line(key, result) + '\n';
  if (std::fwrite(line.data(), 1, line.size(), file_) != line.size() || std::fflush(file_) != 0 ||
      ::fsync(::fileno(file_)) != 0) {
    if (error_.empty()) error_ = path_ + ": cannot append: " + std::strerror(errno);
    std::fclose(file_);
    file_ = nullptr;
  }
}

std::string TestJournal::remove() {
  if (file_ != nullptr) {
    std::fclose(file_);
    file_ = nullptr;
  }
  if (std::remove(path_.c_str()) != 0 && errno != ENOENT) {
    return path_ + ": cannot remove: " + std::strerror(errno);
  }
  return {};
}

}  // namespace planner
