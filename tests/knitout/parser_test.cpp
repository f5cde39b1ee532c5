#include "knitout/parser.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "knitout/writer.hpp"

namespace knitout {
namespace {

constexpr std::string_view kHead = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n";

Program parse_ok(std::string_view text) {
  DiagnosticSink sink;
  Program program = parse_string(text, "t.k", sink);
  EXPECT_FALSE(sink.has_errors()) << format(sink.diagnostics().front());
  return program;
}

Program parse_body(std::string_view body) {
  return parse_ok(std::string(kHead) + std::string(body));
}

TEST(ParserTest, ReadsMagicHeadersAndInstructionsWithLines) {
  const Program p = parse_ok(std::string(kHead) + ";;Gauge: 15\ninhook 3\nknit + f10 3\n");
  EXPECT_EQ(p.version, 2);
  EXPECT_TRUE(p.has_magic);
  ASSERT_EQ(p.headers.size(), 2u);
  EXPECT_EQ(p.headers[1].key, "Gauge");
  EXPECT_EQ(p.headers[1].value, "15");
  EXPECT_EQ(p.headers[1].line, 3u);
  ASSERT_EQ(p.instructions.size(), 2u);
  EXPECT_EQ(p.instructions[1].op, Op::Knit);
  EXPECT_EQ(p.instructions[1].direction, Direction::Plus);
  EXPECT_EQ(p.instructions[1].needle, (Needle{Bed::Front, 10}));
  EXPECT_EQ(p.instructions[1].line, 5u);
  EXPECT_EQ(p.carrier_name(p.instructions[1].carriers[0]), "3");
}

TEST(ParserTest, ReadsEveryOperationOfTheSpec) {
  const Program p = parse_body(
      "in 1\ninhook 2\nreleasehook 2\nout 1\nouthook 2\nstitch 5 6.5\nrack -0.75\n"
      "knit - b-2 1 2\ntuck + fs3 1\nsplit + f1 b1 3\ndrop bs4\namiss f5\nxfer f1 bs2\n"
      "miss - f0 4\npause\n");
  const Op expected[] = {Op::In,     Op::Inhook, Op::Releasehook, Op::Out,  Op::Outhook,
                         Op::Stitch, Op::Rack,   Op::Knit,        Op::Tuck, Op::Split,
                         Op::Drop,   Op::Amiss,  Op::Xfer,        Op::Miss, Op::Pause};
  ASSERT_EQ(p.instructions.size(), std::size(expected));
  for (std::size_t i = 0; i < std::size(expected); ++i) {
    EXPECT_EQ(p.instructions[i].op, expected[i]) << "instruction " << i;
  }
  EXPECT_EQ(p.instructions[5].value[0], 5.0);
  EXPECT_EQ(p.instructions[5].value[1], 6.5);
  EXPECT_EQ(p.instructions[6].racking(), -0.75);
  EXPECT_EQ(p.instructions[7].needle, (Needle{Bed::Back, -2}));
  EXPECT_EQ(p.instructions[7].carriers.size(), 2u);
  EXPECT_EQ(p.instructions[8].needle.bed, Bed::FrontSlider);
  EXPECT_EQ(p.instructions[9].needle2, (Needle{Bed::Back, 1}));
  EXPECT_EQ(p.instructions[10].needle, (Needle{Bed::BackSlider, 4}));
  EXPECT_EQ(p.instructions[12].needle2, (Needle{Bed::BackSlider, 2}));
  EXPECT_EQ(p.instructions[13].direction, Direction::Minus);
}

TEST(ParserTest, KnitWithNoCarriersIsADrop) {
  const Program p = parse_body("knit + f1\ntuck - b2\nsplit + f1 b1\n");
  for (const Instruction& in : p.instructions) EXPECT_TRUE(in.carriers.empty());
}

TEST(ParserTest, ReadsKnownExtensionsWithTheirValues) {
  const Program p = parse_body(
      "x-stitch-number 61\nx-speed-number 0\nx-presser-mode auto\nx-sub-roller-number 3\n"
      "x-xfer-stitch-number 12\nx-carrier-spacing 2\nx-vis-color #7785c2 3\n");
  ASSERT_EQ(p.instructions.size(), 7u);
  EXPECT_EQ(p.instructions[0].extension, Extension::StitchNumber);
  EXPECT_EQ(p.instructions[0].value[0], 61);
  EXPECT_EQ(p.instructions[2].extension, Extension::PresserMode);
  EXPECT_EQ(static_cast<PresserMode>(p.instructions[2].value[0]), PresserMode::Auto);
  EXPECT_EQ(p.instructions[3].extension, Extension::SubRollerNumber);
  EXPECT_EQ(p.instructions[4].extension, Extension::XferStitchNumber);
  EXPECT_EQ(p.instructions[5].extension, Extension::CarrierSpacing);
  EXPECT_EQ(p.instructions[6].extension, Extension::VisColor);
  EXPECT_EQ(p.text(p.instructions[6]), "#7785c2");
  EXPECT_EQ(p.carrier_name(p.instructions[6].carriers[0]), "3");
}

TEST(ParserTest, KeepsUnknownExtensionsWithOneWarningPerName) {
  DiagnosticSink sink;
  const Program p =
      parse_string(std::string(kHead) + "x-roller-advance 100\nx-roller-advance   50\nx-end-pass\n",
                   "t.k", sink);
  ASSERT_EQ(p.instructions.size(), 3u);
  EXPECT_EQ(p.instructions[1].extension, Extension::Unknown);
  EXPECT_EQ(p.text(p.instructions[1]), "x-roller-advance 50");
  ASSERT_EQ(sink.warning_count(), 2u);
  EXPECT_EQ(format(sink.diagnostics()[0]),
            "t.k:3:1: warning: [K020] unknown extension 'x-roller-advance' kept as written "
            "(reported once per file)");
  EXPECT_EQ(sink.diagnostics()[1].line, 5u);
}

TEST(ParserTest, KeepsCommentsOnTheirOwnAndAfterInstructions) {
  const Program p = parse_body(";a comment\ninhook 1; trailing\n;\n");
  ASSERT_EQ(p.instructions.size(), 3u);
  EXPECT_EQ(p.instructions[0].op, Op::Comment);
  EXPECT_EQ(p.comment(p.instructions[0]), "a comment");
  EXPECT_EQ(p.instructions[1].op, Op::Inhook);
  EXPECT_EQ(p.comment(p.instructions[1]), " trailing");
  EXPECT_TRUE(p.instructions[2].has_comment());
  EXPECT_EQ(p.comment(p.instructions[2]), "");
}

TEST(ParserTest, BlankLinesAreSkippedButCounted) {
  const Program p = parse_body("\n\n   \t\nknit + f1 1\n");
  ASSERT_EQ(p.instructions.size(), 1u);
  EXPECT_EQ(p.instructions[0].line, 6u);
}

TEST(ParserTest, CarriersHeaderNamesComeFirstInRailOrder) {
  const Program p = parse_ok(";!knitout-2\n;;Carriers: A B,C;D\nknit + f1 D\n");
  ASSERT_EQ(p.carriers.size(), 4u);
  EXPECT_EQ(p.carriers.name(0), "A");
  EXPECT_EQ(p.carriers.name(2), "C");
  EXPECT_EQ(p.instructions[0].carriers[0], 3);
}

TEST(ParserTest, HeaderWithoutColonSpaceEndsTheHeaderBlock) {
  DiagnosticSink sink;
  const Program p = parse_string(";!knitout-2\n;;Machine\n;;Carriers: 1 2\n", "t.k", sink);
  EXPECT_TRUE(p.headers.empty());
  ASSERT_EQ(p.instructions.size(), 2u);
  EXPECT_EQ(p.comment(p.instructions[1]), ";Carriers: 1 2");
  ASSERT_GE(sink.diagnostics().size(), 1u);
  EXPECT_EQ(sink.diagnostics()[0].code, "K030");
  EXPECT_EQ(sink.diagnostics()[0].line, 2u);
}

TEST(ParserTest, DuplicateHeaderWarnsAndTheLastWins) {
  DiagnosticSink sink;
  const Program p = parse_string(std::string(kHead) + ";;Gauge: 7\n;;Gauge: 15\n", "t.k", sink);
  EXPECT_EQ(p.header("Gauge"), "15");
  ASSERT_EQ(sink.diagnostics().size(), 1u);
  EXPECT_EQ(format(sink.diagnostics()[0]),
            "t.k:4:3: warning: [K031] header 'Gauge' given again (line 3); the last value wins");
}

TEST(ParserTest, MissingCarriersHeaderWarns) {
  DiagnosticSink sink;
  parse_string(";!knitout-2\n;;Machine: SWG091N2\nin A\n", "t.k", sink);
  ASSERT_EQ(sink.diagnostics().size(), 1u);
  EXPECT_EQ(sink.diagnostics()[0].code, "K032");
  EXPECT_EQ(sink.diagnostics()[0].severity, Severity::Warning);
}

TEST(ParserTest, NewerVersionWarnsButReads) {
  DiagnosticSink sink;
  const Program p = parse_string(";!knitout-3\n;;Carriers: 1\nin 1\n", "t.k", sink);
  EXPECT_EQ(p.version, 3);
  ASSERT_EQ(sink.diagnostics().size(), 1u);
  EXPECT_EQ(format(sink.diagnostics()[0]),
            "t.k:1:11: warning: [K002] file is knitout version 3; wearknit knows versions up to "
            "2");
}

TEST(ParserTest, MissingMagicLineWarnsAndReadsHeadersAnyway) {
  DiagnosticSink sink;
  const Program p = parse_string(";;Carriers: 1 2\ninhook 2\n", "t.k", sink);
  EXPECT_FALSE(p.has_magic);
  EXPECT_EQ(p.header("Carriers"), "1 2");
  ASSERT_EQ(p.instructions.size(), 1u);
  EXPECT_EQ(sink.diagnostics()[0].code, "K001");
  EXPECT_FALSE(sink.has_errors());
}

TEST(ParserTest, ReportsEveryErrorInOnePass) {
  DiagnosticSink sink;
  const Program p = parse_string(
      std::string(kHead) + "knot + f1 1\nknit + f1 1\nknit * f2 1\nrack x\nknit + f3 1\n", "t.k",
      sink);
  EXPECT_EQ(sink.error_count(), 3u);
  EXPECT_EQ(p.instructions.size(), 2u);
  EXPECT_EQ(sink.diagnostics()[0].line, 3u);
  EXPECT_EQ(sink.diagnostics()[1].line, 5u);
  EXPECT_EQ(sink.diagnostics()[2].line, 6u);
}

TEST(ParserTest, StopsAfterTheErrorCapWithOneMoreDiagnostic) {
  std::string text(kHead);
  for (int i = 0; i < 50; ++i) text += "bogus\n";
  DiagnosticSink sink(10);
  parse_string(text, "t.k", sink);
  EXPECT_TRUE(sink.saturated());
  ASSERT_EQ(sink.diagnostics().size(), 11u);
  EXPECT_EQ(format(sink.diagnostics().back()),
            "t.k:13: error: [K099] too many errors (10); stopped reading here");
}

TEST(ParserTest, StreamingReaderMatchesParse) {
  const std::string text = std::string(kHead) + ";c\nin 1\nknit + f1 1 ;x\nx-foo 1 2\nout 1\n";
  DiagnosticSink sink_a;
  const Program whole = parse_string(text, "t.k", sink_a);
  std::istringstream in(text);
  DiagnosticSink sink_b;
  Reader reader(in, "t.k", sink_b);
  Instruction instruction;
  std::size_t i = 0;
  while (reader.next(instruction)) {
    ASSERT_LT(i, whole.instructions.size());
    EXPECT_EQ(instruction.op, whole.instructions[i].op);
    EXPECT_EQ(instruction.line, whole.instructions[i].line);
    EXPECT_EQ(reader.comment(), whole.comment(whole.instructions[i]));
    EXPECT_EQ(reader.text(), whole.text(whole.instructions[i]));
    ++i;
  }
  EXPECT_EQ(i, whole.instructions.size());
  EXPECT_EQ(sink_a.diagnostics(), sink_b.diagnostics());
}

TEST(ParserTest, ReadsNumbersInEveryDecimalForm) {
  const Program p = parse_body("rack +1\nrack .25\nrack -2.\nrack 1e0\nrack -0\n");
  ASSERT_EQ(p.instructions.size(), 5u);
  EXPECT_EQ(p.instructions[0].racking(), 1);
  EXPECT_EQ(p.instructions[1].racking(), 0.25);
  EXPECT_EQ(p.instructions[2].racking(), -2);
  EXPECT_EQ(p.instructions[3].racking(), 1);
  EXPECT_EQ(p.instructions[4].racking(), 0);
}

}  // namespace
}  // namespace knitout
