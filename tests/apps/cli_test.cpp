#include "apps/wearknit/cli.hpp"

#include <gtest/gtest.h>

#include "tests/test_support.hpp"

namespace wearknit::cli {
namespace {

using test::read_file;
using test::run_wearknit;
using test::write_file;

class CliFiles : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::make_temp_dir("wearknit-cli"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

TEST(CliTest, UnknownVerbPrintsUsageAndExitsTwo) {
  const auto result = run_wearknit("frobnicate");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("unknown verb 'frobnicate'"), std::string::npos);
  EXPECT_NE(result.err.find("usage: wearknit VERB"), std::string::npos);
}

TEST(CliTest, NoArgumentsPrintsUsageAndExitsTwo) {
  const auto result = run_wearknit("");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("usage: wearknit VERB"), std::string::npos);
}

TEST(CliTest, VersionPrintsTheProjectVersion) {
  const auto result = run_wearknit("--version");
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_EQ(result.out.rfind("wearknit ", 0), 0u);
  EXPECT_NE(result.out.find('.'), std::string::npos);
}

TEST(CliTest, HelpListsEveryVerb) {
  const auto result = run_wearknit("--help");
  EXPECT_EQ(result.exit_code, 0);
  for (const Verb& verb : verbs()) {
    EXPECT_NE(result.out.find("  " + std::string(verb.name) + " "), std::string::npos) << verb.name;
  }
}

TEST(CliTest, EveryVerbHasHelpWithItsSynopsis) {
  for (const Verb& verb : verbs()) {
    const auto result = run_wearknit(std::string(verb.name) + " --help");
    EXPECT_EQ(result.exit_code, 0) << verb.name << ": " << result.err;
    EXPECT_NE(result.out.find("usage: wearknit " + std::string(verb.synopsis)), std::string::npos)
        << verb.name;
  }
}

TEST(CliTest, VerbHelpShowsDefaults) {
  const auto result = run_wearknit("fmt --help");
  EXPECT_NE(result.out.find("(=text)"), std::string::npos) << result.out;
  const auto demo = run_wearknit("demo --help");
  EXPECT_NE(demo.out.find("(=wearknit-demo)"), std::string::npos) << demo.out;
}

TEST(CliTest, UnknownOptionExitsTwoWithUsage) {
  const auto result = run_wearknit("fmt --frob x.k");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("unrecognised option '--frob'"), std::string::npos) << result.err;
  EXPECT_NE(result.err.find("usage: wearknit fmt FILE.k"), std::string::npos);
}

TEST(CliTest, MissingInputExitsTwo) {
  const auto result = run_wearknit("fmt");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.err.find("'--input' is required"), std::string::npos) << result.err;
}

TEST(CliTest, UnreadableFileExitsTwo) {
  const auto result = run_wearknit("fmt /nonexistent/x.k");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_EQ(result.err, "/nonexistent/x.k: error: cannot open file\n");
}

TEST(CliTest, FmtReadsStdinAndWritesCanonicalStdout) {
  const auto result = run_wearknit("fmt -", ";!knitout-2\n;;Carriers: 1\nin   1\n\nknit  + f1 1\n");
  EXPECT_EQ(result.exit_code, 0) << result.err;
  EXPECT_EQ(result.out, ";!knitout-2\n;;Carriers: 1\nin 1\nknit + f1 1\n");
}

TEST_F(CliFiles, FmtWithErrorsExitsOneAndWritesNothing) {
  write_file(path("bad.k"), ";!knitout-2\n;;Carriers: 1\nknot + f1 1\nxfer f1\n");
  const auto result = run_wearknit("fmt " + path("bad.k") + " -o " + path("out.k"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.err, path("bad.k") + ":3:1: error: [K010] unknown operation 'knot'\n" +
                            path("bad.k") + ":4:8: error: [K013] missing needle for 'xfer'\n");
  EXPECT_FALSE(std::filesystem::exists(path("out.k")));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_),
                          std::filesystem::directory_iterator()),
            1);
}

TEST_F(CliFiles, FmtJsonPutsDiagnosticsOnStdout) {
  write_file(path("bad.k"), ";!knitout-2\n;;Carriers: 1\nrack x\n");
  const auto result = run_wearknit("fmt --json " + path("bad.k"));
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_EQ(result.out, "[\n  {\"file\": \"" + path("bad.k") +
                            "\", \"line\": 3, \"column\": 6, \"severity\": \"error\", \"code\": "
                            "\"K015\", \"message\": \"racking 'x' is not a number\"}\n]\n");
}

TEST_F(CliFiles, FmtCheckTellsCanonicalFromNot) {
  write_file(path("a.k"), ";!knitout-2\n;;Carriers: 1\nin  1\n");
  EXPECT_EQ(run_wearknit("fmt --check " + path("a.k")).exit_code, 1);
  EXPECT_EQ(run_wearknit("fmt " + path("a.k") + " -o " + path("a.k")).exit_code, 0);
  EXPECT_EQ(read_file(path("a.k")), ";!knitout-2\n;;Carriers: 1\nin 1\n");
  EXPECT_EQ(run_wearknit("fmt --check " + path("a.k")).exit_code, 0);
}

}  // namespace
}  // namespace wearknit::cli
