// `wearknit dat` and `wearknit dat-info` end to end.
#include <gtest/gtest.h>

#include <filesystem>

#include "tests/test_support.hpp"

namespace wearknit::cli {
namespace {

namespace fs = std::filesystem;
using test::read_file;
using test::run_wearknit;
using test::write_file;

const std::string kProgram =
    ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\ninhook 3\nknit + f1 3\nknit + f2 3\n"
    "releasehook 3\nknit - f2 3\nknit - f1 3\nxfer f1 b1\nouthook 3\n";

class DatCliTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::make_temp_dir("dat_cli"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

TEST_F(DatCliTest, WritesADatAndVerifiesIt) {
  write_file(path("a.k"), kProgram);
  const auto result = run_wearknit("dat '" + path("a.k") + "' -o '" + path("a.dat") + "' --verify");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.err, "");
  const std::string bytes = read_file(path("a.dat"));
  ASSERT_GT(bytes.size(), 0x600u);
  EXPECT_EQ(static_cast<unsigned char>(bytes[8]) | (static_cast<unsigned char>(bytes[9]) << 8),
            1000);
}

TEST_F(DatCliTest, RejectedProgramLeavesNothingBehind) {
  write_file(path("bad.k"), ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\nknit + f1 3\n");
  const auto result = run_wearknit("dat '" + path("bad.k") + "' -o '" + path("bad.dat") + "'");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err, path("bad.k") +
                            ":3: error: [D014] carrier '3' is used but not in (bring it in with "
                            "'in' or 'inhook')\n");
  EXPECT_FALSE(fs::exists(path("bad.dat")));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(DatCliTest, DiagnosticsAsJson) {
  write_file(path("bad.k"), ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\nmiss + f1\n");
  const auto result =
      run_wearknit("dat '" + path("bad.k") + "' -o '" + path("bad.dat") + "' --json");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.out.find("\"code\": \"D024\""), std::string::npos) << result.out;
}

TEST_F(DatCliTest, OtherMachinesAreAUsageError) {
  write_file(path("a.k"), kProgram);
  const auto result =
      run_wearknit("dat '" + path("a.k") + "' -o '" + path("a.dat") + "' --machine kniterate");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err,
            "wearknit dat: machine 'kniterate' has no DAT profile; profiles: swg091n2\n");
}

TEST_F(DatCliTest, ReadsKnitoutFromStdin) {
  const auto result = run_wearknit("dat - -o '" + path("s.dat") + "'", kProgram);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  write_file(path("a.k"), kProgram);
  ASSERT_EQ(run_wearknit("dat '" + path("a.k") + "' -o '" + path("a.dat") + "'").exit_code, 0);
  EXPECT_EQ(read_file(path("s.dat")), read_file(path("a.dat")));
}

TEST_F(DatCliTest, UnwritableOutputIsAnIoError) {
  write_file(path("a.k"), kProgram);
  const auto result =
      run_wearknit("dat '" + path("a.k") + "' -o '" + path("no/such/dir/a.dat") + "'");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("wearknit dat: "), std::string::npos) << result.err;
  EXPECT_FALSE(fs::exists(path("no")));
}

TEST_F(DatCliTest, DatInfoPrintsSizePositionAndPasses) {
  write_file(path("a.k"), kProgram);
  ASSERT_EQ(run_wearknit("dat '" + path("a.k") + "' -o '" + path("a.dat") + "'").exit_code, 0);
  const auto result = run_wearknit("dat-info '" + path("a.dat") + "' --passes");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  // 2 slots: 112 columns; 6 passes (knit, empty, release, knit, xfer, out):
  // 25 rows. Centred on 540 needles: (540 - 2) / 2 = 269.
  EXPECT_NE(result.out.find(": 112 x 25 raster, 2 needle slots, 6 passes, position 269\n"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("pass 1 (row 8): + carriers 3 racking 0 stitch 5 speed 0 R5=2 "
                            "R10=3 R15=10: knit-front x2 (slots 0-1)\n"),
            std::string::npos)
      << result.out;
  EXPECT_NE(result.out.find("pass 5 (row 12): none carriers - racking 0 stitch 0 speed 0 R5=1: "
                            "xfer-to-back x1 (slot 0)\n"),
            std::string::npos)
      << result.out;
}

TEST_F(DatCliTest, DatInfoDrawsAPng) {
  write_file(path("a.k"), kProgram);
  ASSERT_EQ(run_wearknit("dat '" + path("a.k") + "' -o '" + path("a.dat") + "'").exit_code, 0);
  const auto result =
      run_wearknit("dat-info '" + path("a.dat") + "' --png '" + path("a.png") + "' --scale 3");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  const std::string png = read_file(path("a.png"));
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_EQ(static_cast<unsigned char>(png[18]) * 256 + static_cast<unsigned char>(png[19]),
            112 * 3);
}

TEST_F(DatCliTest, DatInfoRejectsACorruptFile) {
  write_file(path("t.dat"), std::string(700, '\0'));
  const auto result = run_wearknit("dat-info '" + path("t.dat") + "'");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err, path("t.dat") +
                            ": error: [D040] truncated DAT: 700 bytes, but header and palette "
                            "alone take 1536\n");
}

TEST_F(DatCliTest, DatInfoOnAMissingFileIsAnIoError) {
  const auto result = run_wearknit("dat-info '" + path("none.dat") + "'");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("[D049] cannot open file"), std::string::npos);
}

}  // namespace
}  // namespace wearknit::cli

// simulate --stats reports the passes this backend forms: as many as the
// reference DAT of the same program holds.
TEST(DatSimulateTest, SimulateReportsTheCarriagePassesOfTheReferenceDat) {
  WEARKNIT_REQUIRE_SHARED(shared);
  for (const char* name : {"kex-rectangle", "swg-rib2x2", "mil-interlock", "gen-features"}) {
    SCOPED_TRACE(name);
    const auto info = wearknit::test::run_wearknit(
        "dat-info '" +
        (shared / "corpus" / "dat-reference" / (std::string(name) + ".dat")).string() + "'");
    ASSERT_EQ(info.exit_code, 0) << info.err;
    const std::size_t passes_at = info.out.find(" passes");
    ASSERT_NE(passes_at, std::string::npos) << info.out;
    const std::size_t number_at = info.out.rfind(' ', passes_at - 1) + 1;
    const std::string reference_passes = info.out.substr(number_at, passes_at - number_at);

    const auto simulate = wearknit::test::run_wearknit(
        "simulate '" + (shared / "corpus" / "knitout" / (std::string(name) + ".k")).string() + "'");
    EXPECT_EQ(simulate.exit_code, 0) << simulate.err;
    EXPECT_NE(simulate.out.find("  DAT passes           " + reference_passes + "\n"),
              std::string::npos)
        << simulate.out;
    EXPECT_NE(simulate.out.find("  carriage passes: " + reference_passes + " ("), std::string::npos)
        << simulate.out;
  }
}

TEST(DatSimulateTest, SimulateSaysWhyAProgramHasNoPasses) {
  const auto result = wearknit::test::run_wearknit(
      "simulate -",
      ";!knitout-2\n;;Carriers: 1 2 3\ninhook 3\ntuck + f1 3\nreleasehook 3\nouthook 3\n");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.out.find("  carriage passes: none formed (the DAT backend refuses the program: "
                            "<stdin>:2: error: [D003]"),
            std::string::npos)
      << result.out;
}
