// Every knitout file of ../shared/corpus parses; the canonical form reads
// back to the same program and formatting it again changes nothing.
#include <gtest/gtest.h>

#include <map>

#include "knitout/parser.hpp"
#include "knitout/writer.hpp"
#include "tests/test_support.hpp"

namespace knitout {
namespace {

// Corpus files the reference rejects for a reason that is knitout syntax:
// the line and code the parser must report. Every other file, including the
// ones the reference rejects for semantic or DAT-specific reasons, is
// syntactically valid knitout.
const std::map<std::string, std::pair<std::uint32_t, std::string>>& syntax_rejects() {
  static const std::map<std::string, std::pair<std::uint32_t, std::string>> kRejects = {
      {"neg-bad-needle.k", {37, "K011"}}, {"neg-bad-presser.k", {5, "K021"}},
      {"neg-bad-speed.k", {5, "K021"}},   {"neg-drop-with-carrier.k", {37, "K014"}},
      {"neg-unknown-op.k", {37, "K010"}},
  };
  return kRejects;
}

TEST(CorpusTest, EveryFileParsesAndFormatsToAFixedPoint) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const auto dir = shared / "corpus" / "knitout";
  std::size_t files = 0;
  std::size_t instructions = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".k") continue;
    ++files;
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    DiagnosticSink sink;
    const Program program = parse_file(entry.path().string(), sink);
    const auto reject = syntax_rejects().find(name);
    if (reject != syntax_rejects().end()) {
      ASSERT_TRUE(sink.has_errors());
      const Diagnostic& first = sink.diagnostics().back();
      EXPECT_EQ(first.line, reject->second.first);
      EXPECT_EQ(first.code, reject->second.second);
      continue;
    }
    ASSERT_FALSE(sink.has_errors()) << format(sink.diagnostics().front());
    instructions += program.instructions.size();
    const std::string once = write_to_string(program);
    DiagnosticSink again_sink;
    const Program again = parse_string(once, name, again_sink);
    EXPECT_FALSE(again_sink.has_errors());
    EXPECT_TRUE(again == program) << "canonical form reads back differently";
    EXPECT_EQ(write_to_string(again), once) << "fmt is not idempotent";
  }
  EXPECT_EQ(files, 123u) << "the corpus README lists 123 files";
  EXPECT_GT(instructions, 700000u);
}

TEST(CorpusTest, FmtVerbIsIdempotentOnACorpusFile) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const auto tmp = wearknit::test::make_temp_dir("wearknit-fmt");
  const auto input = shared / "corpus" / "knitout" / "lv-crlf.k";
  const auto first = wearknit::test::run_wearknit("fmt '" + input.string() + "' -o '" +
                                                  (tmp / "a.k").string() + "'");
  EXPECT_EQ(first.exit_code, 0) << first.err;
  EXPECT_NE(first.err.find("[K003] CRLF line ending"), std::string::npos);
  const auto second = wearknit::test::run_wearknit("fmt '" + (tmp / "a.k").string() + "'");
  EXPECT_EQ(second.exit_code, 0);
  EXPECT_EQ(second.out, wearknit::test::read_file(tmp / "a.k"));
  const auto check = wearknit::test::run_wearknit("fmt --check '" + (tmp / "a.k").string() + "'");
  EXPECT_EQ(check.exit_code, 0) << check.err;
  std::filesystem::remove_all(tmp);
}

}  // namespace
}  // namespace knitout
