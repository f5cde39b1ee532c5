// Malformed knitout: each input gets exactly the documented diagnostic
// (code, line, column, text), and nothing crashes (the sanitizer build runs
// these too).
#include <gtest/gtest.h>

#include <ostream>
#include <string>

#include "knitout/parser.hpp"

namespace knitout {
namespace {

constexpr std::string_view kHead = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n";

struct Case {
  const char* name;
  std::string body;      // appended to kHead; its first line is line 3
  std::string expected;  // the first diagnostic, formatted
};

// Shown by GoogleTest (and ctest) in place of the case's bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

std::string with_nul() {
  std::string s = "knit + f1";
  s += '\0';
  s += " 3\n";
  return s;
}

std::vector<Case> cases() {
  const std::string long_token(10 * 1024 * 1024, 'q');
  return {
      {"UnknownOpcode", "knot + f1 3\n", "t.k:3:1: error: [K010] unknown operation 'knot'"},
      {"GarbageBytes", "\xff\xfe\x80 f1\n",
       "t.k:3:1: error: [K010] unknown operation '\xff\xfe\x80'"},
      {"ControlCharacter", "knit + f1 \x01\n",
       "t.k:3:11: error: [K004] control character 0x01 in line; knitout is text"},
      {"UppercaseOpcode", "KNIT + f1 3\n", "t.k:3:1: error: [K010] unknown operation 'KNIT'"},
      {"BadNeedleLetter", "knit + x5 3\n",
       "t.k:3:8: error: [K011] invalid needle 'x5'; expected f, b, fs or bs followed by an "
       "integer"},
      {"NeedleWithoutNumber", "tuck - f 3\n",
       "t.k:3:8: error: [K011] invalid needle 'f'; expected f, b, fs or bs followed by an "
       "integer"},
      {"NeedleWithTrailingJunk", "knit + f1a 3\n",
       "t.k:3:8: error: [K011] invalid needle 'f1a'; expected f, b, fs or bs followed by an "
       "integer"},
      {"NeedleOutOfRange", "drop b99999999999\n",
       "t.k:3:6: error: [K011] invalid needle 'b99999999999'; expected f, b, fs or bs "
       "followed by an integer"},
      {"NeedleMinusOnly", "knit + b- 3\n",
       "t.k:3:8: error: [K011] invalid needle 'b-'; expected f, b, fs or bs followed by an "
       "integer"},
      {"MissingDirection", "knit\n",
       "t.k:3:5: error: [K013] missing direction ('+' or '-') for 'knit'"},
      {"MissingNeedle", "knit +\n", "t.k:3:7: error: [K013] missing needle for 'knit'"},
      {"BadDirection", "knit * f1 3\n",
       "t.k:3:6: error: [K012] invalid direction '*'; expected '+' or '-'"},
      {"DirectionAndNeedleSwapped", "tuck f1 + 3\n",
       "t.k:3:6: error: [K012] invalid direction 'f1'; expected '+' or '-'"},
      {"XferWithCarrier", "xfer f1 b1 3\n",
       "t.k:3:12: error: [K014] unexpected argument '3' for 'xfer'"},
      {"DropWithCarrier", "drop f1 3\n",
       "t.k:3:9: error: [K014] unexpected argument '3' for 'drop'"},
      {"XferMissingTarget", "xfer f1\n", "t.k:3:8: error: [K013] missing needle for 'xfer'"},
      {"SplitMissingTarget", "split + f1\n", "t.k:3:11: error: [K013] missing needle for 'split'"},
      {"RackNotANumber", "rack x\n", "t.k:3:6: error: [K015] racking 'x' is not a number"},
      {"RackHex", "rack 0x1\n", "t.k:3:6: error: [K015] racking '0x1' is not a number"},
      {"RackMissing", "rack\n", "t.k:3:5: error: [K013] missing racking for 'rack'"},
      {"RackTwoArguments", "rack 1 2\n",
       "t.k:3:8: error: [K014] unexpected argument '2' for 'rack'"},
      {"StitchOneArgument", "stitch 5\n",
       "t.k:3:9: error: [K013] missing stitch value for 'stitch'"},
      {"StitchNotANumber", "stitch a 5\n",
       "t.k:3:8: error: [K015] leading value 'a' is not a number"},
      {"InWithoutCarriers", "in\n", "t.k:3:3: error: [K013] missing carriers for 'in'"},
      {"OuthookWithoutCarriers", "outhook   \n",
       "t.k:3:11: error: [K013] missing carriers for 'outhook'"},
      {"PauseWithArgument", "pause now\n",
       "t.k:3:7: error: [K014] unexpected argument 'now' for 'pause'"},
      {"CarrierWithComma", "knit + f1 1,2\n",
       "t.k:3:11: error: [K016] invalid carrier name '1,2'; names hold no ',' or ';'"},
      {"CarrierTwice", "knit + f1 3 3\n", "t.k:3:13: error: [K018] carrier '3' named twice"},
      {"TooManyCarriers", "in 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16\n",
       "t.k:3:40: error: [K017] too many carriers in one instruction (at most 15)"},
      {"TooManyTokens", "knit + f1 1 2 3 4 5 6 7 8 9 10 a b c d e f g h i j k l m\n",
       "t.k:3:54: error: [K014] too many arguments for 'knit' (more than 23)"},
      {"NulByte", with_nul(), "t.k:3:10: error: [K004] NUL byte in line; knitout is text"},
      {"CarriageReturnInsideLine", "in A\r\x16knit - B\r \n",
       "t.k:3:5: error: [K004] control character 0x0D in line; knitout is text"},
      {"PresserModeWord", "x-presser-mode sometimes\n",
       "t.k:3:16: error: [K021] x-presser-mode takes on, off or auto, not 'sometimes'"},
      {"StitchNumberNegative", "x-stitch-number -1\n",
       "t.k:3:17: error: [K021] x-stitch-number takes one non-negative integer, not '-1'"},
      {"SpeedNumberMissing", "x-speed-number\n",
       "t.k:3:15: error: [K013] missing number for 'x-speed-number'"},
      {"VisColorNotAColour", "x-vis-color red 1\n",
       "t.k:3:13: error: [K021] x-vis-color takes a colour #RRGGBB, not 'red'"},
      {"TruncatedLastLine", "inhook 3\nknit + ",
       "t.k:4:8: error: [K013] missing needle for 'knit'"},
      {"TruncatedNeedle", "xfer f1 b",
       "t.k:3:9: error: [K011] invalid needle 'b'; expected f, b, "
       "fs or bs followed by an integer"},
      {"TenMegabyteLine", long_token + "\n",
       "t.k:3:1: error: [K010] unknown operation '" + std::string(40, 'q') + "...'"},
  };
}

class MalformedTest : public ::testing::TestWithParam<Case> {};

TEST_P(MalformedTest, GetsTheDocumentedErrorOnTheRightLine) {
  const Case& c = GetParam();
  DiagnosticSink sink;
  const std::string text = std::string(kHead) + c.body;
  parse_string(text, "t.k", sink);
  ASSERT_TRUE(sink.has_errors()) << c.name;
  std::string first_error;
  for (const Diagnostic& d : sink.diagnostics()) {
    if (d.severity == Severity::Error) {
      first_error = format(d);
      break;
    }
  }
  EXPECT_EQ(first_error, c.expected);
}

INSTANTIATE_TEST_SUITE_P(Inputs, MalformedTest, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& param_info) {
                           return std::string(param_info.param.name);
                         });

TEST(MalformedTest, MalformedMagicLineIsAnError) {
  DiagnosticSink sink;
  parse_string(";!knitout-x\n;;Carriers: 1\n", "t.k", sink);
  ASSERT_EQ(sink.error_count(), 1u);
  EXPECT_EQ(format(sink.diagnostics()[0]),
            "t.k:1:11: error: [K005] malformed magic line: version 'x' is not a whole number");
}

TEST(MalformedTest, EmptyFileWarnsAndHoldsNothing) {
  DiagnosticSink sink;
  const Program p = parse_string("", "empty.k", sink);
  EXPECT_TRUE(p.instructions.empty());
  ASSERT_EQ(sink.diagnostics().size(), 1u);
  EXPECT_EQ(format(sink.diagnostics()[0]),
            "empty.k: warning: [K001] empty file: no knitout magic line ';!knitout-N'");
}

TEST(MalformedTest, CrlfLineEndingsWarnOnceAndReadTheSame) {
  DiagnosticSink crlf_sink;
  const Program crlf = parse_string(
      ";!knitout-2\r\n;;Carriers: 1 2\r\ninhook 1\r\nknit + f1 1 ;c\r\n", "t.k", crlf_sink);
  DiagnosticSink lf_sink;
  const Program lf =
      parse_string(";!knitout-2\n;;Carriers: 1 2\ninhook 1\nknit + f1 1 ;c\n", "t.k", lf_sink);
  EXPECT_EQ(crlf, lf);
  EXPECT_EQ(crlf.header("Carriers"), "1 2");
  ASSERT_EQ(crlf_sink.diagnostics().size(), 1u);
  EXPECT_EQ(format(crlf_sink.diagnostics()[0]),
            "t.k:1: warning: [K003] CRLF line ending; knitout lines end with LF (reported once per "
            "file)");
}

TEST(MalformedTest, TenMegabyteCommentLineIsReadWhole) {
  const std::string comment(10 * 1024 * 1024, 'c');
  DiagnosticSink sink;
  const Program p =
      parse_string(std::string(kHead) + ";" + comment + "\nknit + f1 3\n", "t.k", sink);
  EXPECT_FALSE(sink.has_errors());
  ASSERT_EQ(p.instructions.size(), 2u);
  EXPECT_EQ(p.comment(p.instructions[0]).size(), comment.size());
  EXPECT_EQ(p.instructions[1].line, 4u);
}

TEST(MalformedTest, ErrorLineIsSkippedAndTheRestIsRead) {
  DiagnosticSink sink;
  const Program p =
      parse_string(std::string(kHead) + "knit + f1 1\nxfer f1\nknit - f1 1\n", "t.k", sink);
  EXPECT_EQ(sink.error_count(), 1u);
  ASSERT_EQ(p.instructions.size(), 2u);
  EXPECT_EQ(p.instructions[1].line, 5u);
}

}  // namespace
}  // namespace knitout
