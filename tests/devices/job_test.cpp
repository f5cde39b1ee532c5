#include "devices/job.hpp"

#include <gtest/gtest.h>

#include "tests/devices/device_test_support.hpp"
#include "tests/test_support.hpp"

namespace devices {
namespace {

Bytes to_bytes(const std::string& s) {
  return Bytes(s.begin(), s.end());
}

std::string row_text(const Job& job, std::uint32_t i) {
  const auto r = job.row(i);
  return std::string(r.begin(), r.end());
}

TEST(JobTest, KnitoutRowsAreHeaderThenOnePerCarriagePass) {
  const std::string text =
      ";!knitout-2\n;;Carriers: 1 2 3\ninhook 3\ntuck - f2 3\ntuck - f1 3\nknit + f1 3\n"
      "xfer f1 b1\nknit + f2 3\nknit - f2 3\n; c\nknit - f1 3\nouthook 3\n";
  auto job = make_job("a.k", to_bytes(text));
  ASSERT_TRUE(job.ok()) << job.error().text();
  ASSERT_EQ(job.value().row_count(), 4u);
  EXPECT_EQ(row_text(job.value(), 0), ";!knitout-2\n;;Carriers: 1 2 3\n");
  EXPECT_EQ(row_text(job.value(), 1), "inhook 3\ntuck - f2 3\ntuck - f1 3\n");
  EXPECT_EQ(row_text(job.value(), 2), "knit + f1 3\nxfer f1 b1\nknit + f2 3\n");
  EXPECT_EQ(row_text(job.value(), 3), "knit - f2 3\n; c\nknit - f1 3\nouthook 3\n");
}

TEST(JobTest, RowsConcatenateToTheFile) {
  const Job job = test::make_sheet_job("s.k", 20, 30);
  EXPECT_EQ(job.row_count(), 32u);  // header, cast-on, 30 passes
  std::string joined;
  for (std::uint32_t i = 0; i < job.row_count(); ++i) joined += row_text(job, i);
  EXPECT_EQ(joined, std::string(job.bytes.begin(), job.bytes.end()));
  EXPECT_EQ(job.sha256, sha256(job.bytes));
}

TEST(JobTest, LongPassesAreCutBelowTheRowLimit) {
  const Job job = test::make_sheet_job("wide.k", 3000, 2);
  for (std::uint32_t i = 0; i < job.row_count(); ++i) {
    EXPECT_LE(job.row(i).size(), kMaxRowBytes);
    EXPECT_EQ(job.row(i).back(), '\n');
  }
  EXPECT_GT(job.row_count(), 4u);
}

TEST(JobTest, DatRowsAreHeaderThenOneRasterRowEach) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const auto path = shared / "corpus" / "dat-reference" / "gen-plain-20x10.dat";
  auto job = load_job(path);
  ASSERT_TRUE(job.ok()) << job.error().text();
  const Job& j = job.value();
  EXPECT_EQ(j.format, JobFormat::Dat);
  const unsigned height = (j.bytes[6] | (j.bytes[7] << 8)) + 1u;
  EXPECT_EQ(j.row_count(), height + 1);
  EXPECT_EQ(j.row(0).size(), 0x600u);
  const unsigned width = (j.bytes[4] | (j.bytes[5] << 8)) + 1u;
  for (std::uint32_t i = 1; i < j.row_count(); ++i) {
    unsigned sum = 0;
    for (std::size_t k = 1; k < j.row(i).size(); k += 2) sum += j.row(i)[k];
    EXPECT_EQ(sum, width) << "row " << i;
  }
}

TEST(JobTest, EveryReferenceDatSplitsIntoRows) {
  WEARKNIT_REQUIRE_SHARED(shared);
  int count = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(shared / "corpus" / "dat-reference")) {
    if (entry.path().extension() != ".dat") continue;
    auto job = load_job(entry.path());
    EXPECT_TRUE(job.ok()) << entry.path() << ": " << job.error().text();
    ++count;
  }
  EXPECT_GT(count, 10);
}

TEST(JobTest, RefusesATruncatedDatWithTheReason) {
  Bytes dat(0x600, 0);
  dat[4] = 9;  // width 10
  dat[6] = 1;  // height 2
  dat.insert(dat.end(), {0, 10, 0, 4});
  auto job = make_job("t.dat", dat);
  ASSERT_FALSE(job.ok());
  EXPECT_EQ(job.error().message,
            "[D043] truncated DAT: the data ends in row 1 of 2 (6 pixels missing)");
  dat.insert(dat.end(), {0, 7});
  auto over = make_job("t.dat", dat);
  ASSERT_FALSE(over.ok());
  EXPECT_EQ(over.error().message,
            "[D044] corrupt DAT: the run at byte 1540 (7 pixels of colour 0) crosses the end "
            "of row 1");
  dat.back() = 6;
  EXPECT_TRUE(make_job("t.dat", dat).ok());
  dat.insert(dat.end(), {5, 5});
  auto extra = make_job("t.dat", dat);
  ASSERT_FALSE(extra.ok());
  EXPECT_EQ(extra.error().message, "DAT has 2 bytes after its 2 raster rows");
}

TEST(JobTest, RefusesUnknownFormatsAndPathNames) {
  auto unknown = make_job("notes.txt", to_bytes("hello"));
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().message, "not a DAT (.dat) or knitout (.k) job: cannot tell its rows");
  EXPECT_FALSE(make_job("../x.k", to_bytes(";!knitout-2\n")).ok());
  EXPECT_FALSE(make_job(".hidden.k", to_bytes(";!knitout-2\n")).ok());
  EXPECT_TRUE(make_job("job", to_bytes(";!knitout-2\nknit + f1 1\n")).ok());  // by magic
}

TEST(JobTest, KnitoutSyntaxCheckNamesFileLineAndCode) {
  const std::string bad = ";!knitout-2\n;;Carriers: 1 2 3\nbogus 3\n";
  const std::string reason = check_knitout_syntax(
      "bad.k", std::span(reinterpret_cast<const std::uint8_t*>(bad.data()), bad.size()));
  EXPECT_EQ(reason.rfind("bad.k:3:", 0), 0u) << reason;
  EXPECT_NE(reason.find("error: [K"), std::string::npos) << reason;
  const std::string good = test::sheet_knitout(4, 2);
  EXPECT_EQ(
      check_knitout_syntax(
          "good.k", std::span(reinterpret_cast<const std::uint8_t*>(good.data()), good.size())),
      "");
}

}  // namespace
}  // namespace devices
