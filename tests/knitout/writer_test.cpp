#include "knitout/writer.hpp"

#include <gtest/gtest.h>

#include <random>

#include "knitout/parser.hpp"

namespace knitout {
namespace {

Program parse_clean(const std::string& text) {
  DiagnosticSink sink;
  Program program = parse_string(text, "t.k", sink);
  EXPECT_FALSE(sink.has_errors()) << format(sink.diagnostics().front()) << "\n" << text;
  return program;
}

TEST(WriterTest, WritesTheCanonicalForm) {
  const Program p = parse_clean(
      ";!knitout-2\n;;Carriers: 1 2 3\n;;Gauge: 15\n  knit\t+  f10 3   ;  hi \n"
      "rack 0.250\nrack -1.0\nstitch 05 6.50\nx-presser-mode  on\nx-foo   a  b\n;note\n"
      "split - b-3 fs2 1 2\n\n\npause;\n");
  EXPECT_EQ(write_to_string(p),
            ";!knitout-2\n;;Carriers: 1 2 3\n;;Gauge: 15\nknit + f10 3 ;  hi \nrack 0.25\n"
            "rack -1\nstitch 5 6.5\nx-presser-mode on\nx-foo a b\n;note\n"
            "split - b-3 fs2 1 2\npause ;\n");
}

TEST(WriterTest, FormatsNumbersShortestAndWithoutNegativeZero) {
  EXPECT_EQ(format_number(0.25), "0.25");
  EXPECT_EQ(format_number(-0.75), "-0.75");
  EXPECT_EQ(format_number(-0.0), "0");
  EXPECT_EQ(format_number(3), "3");
  EXPECT_EQ(format_number(0.1), "0.1");
}

TEST(WriterTest, CommentRightAfterHeadersStaysAComment) {
  const Program p = parse_clean(";!knitout-2\n;;Carriers: 1\n ;;Looks: like a header\nin 1\n");
  ASSERT_EQ(p.headers.size(), 1u);
  const std::string text = write_to_string(p);
  const Program again = parse_clean(text);
  EXPECT_EQ(again, p);
  EXPECT_EQ(write_to_string(again), text);
}

TEST(WriterTest, ProgramsDifferingInOneCarrierAreNotEqual) {
  const Program a = parse_clean(";!knitout-2\n;;Carriers: 1 2\nknit + f1 1\n");
  const Program b = parse_clean(";!knitout-2\n;;Carriers: 1 2\nknit + f1 2\n");
  const Program c = parse_clean(";!knitout-2\n;;Carriers: 1 2\nknit + f1 1 ;x\n");
  EXPECT_FALSE(a == b);
  EXPECT_FALSE(a == c);
}

// A random program drawing on every operation, extension and token shape.
std::string random_program(std::mt19937& rng) {
  auto pick = [&](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  const char* beds[] = {"f", "b", "fs", "bs"};
  const char* carriers[] = {"1", "2", "10", "A", "L3", "x"};
  auto needle = [&] { return std::string(beds[pick(4)]) + std::to_string(pick(41) - 20); };
  auto carrier_list = [&](int min) {
    std::string out;
    const int count = min + pick(3);
    int start = pick(6);
    for (int i = 0; i < count; ++i) out += std::string(" ") + carriers[(start + i) % 6];
    return out;
  };
  auto number = [&] {
    const double values[] = {0, 1, -1, 0.25, -0.75, 2.5, 8, -8.25, 1e-3, 123456.5};
    return format_number(values[pick(10)]);
  };
  std::string text = ";!knitout-" + std::to_string(1 + pick(2)) + "\n";
  if (pick(4) != 0) text += ";;Carriers: 1 2 10 A L3 x\n";
  for (int i = pick(3); i > 0; --i) text += ";;Key" + std::to_string(i) + ": v " + number() + "\n";
  const int lines = 1 + pick(60);
  for (int i = 0; i < lines; ++i) {
    std::string line;
    const char dir = pick(2) ? '+' : '-';
    switch (pick(19)) {
      case 0:
        line = "in" + carrier_list(1);
        break;
      case 1:
        line = "inhook" + carrier_list(1);
        break;
      case 2:
        line = "releasehook" + carrier_list(1);
        break;
      case 3:
        line = "out" + carrier_list(1);
        break;
      case 4:
        line = "outhook" + carrier_list(1);
        break;
      case 5:
        line = "stitch " + number() + " " + number();
        break;
      case 6:
        line = "rack " + number();
        break;
      case 7:
        line = std::string("knit ") + dir + " " + needle() + carrier_list(0);
        break;
      case 8:
        line = std::string("tuck ") + dir + " " + needle() + carrier_list(0);
        break;
      case 9:
        line = std::string("split ") + dir + " " + needle() + " " + needle() + carrier_list(0);
        break;
      case 10:
        line = "drop " + needle();
        break;
      case 11:
        line = "amiss " + needle();
        break;
      case 12:
        line = "xfer " + needle() + " " + needle();
        break;
      case 13:
        line = std::string("miss ") + dir + " " + needle() + carrier_list(1);
        break;
      case 14:
        line = "pause";
        break;
      case 15:
        line = "x-stitch-number " + std::to_string(pick(100));
        break;
      case 16:
        line = std::string("x-presser-mode ") + (pick(2) ? "auto" : "off");
        break;
      case 17:
        line = "x-vis-color #a0b1c2" + carrier_list(1);
        break;
      case 18:
        line = "x-custom-thing " + number() + " q";
        break;
    }
    if (pick(5) == 0) line += ";c" + std::to_string(pick(9));
    if (pick(20) == 0) line = ";" + line;
    text += line + "\n";
  }
  return text;
}

TEST(WriterTest, ParseOfWriteIsTheProgramForRandomPrograms) {
  std::mt19937 rng(20261122);
  for (int round = 0; round < 500; ++round) {
    const std::string source = random_program(rng);
    DiagnosticSink sink;
    const Program p = parse_string(source, "random.k", sink);
    ASSERT_FALSE(sink.has_errors()) << format(sink.diagnostics().front()) << "\n" << source;
    const std::string once = write_to_string(p);
    const Program again = parse_clean(once);
    ASSERT_EQ(again, p) << "round " << round << "\n" << source << "\n---\n" << once;
    ASSERT_EQ(write_to_string(again), once) << "round " << round;
  }
}

}  // namespace
}  // namespace knitout
