// The DAT backend against the reference outputs of ../shared/corpus: every
// file knitout-to-dat.js accepts converts to the same bytes, every file it
// rejects is rejected with an error at a line of the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "backends/dat/format.hpp"
#include "backends/dat/passes.hpp"
#include "backends/dat/raster.hpp"
#include "tests/test_support.hpp"

namespace dat {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> bytes_of(const std::string& text) {
  return {text.begin(), text.end()};
}

// Where two DATs first differ: header byte, palette byte, or raster row and
// column (decoded, so a run-length difference is located in the picture).
std::string first_difference(const std::vector<std::uint8_t>& ours,
                             const std::vector<std::uint8_t>& reference) {
  const std::size_t common = std::min(ours.size(), reference.size());
  std::size_t i = 0;
  while (i < common && ours[i] == reference[i]) ++i;
  if (i < kPaletteOffset) return "header byte " + std::to_string(i);
  if (i < kDataOffset) return "palette byte " + std::to_string(i - kPaletteOffset);
  knitout::DiagnosticSink sink;
  const Raster a = decode(ours, "ours", sink);
  const Raster b = decode(reference, "reference", sink);
  if (sink.has_errors()) return "run-length data at byte " + std::to_string(i) + " (undecodable)";
  if (a.width != b.width || a.height != b.height) {
    return "raster size " + std::to_string(a.width) + "x" + std::to_string(a.height) +
           " vs reference " + std::to_string(b.width) + "x" + std::to_string(b.height);
  }
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      if (a.at(x, y) != b.at(x, y)) {
        return "row " + std::to_string(y) + " column " + std::to_string(x) + ": colour " +
               std::to_string(a.at(x, y)) + " vs reference " + std::to_string(b.at(x, y));
      }
    }
  }
  return "run-length encoding at byte " + std::to_string(i) + " (same pixels)";
}

struct Outcome {
  std::optional<std::vector<std::uint8_t>> bytes;
  knitout::DiagnosticSink sink;
};

void convert(const fs::path& path, Outcome& outcome) {
  std::ifstream in(path, std::ios::binary);
  ASSERT_TRUE(in) << path;
  auto passes = form_passes(in, path.filename().string(), outcome.sink);
  if (passes) outcome.bytes = write_dat(*passes, outcome.sink);
}

TEST(DatCorpusTest, AcceptedFilesMatchTheReferenceByteForByte) {
  WEARKNIT_REQUIRE_SHARED(shared);
  int compared = 0;
  for (const auto& entry : fs::directory_iterator(shared / "corpus" / "dat-reference")) {
    const fs::path reference = entry.path();
    const fs::path knitout = shared / "corpus" / "knitout" / (reference.stem().string() + ".k");
    SCOPED_TRACE(knitout.filename().string());
    Outcome outcome;
    convert(knitout, outcome);
    ASSERT_FALSE(outcome.sink.has_errors()) << knitout::format(outcome.sink.diagnostics().front());
    ASSERT_TRUE(outcome.bytes.has_value());
    const auto expected = bytes_of(wearknit::test::read_file(reference));
    EXPECT_TRUE(*outcome.bytes == expected)
        << "first difference: " << first_difference(*outcome.bytes, expected);
    ++compared;
  }
  EXPECT_EQ(compared, 68);
}

TEST(DatCorpusTest, RejectedFilesAreRejectedAtALine) {
  WEARKNIT_REQUIRE_SHARED(shared);
  int rejected = 0;
  for (const auto& entry : fs::directory_iterator(shared / "corpus" / "knitout")) {
    const fs::path knitout = entry.path();
    if (fs::exists(shared / "corpus" / "dat-reference" / (knitout.stem().string() + ".dat"))) {
      continue;
    }
    SCOPED_TRACE(knitout.filename().string());
    Outcome outcome;
    convert(knitout, outcome);
    EXPECT_FALSE(outcome.bytes.has_value());
    ASSERT_TRUE(outcome.sink.has_errors());
    const knitout::Diagnostic* first = nullptr;
    for (const auto& d : outcome.sink.diagnostics()) {
      if (d.severity == knitout::Severity::Error) {
        first = &d;
        break;
      }
    }
    ASSERT_NE(first, nullptr);
    EXPECT_GT(first->line, 0u) << knitout::format(*first);
    EXPECT_EQ(first->source, knitout.filename().string());
    ++rejected;
  }
  EXPECT_EQ(rejected, 55);
}

// The failure message of the byte comparison locates a difference in the
// picture, not only in the bytes.
TEST(DatCorpusTest, MismatchMessageNamesTheFirstDifferingRowAndColumn) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const auto reference = bytes_of(
      wearknit::test::read_file(shared / "corpus" / "dat-reference" / "gen-plain-20x10.dat"));
  knitout::DiagnosticSink sink;
  Raster raster = decode(reference, "reference", sink);
  ASSERT_FALSE(sink.has_errors());
  const std::uint8_t was = raster.at(60, 9);
  raster.pixels[static_cast<std::size_t>(9 * raster.width + 60)] = 11;
  EXPECT_EQ(first_difference(encode(raster), reference),
            "row 9 column 60: colour 11 vs reference " + std::to_string(was));
  auto header = reference;
  header[4] ^= 1;
  EXPECT_EQ(first_difference(header, reference), "header byte 4");
}

// The reasons for a few rejections, checked by code and line.
TEST(DatCorpusTest, RejectionsNameTheCodeAndLine) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const std::vector<std::tuple<std::string, std::string, std::uint32_t>> cases = {
      {"neg-bad-magic.k", "D001", 1},          {"neg-no-carriers-header.k", "D002", 1},
      {"neg-carriers-8.k", "D003", 4},         {"neg-bad-gauge.k", "D004", 3},
      {"neg-bad-position.k", "D006", 4},       {"neg-double-in.k", "D011", 6},
      {"neg-inactive-carrier.k", "D014", 5},   {"neg-inhook-hook-busy.k", "D013", 17},
      {"neg-miss-no-carrier.k", "D024", 37},   {"neg-out-inactive.k", "D016", 38},
      {"neg-out-unused.k", "D016", 6},         {"neg-rack-half.k", "D020", 5},
      {"neg-releasehook-empty.k", "D015", 37}, {"neg-stitch-not-in-table.k", "D023", 5},
      {"neg-carriers-left-in.k", "D018", 5},   {"neg-unknown-op.k", "K010", 37},
      {"neg-drop-with-carrier.k", "K014", 37},
  };
  for (const auto& [name, code, line] : cases) {
    SCOPED_TRACE(name);
    Outcome outcome;
    convert(shared / "corpus" / "knitout" / name, outcome);
    ASSERT_TRUE(outcome.sink.has_errors());
    const auto& d = outcome.sink.diagnostics();
    auto first = std::find_if(d.begin(), d.end(), [](const knitout::Diagnostic& x) {
      return x.severity == knitout::Severity::Error;
    });
    EXPECT_EQ(first->code, code) << knitout::format(*first);
    EXPECT_EQ(first->line, line) << knitout::format(*first);
  }
}

}  // namespace
}  // namespace dat
