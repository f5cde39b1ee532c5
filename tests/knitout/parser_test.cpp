#include "knitout/parser.hpp"

#include <gtest/gtest.h>

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

TEST(ParserTest, ReadsMagicHeadersAndInstructionsWithLines) {
  const Program p = parse_ok(std::string(kHead) + ";;Gauge: 15\ninhook 3\nknit + f10 3\n");
  EXPECT_EQ(p.version, 2);
  ASSERT_EQ(p.headers.size(), 2u);
  EXPECT_EQ(p.headers[1].key, "Gauge");
  EXPECT_EQ(p.headers[1].value, "15");
  ASSERT_EQ(p.instructions.size(), 2u);
  EXPECT_EQ(p.instructions[1].op, Op::Knit);
  EXPECT_EQ(p.instructions[1].direction, Direction::Plus);
  EXPECT_EQ(p.instructions[1].needle, (Needle{Bed::Front, 10}));
  EXPECT_EQ(p.instructions[1].line, 5u);
  EXPECT_EQ(p.carrier_name(p.instructions[1].carriers[0]), "3");
}

}  // namespace
}  // namespace knitout
