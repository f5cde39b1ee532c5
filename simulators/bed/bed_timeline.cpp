#include "simulators/bed/bed_timeline.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "simulators/bed/validate.hpp"

namespace bed {

namespace {

constexpr std::uint32_t kMagic = 0x54424b57;  // "WKBT" read as little-endian u32
constexpr std::uint32_t kVersion = 1;

// Appends little-endian values; every section is padded to 4 bytes.
class ByteWriter {
 public:
  explicit ByteWriter(std::string& out) : out_(out) {}
  void u8(std::uint8_t v) { out_ += static_cast<char>(v); }
  void u16(std::uint16_t v) {
    u8(static_cast<std::uint8_t>(v));
    u8(static_cast<std::uint8_t>(v >> 8));
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void bytes(std::string_view text) { out_ += text; }
  void pad() {
    while (out_.size() % 4 != 0) out_ += '\0';
  }

 private:
  std::string& out_;
};

std::uint8_t severity_code(knitout::Severity severity) {
  switch (severity) {
    case knitout::Severity::Error:
      return 0;
    case knitout::Severity::Warning:
      return 1;
    default:
      return 2;
  }
}

}  // namespace

BedTimeline::Cell* BedTimeline::cell(knitout::Needle needle) {
  if (!based_) {
    based_ = true;
    base_ = std::int64_t{needle.index} - kMaxNeedles / 2;
    for (auto& bed : beds_) bed.assign(static_cast<std::size_t>(kMaxNeedles), Cell{});
  }
  const std::int64_t i = std::int64_t{needle.index} - base_;
  if (i < 0 || i >= kMaxNeedles) return nullptr;
  return &beds_[static_cast<std::size_t>(needle.bed)][static_cast<std::size_t>(i)];
}

void BedTimeline::record(knitout::Needle needle, const Cell& c, std::uint32_t line, bool transfer) {
  if (needle.is_slider()) return;
  if (records_.size() >= max_records_) {
    truncated_ = true;
    return;
  }
  Record r;
  r.needle = needle.index;
  r.line = line;
  r.yarn = c.yarn;
  r.count = static_cast<std::uint8_t>(std::min<std::uint32_t>(c.count, 255));
  r.bed = needle.bed == knitout::Bed::Front ? 0 : 1;
  r.transfer = transfer;
  records_.push_back(r);
}

void BedTimeline::loop_made(const LoopEvent& event) {
  if (stopped_) return;
  if (made_.empty() || made_.back().first != event.line) {
    made_.emplace_back(event.line, event.yarn);
  } else {
    made_.back().second = event.yarn;
  }
  Cell* c = cell(event.needle);
  if (c == nullptr) return;
  switch (event.kind) {
    case LoopKind::Knit:  // the old loops were pulled through and left the needle
      c->count = 1;
      break;
    case LoopKind::Tuck:
      ++c->count;
      break;
    case LoopKind::Split:  // the old loops move to the other bed (loops_moved next)
      split_moved_yarn_ = event.parents.empty() ? c->yarn : event.parents.back().yarn;
      split_needle_ = event.needle;
      split_line_ = event.line;
      split_pending_ = true;
      c->count = 1;
      break;
  }
  c->yarn = event.yarn;
  record(event.needle, *c, event.line, false);
}

void BedTimeline::loops_moved(knitout::Needle from, knitout::Needle to, int count,
                              std::uint32_t line) {
  if (stopped_) return;
  move_lines_.push_back(line);
  const bool split = split_pending_ && split_needle_ == from && split_line_ == line;
  split_pending_ = false;
  Cell* source = cell(from);
  Cell* target = cell(to);
  std::uint16_t yarn = split ? split_moved_yarn_ : 0;
  if (!split && source != nullptr) {
    // xfer moves the whole stack.
    yarn = source->yarn;
    source->count = 0;
    record(from, *source, line, false);
  }
  if (target == nullptr) return;
  target->count += static_cast<std::uint32_t>(std::max(count, 0));
  target->yarn = yarn;
  record(to, *target, line, true);
}

void BedTimeline::loops_dropped(knitout::Needle needle, std::span<const LiveLoop> /*loops*/,
                                std::uint32_t line) {
  if (stopped_) return;
  Cell* c = cell(needle);
  if (c == nullptr) return;
  c->count = 0;
  record(needle, *c, line, false);
}

void BedTimeline::sweep_ended(const Machine& machine, std::uint32_t line) {
  // The machine ends a sweep when the first instruction of the next one has
  // already run, so the changes, moves and loops of lines after `line`
  // belong to the next sweep.
  if (stopped_) return;
  std::size_t end = records_.size();
  const std::size_t begin = sweeps_.empty() ? 0 : sweeps_.back().record_end;
  while (end > begin && records_[end - 1].line > line) --end;
  Sweep sweep;
  sweep.record_begin = static_cast<std::uint32_t>(begin);
  sweep.record_end = static_cast<std::uint32_t>(end);
  sweep.last_line = line;
  sweep.first_line = end > begin ? records_[begin].line : line;
  sweep.racking = machine.racking();
  sweep.racked = sweep.racking != last_racking_;
  last_racking_ = sweep.racking;

  const auto later_move =
      std::find_if(move_lines_.begin(), move_lines_.end(), [&](auto l) { return l > line; });
  sweep.transfers = static_cast<std::uint32_t>(later_move - move_lines_.begin());
  move_lines_.erase(move_lines_.begin(), later_move);

  const auto later_made =
      std::find_if(made_.begin(), made_.end(), [&](const auto& m) { return m.first > line; });
  if (later_made != made_.begin()) sweep.yarn = std::prev(later_made)->second;
  made_.erase(made_.begin(), later_made);
  sweeps_.push_back(sweep);

  lines_ = std::max<std::uint64_t>(lines_, machine.stats().lines);
  // Yarns and carrier names as the machine knows them now (both only grow).
  for (std::size_t y = yarn_codes_.size(); y < machine.yarn_count(); ++y) {
    const knitout::CarrierList& carriers = machine.yarn(static_cast<std::uint16_t>(y));
    yarn_codes_.push_back(
        carriers.empty() ? 0 : static_cast<std::uint8_t>(std::min(carriers[0] + 1, 255)));
  }
  const knitout::CarrierTable& names = machine.carrier_names();
  for (std::size_t c = carrier_names_.size(); c < names.size(); ++c) {
    carrier_names_.push_back(names.name(static_cast<knitout::CarrierId>(c)));
  }
  if (truncated_ || sweeps_.size() >= max_sweeps_) {
    // Stop here: what the next sweep recorded already goes.
    truncated_ = true;
    stopped_ = true;
    records_.resize(end);
    move_lines_.clear();
    made_.clear();
  }
}

std::string BedTimeline::serialize(std::span<const knitout::Diagnostic> diagnostics) const {
  // Records after the last sweep (none when the machine finished) join it.
  std::vector<Sweep> sweeps = sweeps_;
  const std::uint32_t recorded = static_cast<std::uint32_t>(records_.size());
  if (!sweeps.empty() && sweeps.back().record_end < recorded) {
    sweeps.back().record_end = recorded;
    sweeps.back().last_line = std::max(sweeps.back().last_line, records_.back().line);
  } else if (sweeps.empty() && recorded > 0) {
    Sweep only;
    only.record_end = recorded;
    only.first_line = records_.front().line;
    only.last_line = records_.back().line;
    sweeps.push_back(only);
  }

  std::int32_t needle_min = 0;
  std::int32_t needle_max = -1;
  for (const Record& r : records_) {
    if (needle_min > needle_max) {
      needle_min = needle_max = r.needle;
    } else {
      needle_min = std::min(needle_min, r.needle);
      needle_max = std::max(needle_max, r.needle);
    }
  }
  const std::uint32_t width =
      needle_min > needle_max ? 0 : static_cast<std::uint32_t>(needle_max - needle_min + 1);

  auto code_of = [&](std::uint16_t yarn) -> std::uint8_t {
    return yarn < yarn_codes_.size() ? yarn_codes_[yarn] : 0;
  };
  const std::size_t carrier_count = std::min<std::size_t>(carrier_names_.size(), 254);
  auto last_line = static_cast<std::uint32_t>(std::min<std::uint64_t>(lines_, 0xffffffffu));
  for (const Sweep& s : sweeps) last_line = std::max(last_line, s.last_line);
  for (const knitout::Diagnostic& d : diagnostics) last_line = std::max(last_line, d.line);
  // Cells and line deltas as u16 when they all fit, which makes the page
  // quicker to read (less to decompress) and smaller in memory.
  const bool short_cells = 2 * std::uint64_t{width} <= 0x10000;
  bool short_deltas = true;
  for (const Sweep& s : sweeps) {
    if (s.record_end > s.record_begin && records_[s.record_end - 1].line - s.first_line > 0xffff) {
      short_deltas = false;
    }
  }

  std::string out;
  out.reserve(64 + sweeps.size() * 22 + records_.size() * 11 + diagnostics.size() * 96);
  ByteWriter w(out);
  const auto sweep_count = static_cast<std::uint32_t>(sweeps.size());
  w.u32(kMagic);
  w.u32(kVersion);
  w.u32(sweep_count);
  w.u32(recorded);
  w.i32(needle_min);
  w.u32(width);
  w.u32(last_line);
  w.u32((truncated_ ? 1u : 0u) | (short_cells ? 2u : 0u) | (short_deltas ? 4u : 0u));
  w.u32(static_cast<std::uint32_t>(carrier_count));
  w.u32(static_cast<std::uint32_t>(diagnostics.size()));
  w.u32(0);
  w.u32(0);
  for (std::size_t c = 0; c < carrier_count; ++c) {
    const std::string& name = carrier_names_[c];
    const std::size_t n = std::min<std::size_t>(name.size(), 255);
    w.u8(static_cast<std::uint8_t>(n));
    w.bytes(std::string_view(name).substr(0, n));
  }
  w.pad();

  for (const Sweep& s : sweeps) w.u32(s.first_line);
  for (const Sweep& s : sweeps) w.u32(s.last_line);
  for (const Sweep& s : sweeps) w.u32(s.record_begin);
  w.u32(recorded);
  for (const Sweep& s : sweeps) w.u32(s.transfers);
  for (const Sweep& s : sweeps) {
    const double q = std::clamp(std::round(s.racking * 4), -2e9, 2e9);
    w.i32(static_cast<std::int32_t>(q));
  }
  for (const Sweep& s : sweeps) w.u8(s.yarn == 0xffff ? 0 : code_of(s.yarn));
  for (const Sweep& s : sweeps) {
    w.u8(static_cast<std::uint8_t>((s.racked ? 1 : 0) | (s.transfers > 0 ? 2 : 0)));
  }
  w.pad();

  for (const Record& r : records_) {
    const std::uint32_t cell = static_cast<std::uint32_t>(r.needle - needle_min) * 2 + r.bed;
    if (short_cells) {
      w.u16(static_cast<std::uint16_t>(cell));
    } else {
      w.u32(cell);
    }
  }
  w.pad();
  for (const Sweep& s : sweeps) {
    for (std::uint32_t i = s.record_begin; i < s.record_end; ++i) {
      const std::uint32_t delta = records_[i].line - s.first_line;
      if (short_deltas) {
        w.u16(static_cast<std::uint16_t>(delta));
      } else {
        w.u32(delta);
      }
    }
  }
  w.pad();
  for (const Record& r : records_) w.u8(r.count == 0 ? 0 : code_of(r.yarn));
  for (const Record& r : records_) w.u8(r.count);
  for (const Record& r : records_) w.u8(r.transfer ? 1 : 0);
  w.pad();

  for (const knitout::Diagnostic& d : diagnostics) {
    // The sweep whose line range holds the line: the first ending at or after it.
    const auto it =
        std::lower_bound(sweeps.begin(), sweeps.end(), d.line,
                         [](const Sweep& s, std::uint32_t l) { return s.last_line < l; });
    std::uint32_t sweep = static_cast<std::uint32_t>(it - sweeps.begin());
    if (sweep_count > 0) sweep = std::min(sweep, sweep_count - 1);
    const std::string_view code = std::string_view(d.code).substr(0, 255);
    const std::string_view message = std::string_view(d.message).substr(0, 65535);
    w.u32(d.line);
    w.u32(sweep);
    w.u8(severity_code(d.severity));
    w.u8(static_cast<std::uint8_t>(code.size()));
    w.u16(static_cast<std::uint16_t>(message.size()));
    w.bytes(code);
    w.bytes(message);
    w.pad();
  }
  return out;
}

std::string timeline_bytes(const knitout::Program& program, const MachineProfile& profile,
                           std::string_view source, knitout::DiagnosticSink& sink) {
  BedTimeline timeline;
  MachineOptions options;
  options.observer = &timeline;
  validate(program, profile, sink, source, options);
  return timeline.serialize(sink.sorted());
}

}  // namespace bed
