// The bed timeline of the HTML bed view: sweeps, needle records, source
// lines and diagnostics, read back from the serialised layout.
#include "simulators/bed/bed_timeline.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "knitout/generate.hpp"
#include "knitout/parser.hpp"
#include "simulators/bed/validate.hpp"

namespace bed {
namespace {

// The layout of bed_timeline.hpp, read back.
struct ReadTimeline {
  struct Sweep {
    std::uint32_t first_line, last_line, record_begin, record_end, transfers;
    std::int32_t racking_q;
    std::uint8_t carrier, flags;
  };
  struct Record {
    int needle;
    char bed;  // 'f' or 'b'
    std::uint32_t line;
    std::uint8_t carrier, count, flags;
    bool operator==(const Record&) const = default;
  };
  struct Diag {
    std::uint32_t line, sweep;
    std::uint8_t severity;
    std::string code, message;
  };
  std::uint32_t magic = 0, version = 0, last_line = 0, flags = 0;
  std::int32_t needle_min = 0;
  std::uint32_t width = 0;
  std::vector<std::string> carriers;
  std::vector<Sweep> sweeps;
  std::vector<Record> records;  // in sweep order
  std::vector<Diag> diagnostics;
  std::size_t size = 0;
};

ReadTimeline read_timeline(const std::string& bytes) {
  ReadTimeline t;
  std::size_t at = 0;
  auto u8 = [&]() { return static_cast<std::uint8_t>(bytes.at(at++)); };
  auto u16 = [&]() {
    const std::uint16_t low = u8();
    return static_cast<std::uint16_t>(low | u8() << 8);
  };
  auto u32 = [&]() {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= std::uint32_t{u8()} << (8 * i);
    return v;
  };
  auto align = [&]() { at = (at + 3) & ~std::size_t{3}; };
  t.magic = u32();
  t.version = u32();
  const std::uint32_t sweeps = u32();
  const std::uint32_t records = u32();
  t.needle_min = static_cast<std::int32_t>(u32());
  t.width = u32();
  t.last_line = u32();
  t.flags = u32();
  const std::uint32_t carriers = u32();
  const std::uint32_t diagnostics = u32();
  EXPECT_EQ(u32(), 0u);
  EXPECT_EQ(u32(), 0u);
  for (std::uint32_t c = 0; c < carriers; ++c) {
    const std::uint8_t n = u8();
    t.carriers.push_back(bytes.substr(at, n));
    at += n;
  }
  align();
  t.sweeps.resize(sweeps);
  for (auto& s : t.sweeps) s.first_line = u32();
  for (auto& s : t.sweeps) s.last_line = u32();
  for (auto& s : t.sweeps) s.record_begin = u32();
  const std::uint32_t records_end = u32();
  EXPECT_EQ(records_end, records);
  for (std::size_t i = 0; i < t.sweeps.size(); ++i) {
    t.sweeps[i].record_end = i + 1 < t.sweeps.size() ? t.sweeps[i + 1].record_begin : records_end;
  }
  for (auto& s : t.sweeps) s.transfers = u32();
  for (auto& s : t.sweeps) s.racking_q = static_cast<std::int32_t>(u32());
  for (auto& s : t.sweeps) s.carrier = u8();
  for (auto& s : t.sweeps) s.flags = u8();
  align();
  t.records.resize(records);
  for (auto& r : t.records) {
    const std::uint32_t cell = t.flags & 2 ? u16() : u32();
    r.needle = t.needle_min + static_cast<int>(cell / 2);
    r.bed = cell % 2 == 0 ? 'f' : 'b';
  }
  align();
  for (const auto& s : t.sweeps) {
    for (std::uint32_t i = s.record_begin; i < s.record_end; ++i) {
      t.records[i].line = s.first_line + (t.flags & 4 ? u16() : u32());
    }
  }
  align();
  for (auto& r : t.records) r.carrier = u8();
  for (auto& r : t.records) r.count = u8();
  for (auto& r : t.records) r.flags = u8();
  align();
  for (std::uint32_t d = 0; d < diagnostics; ++d) {
    ReadTimeline::Diag diag;
    diag.line = u32();
    diag.sweep = u32();
    diag.severity = u8();
    const std::uint8_t code_length = u8();
    const std::uint16_t message_length = u16();
    diag.code = bytes.substr(at, code_length);
    diag.message = bytes.substr(at + code_length, message_length);
    at += code_length + message_length;
    align();
    t.diagnostics.push_back(diag);
  }
  t.size = at;
  return t;
}

constexpr const char* kProgram =
    ";!knitout-2\n;;Carriers: 1 2 3\n"
    "in 3\n"             // 3
    "tuck + f1 3\n"      // 4   sweep 0
    "tuck + f2 3\n"      // 5
    "knit - f2 3\n"      // 6   sweep 1 (the direction turns)
    "tuck - f1 3\n"      // 7   f1 holds two loops
    "rack 1\n"           // 8
    "xfer f2 b1\n"       // 9   sweep 2, at racking 1
    "rack 0\n"           // 10
    "split + f1 b1 3\n"  // 11  sweep 3: f1's two loops join b1's one
    "drop b1\n"          // 12  sweep 4
    "out 3\n";           // 13

std::string run(const char* text, knitout::DiagnosticSink& sink) {
  const knitout::Program program = knitout::parse_string(text, "t.k", sink);
  return timeline_bytes(program, default_profile(), "t.k", sink);
}

TEST(BedTimelineTest, RecordsEveryNeedleChangeInItsSweepWithItsLine) {
  knitout::DiagnosticSink sink;
  const ReadTimeline t = read_timeline(run(kProgram, sink));
  EXPECT_EQ(t.magic, 0x54424b57u);
  EXPECT_EQ(t.version, 1u);
  EXPECT_EQ(t.flags, 6u);  // short cells and line deltas
  EXPECT_EQ(t.needle_min, 1);
  EXPECT_EQ(t.width, 2u);
  EXPECT_EQ(t.last_line, 13u);
  EXPECT_EQ(t.carriers, (std::vector<std::string>{"1", "2", "3"}));
  ASSERT_EQ(t.sweeps.size(), 5u);
  const std::uint32_t first[] = {4, 6, 9, 11, 12};
  const std::uint32_t last[] = {5, 7, 9, 11, 12};
  for (std::size_t s = 0; s < 5; ++s) {
    EXPECT_EQ(t.sweeps[s].first_line, first[s]) << "sweep " << s;
    EXPECT_EQ(t.sweeps[s].last_line, last[s]) << "sweep " << s;
  }
  // Racking during each sweep, whether it changed, the transfers, the carrier.
  EXPECT_EQ(t.sweeps[1].racking_q, 0);
  EXPECT_EQ(t.sweeps[2].racking_q, 4);
  EXPECT_EQ(t.sweeps[2].flags, 3);  // racked, transfers
  EXPECT_EQ(t.sweeps[3].flags, 3);  // racked back; split moved loops
  EXPECT_EQ(t.sweeps[4].flags, 0);
  EXPECT_EQ(t.sweeps[2].transfers, 1u);
  EXPECT_EQ(t.sweeps[0].carrier, 3);  // carrier id 2 ("3") + 1
  EXPECT_EQ(t.sweeps[2].carrier, 0);  // an xfer uses no carrier
  using R = ReadTimeline::Record;
  const std::vector<R> expected = {
      {1, 'f', 4, 3, 1, 0},  {2, 'f', 5, 3, 1, 0},   // sweep 0: the tucks
      {2, 'f', 6, 3, 1, 0},  {1, 'f', 7, 3, 2, 0},   // sweep 1: knit, second tuck
      {2, 'f', 9, 0, 0, 0},  {1, 'b', 9, 3, 1, 1},   // sweep 2: f2's loop moves to b1
      {1, 'f', 11, 3, 1, 0}, {1, 'b', 11, 3, 3, 1},  // sweep 3: split
      {1, 'b', 12, 0, 0, 0},                         // sweep 4: drop
  };
  EXPECT_EQ(t.records, expected);
  const std::uint32_t begin[] = {0, 2, 4, 6, 8};
  for (std::size_t s = 0; s < 5; ++s) EXPECT_EQ(t.sweeps[s].record_begin, begin[s]);
}

TEST(BedTimelineTest, PlacesDiagnosticsAtTheSweepOfTheirLine) {
  knitout::DiagnosticSink sink;
  const ReadTimeline t = read_timeline(run(kProgram, sink));
  ASSERT_EQ(t.diagnostics.size(), sink.diagnostics().size());
  ASSERT_FALSE(t.diagnostics.empty());
  // The drop of line 12 lets go of the knit loop of line 6 (V053).
  bool found = false;
  for (const auto& d : t.diagnostics) {
    if (d.code != "V053") continue;
    found = true;
    EXPECT_EQ(d.line, 12u);
    EXPECT_EQ(d.sweep, 4u);
    EXPECT_EQ(d.severity, 1);
    EXPECT_NE(d.message.find("let go of 1 loop"), std::string::npos) << d.message;
  }
  EXPECT_TRUE(found);

  knitout::DiagnosticSink bad_sink;
  const ReadTimeline bad = read_timeline(
      run(";!knitout-2\n;;Carriers: 1 2 3\nin 3\ntuck + f1 3\ntuck + f2 3\nknit + f5 2\nout 3\n",
          bad_sink));
  ASSERT_EQ(bad.sweeps.size(), 2u);  // knit with another carrier starts a sweep
  ASSERT_FALSE(bad.diagnostics.empty());
  EXPECT_EQ(bad.diagnostics[0].code, "V004");
  EXPECT_EQ(bad.diagnostics[0].line, 6u);
  EXPECT_EQ(bad.diagnostics[0].sweep, 1u);
  EXPECT_EQ(bad.diagnostics[0].severity, 0);
}

ReadTimeline run_capped(std::size_t max_records, std::size_t max_sweeps) {
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(kProgram, "t.k", sink);
  BedTimeline timeline(max_records, max_sweeps);
  MachineOptions options;
  options.observer = &timeline;
  validate(program, default_profile(), sink, "t.k", options);
  EXPECT_TRUE(timeline.truncated());
  return read_timeline(timeline.serialize(sink.sorted()));
}

TEST(BedTimelineTest, StopsAtTheEndOfTheSweepThatReachedItsRecordCap) {
  // The fifth record (f2 emptied by the xfer of line 9) is the last: the
  // timeline ends with that sweep, and says so.
  const ReadTimeline t = run_capped(5, BedTimeline::kMaxSweeps);
  EXPECT_EQ(t.flags & 1, 1u);
  ASSERT_EQ(t.sweeps.size(), 3u);
  ASSERT_EQ(t.records.size(), 5u);
  EXPECT_EQ(t.records[4].line, 9u);
  EXPECT_EQ(t.sweeps[2].record_end, 5u);
  // The diagnostics beyond it are placed at the last sweep recorded.
  for (const auto& d : t.diagnostics) EXPECT_LE(d.sweep, 2u);
}

TEST(BedTimelineTest, StopsAtItsSweepCap) {
  const ReadTimeline t = run_capped(BedTimeline::kMaxRecords, 2);
  EXPECT_EQ(t.flags & 1, 1u);
  ASSERT_EQ(t.sweeps.size(), 2u);
  EXPECT_EQ(t.records.size(), 4u);
  EXPECT_EQ(t.sweeps[1].last_line, 7u);
}

TEST(BedTimelineTest, KeepsLongLineDeltasWhole) {
  // 70,000 comment lines inside one sweep: its second record is 70,001 lines
  // after its first, too far for the short line deltas.
  std::string text = ";!knitout-2\n;;Carriers: 1 2 3\nin 3\ntuck + f1 3\n";
  for (int i = 0; i < 70000; ++i) text += ";\n";
  text += "tuck + f2 3\nout 3\n";
  knitout::DiagnosticSink sink;
  const ReadTimeline t = read_timeline(run(text.c_str(), sink));
  EXPECT_EQ(t.flags, 2u);  // short cells, long line deltas
  ASSERT_EQ(t.sweeps.size(), 1u);
  ASSERT_EQ(t.records.size(), 2u);
  EXPECT_EQ(t.records[0].line, 4u);
  EXPECT_EQ(t.records[1].line, 70005u);
}

TEST(BedTimelineTest, SerialisedSizeMatchesItsLayout) {
  knitout::DiagnosticSink sink;
  const std::string bytes = run(kProgram, sink);
  EXPECT_EQ(bytes.size() % 4, 0u);
  EXPECT_EQ(read_timeline(bytes).size, bytes.size());
}

TEST(BedTimelineTest, AProgramWithoutSweepsHasAnEmptyTimeline) {
  knitout::DiagnosticSink sink;
  const ReadTimeline t = read_timeline(run(";!knitout-2\n;;Carriers: 1\nrack 1\nrack 0\n", sink));
  EXPECT_EQ(t.sweeps.size(), 0u);
  EXPECT_EQ(t.records.size(), 0u);
  EXPECT_EQ(t.width, 0u);
}

TEST(BedTimelineTest, AgreesWithTheMachineOnAGeneratedSheet) {
  // Every needle's last record is what the machine holds at the end.
  knitout::SheetParams params;
  params.width_needles = 9;
  params.rows = 5;
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(knitout::sheet_text(params), "s.k", sink);
  BedTimeline timeline;
  MachineOptions options;
  options.observer = &timeline;
  Machine machine(default_profile(), sink, "s.k", program.carriers, program.carriers.size(),
                  options);
  std::uint32_t last = 0;
  for (const auto& instruction : program.instructions) {
    machine.step(instruction);
    last = instruction.line;
  }
  machine.finish(last);
  ASSERT_FALSE(sink.has_errors());
  const ReadTimeline t = read_timeline(timeline.serialize(sink.sorted()));
  ASSERT_GT(t.sweeps.size(), 5u);
  for (int n = t.needle_min; n < t.needle_min + static_cast<int>(t.width); ++n) {
    for (char bed : {'f', 'b'}) {
      int count = 0;
      for (const auto& r : t.records) {
        if (r.needle == n && r.bed == bed) count = r.count;
      }
      const knitout::Needle needle{bed == 'f' ? knitout::Bed::Front : knitout::Bed::Back, n};
      EXPECT_EQ(count, static_cast<int>(machine.loops_on(needle).size())) << bed << n;
    }
  }
  // Sweeps cover the lines in order, each record inside its sweep's lines.
  std::uint32_t previous = 0;
  for (const auto& s : t.sweeps) {
    EXPECT_GT(s.last_line, previous);
    EXPECT_LE(s.first_line, s.last_line);
    for (std::uint32_t i = s.record_begin; i < s.record_end; ++i) {
      EXPECT_GT(t.records[i].line, previous);
      EXPECT_LE(t.records[i].line, s.last_line);
    }
    previous = s.last_line;
  }
}

}  // namespace
}  // namespace bed
