// The DAT byte format: run-length encoding with its 255-run quirk, the
// header, and a decoder that never crashes on truncated or corrupt input.
#include <gtest/gtest.h>

#include <random>
#include <sstream>

#include "backends/dat/format.hpp"
#include "backends/dat/passes.hpp"
#include "backends/dat/png.hpp"
#include "backends/dat/raster.hpp"
#include "backends/dat/reader.hpp"
#include "tests/test_support.hpp"

namespace dat {
namespace {

std::vector<std::uint8_t> rle(const std::vector<std::uint8_t>& row) {
  std::vector<std::uint8_t> out;
  encode_row(row, out);
  return out;
}

TEST(DatFormatTest, RunsAreCutAt255) {
  std::vector<std::uint8_t> row(300, 7);
  row.push_back(0);
  row.push_back(0);
  EXPECT_EQ(rle(row), (std::vector<std::uint8_t>{7, 255, 7, 45, 0, 2}));
}

TEST(DatFormatTest, RunOfExactly255ThenAnotherColourEmitsAZeroLengthPair) {
  std::vector<std::uint8_t> row(255, 7);
  row.insert(row.end(), 3, 0);
  EXPECT_EQ(rle(row), (std::vector<std::uint8_t>{7, 255, 7, 0, 0, 3}));
  std::vector<std::uint8_t> twice(510, 9);
  twice.insert(twice.end(), 2, 0);
  EXPECT_EQ(rle(twice), (std::vector<std::uint8_t>{9, 255, 9, 255, 9, 0, 0, 2}));
}

TEST(DatFormatTest, RowEndingExactlyOnA255RunHasNoZeroPair) {
  std::vector<std::uint8_t> row(510, 0);
  EXPECT_EQ(rle(row), (std::vector<std::uint8_t>{0, 255, 0, 255}));
}

TEST(DatFormatTest, HeaderHoldsSizeMagicAndPalette) {
  const auto prefix = file_prefix(130, 25);
  ASSERT_EQ(prefix.size(), kDataOffset);
  EXPECT_EQ(prefix[4] | (prefix[5] << 8), 129);
  EXPECT_EQ(prefix[6] | (prefix[7] << 8), 24);
  EXPECT_EQ(prefix[8] | (prefix[9] << 8), 1000);
  EXPECT_EQ(prefix[16] | (prefix[17] << 8), 1000);
  EXPECT_EQ(prefix[0x200], kPalette[0]);
  EXPECT_EQ(prefix[0x4FF], kPalette[767]);
  EXPECT_EQ(prefix[0x500], 0);
}

Raster sample_raster() {
  Raster raster;
  raster.width = 300;
  raster.height = 4;
  raster.palette = kPalette;
  raster.pixels.assign(1200, 0);
  for (int x = 0; x < 255; ++x) raster.pixels[static_cast<std::size_t>(300 + x)] = 51;
  raster.pixels[650] = 13;
  return raster;
}

TEST(DatFormatTest, EncodeDecodeRoundTrip) {
  const Raster raster = sample_raster();
  knitout::DiagnosticSink sink;
  const Raster back = decode(encode(raster), "x.dat", sink);
  EXPECT_FALSE(sink.has_errors());
  EXPECT_EQ(back.width, 300);
  EXPECT_EQ(back.height, 4);
  EXPECT_EQ(back.pixels, raster.pixels);
  EXPECT_EQ(back.palette, kPalette);
}

std::string first_error(const knitout::DiagnosticSink& sink) {
  for (const auto& d : sink.diagnostics()) {
    if (d.severity == knitout::Severity::Error) return knitout::format(d);
  }
  return "";
}

TEST(DatFormatTest, ShortFileIsTruncated) {
  knitout::DiagnosticSink sink;
  const std::vector<std::uint8_t> bytes(100, 0);
  decode(bytes, "t.dat", sink);
  EXPECT_EQ(first_error(sink),
            "t.dat: error: [D040] truncated DAT: 100 bytes, but header and palette alone take "
            "1536");
}

TEST(DatFormatTest, InvertedDimensionsAreRejected) {
  auto bytes = encode(sample_raster());
  bytes[0] = 0xFF;  // x-min above x-max
  bytes[1] = 0x01;
  knitout::DiagnosticSink sink;
  decode(bytes, "t.dat", sink);
  EXPECT_EQ(first_error(sink),
            "t.dat: error: [D041] bad DAT header: x 511..299, y 0..3 is an empty raster");
}

TEST(DatFormatTest, OddDataIsTruncated) {
  auto bytes = encode(sample_raster());
  bytes.pop_back();
  knitout::DiagnosticSink sink;
  decode(bytes, "t.dat", sink);
  EXPECT_NE(first_error(sink).find("[D043] truncated DAT: run-length data has an odd number"),
            std::string::npos);
}

TEST(DatFormatTest, MissingRowsAreTruncated) {
  auto bytes = encode(sample_raster());
  bytes.resize(bytes.size() - 4);
  knitout::DiagnosticSink sink;
  decode(bytes, "t.dat", sink);
  EXPECT_NE(first_error(sink).find("[D043] truncated DAT: the data ends in row 3 of 4"),
            std::string::npos)
      << first_error(sink);
}

TEST(DatFormatTest, RunAcrossARowEndIsCorrupt) {
  auto bytes = encode(sample_raster());
  // The first row is 0x255, 0x45; make the second run 46 long.
  ASSERT_EQ(bytes[kDataOffset + 3], 45);
  bytes[kDataOffset + 3] = 46;
  knitout::DiagnosticSink sink;
  decode(bytes, "t.dat", sink);
  EXPECT_EQ(first_error(sink),
            "t.dat: error: [D044] corrupt DAT: the run at byte 1538 (46 pixels of colour 0) "
            "crosses the end of row 0");
}

TEST(DatFormatTest, ExtraBytesAfterTheLastRowAreAWarning) {
  auto bytes = encode(sample_raster());
  bytes.push_back(5);
  bytes.push_back(5);
  knitout::DiagnosticSink sink;
  const Raster raster = decode(bytes, "t.dat", sink);
  EXPECT_FALSE(sink.has_errors());
  EXPECT_EQ(raster.height, 4);
  ASSERT_EQ(sink.diagnostics().size(), 1u);
  EXPECT_EQ(sink.diagnostics()[0].code, "D045");
}

TEST(DatFormatTest, ScanRunsFindsEachRowWithItsZeroLengthPairs) {
  // A 300-pixel row of one colour is (c, 255) (c, 45); a 255-pixel run
  // followed by another colour adds a (c, 0) pair that stays with its row.
  std::vector<std::uint8_t> bytes = file_prefix(300, 2);
  bytes.insert(bytes.end(), {7, 255, 7, 45});
  bytes.insert(bytes.end(), {7, 255, 7, 0, 8, 45, 8, 0});
  knitout::DiagnosticSink sink;
  const std::optional<RunRows> rows = scan_runs(bytes, "t.dat", sink);
  ASSERT_TRUE(rows.has_value());
  EXPECT_TRUE(sink.diagnostics().empty());
  EXPECT_EQ(rows->width, 300);
  EXPECT_EQ(rows->height, 2);
  EXPECT_EQ(rows->row_offsets,
            (std::vector<std::size_t>{kDataOffset, kDataOffset + 4, kDataOffset + 4 + 8}));
}

TEST(DatFormatTest, ScanRunsRejectsWhatDecodeRejects) {
  std::vector<std::uint8_t> bytes = file_prefix(10, 2);
  bytes.insert(bytes.end(), {0, 10, 0, 4});
  knitout::DiagnosticSink sink;
  EXPECT_FALSE(scan_runs(bytes, "t.dat", sink).has_value());
  EXPECT_EQ(first_error(sink),
            "t.dat: error: [D043] truncated DAT: the data ends in row 1 of 2 (6 pixels missing)");
}

TEST(DatFormatTest, RasterTheDataCannotFillIsRejectedBeforeAllocating) {
  auto bytes = file_prefix(4096, 65536);
  bytes.push_back(0);
  bytes.push_back(255);
  knitout::DiagnosticSink sink;
  decode(bytes, "t.dat", sink);
  EXPECT_EQ(first_error(sink),
            "t.dat: error: [D043] truncated DAT: 1 run-length pairs cannot fill a 4096 x 65536 "
            "raster");
}

// A file whose runs really do fill a 65536 x 65536 raster (34 MB of pairs
// for 4 GiB of pixels) is refused by its declared size, before the pairs
// are walked or a pixel is allocated.
TEST(DatFormatTest, RasterBeyondTheLimitIsRefusedByItsDeclaredSize) {
  auto bytes = file_prefix(65536, 65536);
  const std::size_t pairs_per_row = 65536 / 255 + 1;
  for (std::size_t i = 0; i + 1 < pairs_per_row; ++i) bytes.insert(bytes.end(), {1, 255});
  bytes.insert(bytes.end(), {1, static_cast<std::uint8_t>(65536 % 255)});
  knitout::DiagnosticSink sink;
  EXPECT_FALSE(scan_runs(bytes, "t.dat", sink).has_value());
  EXPECT_EQ(first_error(sink),
            "t.dat: error: [D047] DAT raster too large: the header declares 65536 x 65536 pixels, "
            "more than the 268435456 this reader takes (no machine bed needs them)");
  EXPECT_EQ(declared_size(bytes), std::optional(std::pair(65536, 65536)));
}

TEST(DatFormatTest, RasterAtTheLimitIsRead) {
  const int width = 4096;
  const int height = static_cast<int>(kMaxRasterPixels / width);
  auto bytes = file_prefix(width, height);
  std::vector<std::uint8_t> row;
  for (int i = 0; i < width / 256; ++i) row.insert(row.end(), {1, 255, 2, 1});
  for (int y = 0; y < height; ++y) bytes.insert(bytes.end(), row.begin(), row.end());
  knitout::DiagnosticSink sink;
  const std::optional<RunRows> rows = scan_runs(bytes, "t.dat", sink);
  ASSERT_TRUE(rows.has_value()) << first_error(sink);
  EXPECT_EQ(rows->height, height);
}

// Everything dat-info does with a file: decode, read the layout, describe
// it, draw it. None of it may crash or read out of bounds, whatever the bytes.
void read_everything(const std::vector<std::uint8_t>& bytes) {
  knitout::DiagnosticSink sink;
  const Raster raster = decode(bytes, "fuzz.dat", sink);
  if (sink.has_errors()) {
    EXPECT_EQ(raster.width, 0);
    return;
  }
  if (auto layout = read_layout(raster, "fuzz.dat", sink)) {
    for (const DecodedPass& pass : layout->passes) {
      (void)carrier_code_text(pass.carriers());
      for (const auto& op : pass.ops) (void)colour_name(op.second);
    }
  }
  if (static_cast<long long>(raster.width) * raster.height < 2'000'000) {
    std::ostringstream png;
    (void)write_png(png, raster, 1);
  }
}

std::vector<std::uint8_t> small_dat() {
  knitout::DiagnosticSink sink;
  auto passes =
      form_passes(knitout::parse_string(";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\ninhook 3\n"
                                        "knit + f1 3\nknit + f2 3\nreleasehook 3\nknit - f2 3\n"
                                        "xfer f1 b1\nrack 1\nxfer b1 f2\nrack 0\nknit - f1 3\n"
                                        "outhook 3\n",
                                        "small.k", sink),
                  "small.k", sink);
  EXPECT_TRUE(passes.has_value());
  auto bytes = write_dat(*passes, sink);
  EXPECT_TRUE(bytes.has_value());
  return *bytes;
}

TEST(DatFormatTest, TruncatedFilesNeverCrashTheReader) {
  const auto bytes = small_dat();
  for (std::size_t length = 0; length < bytes.size(); ++length) {
    SCOPED_TRACE(length);
    read_everything(std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + length));
  }
}

TEST(DatFormatTest, RandomlyCorruptedFilesNeverCrashTheReader) {
  const auto original = small_dat();
  std::mt19937 random(20261122);  // fixed seed: the same cases every run
  std::uniform_int_distribution<std::size_t> where(0, original.size() - 1);
  std::uniform_int_distribution<int> value(0, 255);
  std::uniform_int_distribution<int> flips(1, 8);
  for (int trial = 0; trial < 2000; ++trial) {
    auto bytes = original;
    const int count = flips(random);
    for (int k = 0; k < count; ++k) {
      // Corrupt the header and data more often than the palette, which
      // any byte value is valid for.
      std::size_t at = where(random);
      if (trial % 2 == 0)
        at = trial % 4 == 0 ? at % 16 : kDataOffset + at % (bytes.size() - kDataOffset);
      bytes[at] = static_cast<std::uint8_t>(value(random));
    }
    if (trial % 7 == 0) bytes.resize(where(random));
    SCOPED_TRACE(trial);
    read_everything(bytes);
  }
}

TEST(DatFormatTest, WrittenPngIsAPaletteImageOfTheScaledRaster) {
  const Raster raster = sample_raster();
  std::ostringstream out;
  ASSERT_EQ(write_png(out, raster, 2), "");
  const std::string png = out.str();
  ASSERT_GT(png.size(), 33u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  auto u32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) |
           (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(u32(16), 600u);
  EXPECT_EQ(u32(20), 8u);
  EXPECT_EQ(png[25], 3);  // colour type: palette
  EXPECT_NE(png.find("PLTE"), std::string::npos);
}

TEST(DatFormatTest, PngRefusesAbsurdScale) {
  std::ostringstream out;
  EXPECT_EQ(write_png(out, sample_raster(), 0), "PNG scale must be 1..64, not 0");
}

}  // namespace
}  // namespace dat
