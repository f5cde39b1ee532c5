// `wearknit validate` and `wearknit simulate` end to end.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "knitout/generate.hpp"
#include "tests/test_support.hpp"

namespace wearknit::cli {
namespace {

using test::read_file;
using test::run_wearknit;
using test::write_file;

constexpr const char* kBad =
    ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n"
    "knit - f1 3\n"   // 3: V004 and V050
    "knit + f1 3\n";  // 4

class VmCliTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::make_temp_dir("vm-cli");
    good_ = (dir_ / "good.k").string();
    bad_ = (dir_ / "bad.k").string();
    knitout::SheetParams params;
    params.width_needles = 12;
    params.rows = 6;
    write_file(good_, knitout::sheet_text(params));
    write_file(bad_, kBad);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
  std::string good_;
  std::string bad_;
};

TEST_F(VmCliTest, ValidateAcceptsAValidSheet) {
  const auto r = run_wearknit("validate '" + good_ + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("good.k: valid on swg091n2"), std::string::npos) << r.out;
}

TEST_F(VmCliTest, ValidateReportsEachDiagnosticOnItsLine) {
  const auto r = run_wearknit("validate '" + bad_ + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(
      r.err.find(bad_ + ":3: error: [V004] carrier '3' is not in; bring it in with in or inhook "
                        "before using it\n"),
      std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find(bad_ + ":3: warning: [V050] knit on empty needle f1"), std::string::npos);
  EXPECT_NE(r.out.find("bad.k: INVALID on swg091n2"), std::string::npos);
}

TEST_F(VmCliTest, WerrorTurnsWarningsIntoFailure) {
  const std::string warn = (dir_ / "warn.k").string();
  write_file(warn, ";!knitout-2\n;;Carriers: 3\nin 3\nknit + f1 3\nout 3\n");
  EXPECT_EQ(run_wearknit("validate '" + warn + "'").exit_code, 0);
  EXPECT_EQ(run_wearknit("validate --werror '" + warn + "'").exit_code, 1);
}

TEST_F(VmCliTest, ValidateTakesSeveralFiles) {
  const auto r = run_wearknit("validate '" + good_ + "' '" + bad_ + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("good.k: valid"), std::string::npos);
  EXPECT_NE(r.out.find("bad.k: INVALID"), std::string::npos);
}

TEST_F(VmCliTest, GithubFormatAnnotatesTheLine) {
  const auto r = run_wearknit("validate --format github '" + bad_ + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("::error file=" + bad_ +
                       ",line=3::[V004] carrier '3' is not in; bring it in with in "
                       "or inhook before using it\n"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("::warning file=" + bad_ + ",line=3::[V050]"), std::string::npos);
}

TEST_F(VmCliTest, GithubFormatGivesTheColumnWhereKnown) {
  const std::string syntax = (dir_ / "syntax.k").string();
  write_file(syntax, ";!knitout-2\n;;Carriers: 3\nin 3\nknit x f1 3\ntuck + f1 3\nout 3\n");
  const auto r = run_wearknit("validate --format github '" + syntax + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "::error file=" + syntax +
                       ",line=4,col=6::[K012] invalid direction 'x'; expected '+' or '-'\n");
}

TEST_F(VmCliTest, JunitFormatHasOneCasePerDiagnostic) {
  const auto r = run_wearknit("validate --format junit '" + bad_ + "' '" + good_ + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites", 0), 0u);
  // bad.k: file case (failed) + V004 (failed) + V050 (passes, in system-out);
  // good.k: file case + V053 (its last course is dropped off: a warning).
  EXPECT_NE(r.out.find("<testsuites name=\"wearknit validate\" tests=\"5\" failures=\"2\">"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("<testcase classname=\"wearknit.validate.V004\""), std::string::npos);
  EXPECT_NE(r.out.find("file=\"" + bad_ + "\" line=\"3\""), std::string::npos);
  EXPECT_NE(r.out.find("<failure message=\"[V004] carrier &apos;3&apos; is not in"),
            std::string::npos);
}

TEST_F(VmCliTest, JsonFormatListsDiagnostics) {
  const auto r = run_wearknit("validate --json '" + bad_ + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("\"code\": \"V004\""), std::string::npos) << r.out;
}

TEST_F(VmCliTest, UnknownMachineListsTheKnownOnes) {
  const auto r = run_wearknit("validate --machine swg999 '" + good_ + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err,
            "wearknit validate: unknown machine 'swg999'; known machines: swg091n2, kniterate, "
            "generic\n");
}

TEST_F(VmCliTest, MachineOptionPicksTheProfile) {
  const std::string wide = (dir_ / "wide.k").string();
  write_file(wide, ";!knitout-2\n;;Carriers: 1 2 3\nin 3\ntuck + f0 3\nmiss + f300 3\nout 3\n");
  EXPECT_EQ(run_wearknit("validate '" + wide + "'").exit_code, 0);
  const auto r = run_wearknit("validate --machine kniterate '" + wide + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find(":5: error: [V030] needle f300 is outside the bed"), std::string::npos);
}

TEST_F(VmCliTest, ValidateReadsStdin) {
  const auto r = run_wearknit("validate -", kBad);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("<stdin>:3: error: [V004]"), std::string::npos) << r.err;
  EXPECT_EQ(run_wearknit("validate -", test::read_file(good_)).exit_code, 0);
}

TEST_F(VmCliTest, UnknownFormatIsAUsageError) {
  const auto r = run_wearknit("validate --format xml '" + good_ + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "wearknit validate: --format takes text, json, junit or github, not 'xml'\n");
}

TEST_F(VmCliTest, MissingFileIsAnIoError) {
  const auto r = run_wearknit("validate '" + (dir_ / "none.k").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(run_wearknit("simulate '" + (dir_ / "none.k").string() + "'").exit_code, 2);
}

TEST_F(VmCliTest, SimulatePrintsStatistics) {
  const auto r = run_wearknit("simulate --stats '" + good_ + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("  loops made           84\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  bed span             12 needles (slots 0 to 11)\n"), std::string::npos);
  EXPECT_NE(r.out.find("  estimated time       "), std::string::npos);
  // The DAT backend's passes (counted against reference DATs in
  // tests/backends/dat_cli_test.cpp): the same number in both lines.
  const std::size_t at = r.out.find("  DAT passes           ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string count = r.out.substr(at + 23, r.out.find('\n', at) - at - 23);
  EXPECT_GT(std::stoi(count), 0);
  EXPECT_NE(r.out.find("  carriage passes: " + count + " ("), std::string::npos) << r.out;
}

TEST_F(VmCliTest, SimulateJsonHasStatsAndDiagnostics) {
  const auto r = run_wearknit("simulate --json '" + good_ + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("{\"stats\": {", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("\"loops_made\": 84"), std::string::npos);
  const std::size_t at = r.out.find("\"dat_passes\": ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string count = r.out.substr(at + 14, r.out.find_first_of(",\n}", at) - at - 14);
  EXPECT_GT(std::stoi(count), 0) << r.out;
  EXPECT_NE(r.out.find("\"carriage_passes\": {\"count\": " + count), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(", \"diagnostics\": ["), std::string::npos);
}

TEST_F(VmCliTest, SimulateWritesBedViewAndKnitGraph) {
  const std::string png = (dir_ / "view.png").string();
  const std::string svg = (dir_ / "view.svg").string();
  const std::string graph = (dir_ / "graph.json").string();
  auto r = run_wearknit("simulate '" + good_ + "' --bed-view '" + png + "' --knit-graph '" + graph +
                        "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_file(png).substr(0, 4), "\x89PNG");
  EXPECT_NE(read_file(graph).find("\"loops\": ["), std::string::npos);
  r = run_wearknit("simulate '" + good_ + "' --bed-view '" + svg + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(read_file(svg).find("<svg"), std::string::npos);
  r = run_wearknit("simulate '" + good_ + "' --bed-view '" + (dir_ / "view.gif").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(std::filesystem::exists(dir_ / "view.gif"));
}

TEST_F(VmCliTest, SimulateWritesTheHtmlBedViewBesideThePicture) {
  const std::string html = (dir_ / "view.html").string();
  const std::string svg = (dir_ / "view.svg").string();
  auto r = run_wearknit("simulate '" + good_ + "' --html '" + html + "' --bed-view '" + svg + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");  // no statistics unless asked for
  const std::string page = read_file(html);
  EXPECT_EQ(page.substr(0, 15), "<!DOCTYPE html>");
  EXPECT_NE(page.find("<title>good.k</title>"), std::string::npos);
  EXPECT_NE(page.find("id=\"bed-timeline\""), std::string::npos);
  EXPECT_NE(page.find("id=\"bed-source\""), std::string::npos);
  EXPECT_NE(page.find("wk.mountBedView"), std::string::npos);
  EXPECT_EQ(page.find("http://"), std::string::npos);
  EXPECT_EQ(page.find("https://"), std::string::npos);
  EXPECT_NE(read_file(svg).find("<svg"), std::string::npos);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_),
                          std::filesystem::directory_iterator()),
            4);  // good.k, bad.k and the two outputs: no temporary file left
}

TEST_F(VmCliTest, SimulateHtmlOfAnInvalidProgramFromStdin) {
  const std::string html = (dir_ / "bad.html").string();
  const auto r = run_wearknit("simulate - --html '" + html + "'", kBad);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("<stdin>:3: error: [V004]"), std::string::npos) << r.err;
  const std::string page = read_file(html);
  EXPECT_NE(page.find("<title>&lt;stdin&gt;</title>"), std::string::npos);
  EXPECT_NE(page.find("INVALID (1 error, 1 warning)"), std::string::npos) << page.substr(0, 2000);
  EXPECT_NE(page.find("id=\"bed-source\""), std::string::npos);
}

TEST_F(VmCliTest, SimulateHtmlIntoAMissingFolderIsAnIoError) {
  const auto r =
      run_wearknit("simulate '" + good_ + "' --html '" + (dir_ / "no/such/v.html").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("wearknit simulate: "), std::string::npos) << r.err;
}

}  // namespace
}  // namespace wearknit::cli
