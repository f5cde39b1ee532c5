// wearknit batch (apps/wearknit/batch.hpp, verb_batch.cpp): the manifest is
// read strictly, with the file and line of every problem; a batch runs its
// rows, a failed row does not stop the others, the summary says which
// passed; run again, it runs only the rows not done with the same inputs,
// also after it was killed midway.
#include "apps/wearknit/batch.hpp"

#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/shapes.hpp"
#include "tests/test_support.hpp"

namespace wearknit::test {
namespace {

namespace fs = std::filesystem;
using cli::read_manifest;
using nlohmann::json;

fs::path write(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string all;
  for (const std::string& l : lines) all += l + "\n";
  return all;
}

TEST(BatchManifestTest, ReadsRowsWithQuotedFieldsAndPlanOptions) {
  TempDir dir("batch-manifest");
  const fs::path m = write(dir.path() / "m.csv",
                           "name,garment,wearer,size_mm,pattern,no_pictures\r\n"
                           "a,g.obj,/abs/w.obj,100,seed,\r\n"
                           "\r\n"
                           "\"b.2\",\"dir, with comma/g.obj\",w.obj,,,true\r\n");
  std::vector<std::string> problems;
  const auto manifest = read_manifest(m, problems);
  ASSERT_TRUE(manifest) << joined(problems);
  ASSERT_EQ(manifest->rows.size(), 2u);
  const cli::BatchRow& a = manifest->rows[0];
  EXPECT_EQ(a.name, "a");
  EXPECT_EQ(a.line, 2);
  EXPECT_EQ(a.garment_path, fs::absolute(dir.path()) / "g.obj");
  EXPECT_EQ(a.wearer_path, fs::path("/abs/w.obj"));
  ASSERT_EQ(a.options.size(), 2u);
  EXPECT_EQ(a.options[0], (std::pair<std::string, std::string>{"size-mm", "100"}));
  EXPECT_EQ(a.options[1], (std::pair<std::string, std::string>{"pattern", "seed"}));
  const cli::BatchRow& b = manifest->rows[1];
  EXPECT_EQ(b.line, 4);
  EXPECT_EQ(b.garment, "dir, with comma/g.obj");
  // A flag column is given without a value.
  const auto args = cli::plan_arguments(b, "/out", 3);
  const std::vector<std::string> expected = {
      "plan",      (fs::absolute(dir.path()) / "dir, with comma/g.obj").string(),
      "--wearer",  (fs::absolute(dir.path()) / "w.obj").string(),
      "-o",        "/out/b.2",
      "--threads", "3",
      "--quiet",   "--no-pictures"};
  EXPECT_EQ(args, expected);
}

TEST(BatchManifestTest, EveryProblemNamesTheFileAndLine) {
  TempDir dir("batch-manifest");
  std::vector<std::string> problems;
  const fs::path header = write(dir.path() / "h.csv", "name,garment,sise_mm,threads\n");
  EXPECT_FALSE(read_manifest(header, problems));
  const std::string where = header.string() + ":1: error: ";
  EXPECT_EQ(joined(problems),
            where + "column 'sise_mm' is not an option of wearknit plan (--sise-mm)\n" + where +
                "column 'threads': the batch sets --threads itself (--jobs and --threads set "
                "the threads)\n" +
                where + "no column 'wearer' (the header needs name, garment and wearer)\n");

  problems.clear();
  const fs::path rows = write(dir.path() / "r.csv",
                              "name,garment,wearer\n"
                              "a,g,w\n"
                              "a,g,w\n"
                              "../up,g,w\n"
                              "c,g\n"
                              "d,,w\n"
                              "\"e,g,w\n");
  EXPECT_FALSE(read_manifest(rows, problems));
  const std::string at = rows.string() + ":";
  EXPECT_EQ(joined(problems), at + "3: error: the name 'a' is used by an earlier row\n" + at +
                                  "4: error: the name starts with '.'\n" + at +
                                  "5: error: the row has 2 fields; the header has 3\n" + at +
                                  "6: error: row 'd' has no garment\n" + at +
                                  "7: error: a quoted field is not closed\n");

  problems.clear();
  EXPECT_FALSE(read_manifest(write(dir.path() / "e.csv", "name,garment,wearer\n"), problems));
  EXPECT_EQ(problems, std::vector<std::string>{(dir.path() / "e.csv").string() +
                                               ": error: the manifest has a header but no rows"});
}

// The demo's shapes at two sizes and a row whose garment does not exist.
class BatchRunTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream wearer(dir_.path() / "wearer.obj");
    planner::write_obj(wearer, planner::quad_ellipsoid(25, 1.8, 6));
    std::ofstream garment(dir_.path() / "garment.obj");
    planner::write_obj(garment, planner::quad_ellipsoid(26.5, 1.75, 6));
    manifest_ = write(dir_.path() / "m.csv",
                      "name,garment,wearer,size_mm,wear_trials,resolution,cloth_vertices\n"
                      "small,garment.obj,wearer.obj,40,1,32,0\n"
                      "large,garment.obj,wearer.obj,60,1,32,0\n"
                      "missing,nothere.obj,wearer.obj,60,1,32,0\n");
    out_ = dir_.path() / "out";
  }
  json summary() {
    std::ifstream in(out_ / "batch.json");
    return json::parse(in);
  }
  std::string status(const json& s, const std::string& name) {
    for (const json& row : s["rows"])
      if (row["name"] == name) return row["status"];
    return "absent";
  }
  TempDir dir_{"batch-run"};
  fs::path manifest_;
  fs::path out_;
};

TEST_F(BatchRunTest, AFailedRowDoesNotStopTheOthersAndResumeRunsOnlyWhatIsNotDone) {
  const std::string command =
      "batch '" + manifest_.string() + "' -o '" + out_.string() + "' --jobs 2";
  auto r = run_wearknit(command);
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  json s = summary();
  EXPECT_EQ(status(s, "small"), "ok");
  EXPECT_EQ(status(s, "large"), "ok");
  EXPECT_EQ(status(s, "missing"), "failed");
  for (const json& row : s["rows"]) {
    if (row["name"] == "missing") {
      EXPECT_NE(row["error"].get<std::string>().find("nothere.obj: error: [P001]"),
                std::string::npos);
    } else {
      EXPECT_GT(row["summary"]["stitches"].get<int>(), 100);
      EXPECT_TRUE(fs::exists(out_ / row["page"].get<std::string>()));
    }
  }
  std::ifstream csv(out_ / "batch.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("name,status,error,cut_s,wearability_s,", 0), 0u) << header;
  EXPECT_TRUE(fs::exists(out_ / "index.html"));

  // --status of a local batch counts its rows.
  const auto state = run_wearknit("batch --status '" + out_.string() + "'");
  EXPECT_EQ(state.exit_code, 0) << state.err;
  EXPECT_EQ(state.out,
            "no Slurm submission (a local batch); rows: 2 ok, 1 failed, 0 running or "
            "unfinished\n");

  // Again: the two plans that passed are not run again; the failed row is.
  r = run_wearknit(command);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("skip small: done with the same inputs"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("skip large: done with the same inputs"), std::string::npos);
  EXPECT_NE(r.out.find("missing failed"), std::string::npos);

  // A changed option runs its row again.
  write(manifest_,
        "name,garment,wearer,size_mm,wear_trials,resolution,cloth_vertices\n"
        "small,garment.obj,wearer.obj,40,1,32,0\n"
        "large,garment.obj,wearer.obj,60,2,32,0\n");
  r = run_wearknit(command);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("skip small"), std::string::npos);
  EXPECT_NE(r.out.find("large ok"), std::string::npos) << r.out;
}

TEST_F(BatchRunTest, KilledMidwayItFinishesTheRestAndKeepsWhatWasDone) {
  write(manifest_,
        "name,garment,wearer,size_mm,wear_trials,resolution,cloth_vertices\n"
        "small,garment.obj,wearer.obj,40,1,32,0\n"
        "large,garment.obj,wearer.obj,60,1,32,0\n");
  const std::string command =
      "batch '" + manifest_.string() + "' -o '" + out_.string() + "' --jobs 1";
  // Killed once the first row's plan has begun its log: the row running then
  // dies with the batch and is left unfinished.
  ASSERT_TRUE(run_wearknit_and_kill(command, out_ / "small" / "plan.log", 1));
  // Whatever was running then is left unfinished; what had ended is kept.
  std::map<std::string, std::string> before;
  for (const char* row : {"small", "large"}) {
    std::ifstream in(out_ / ".batch" / (std::string(row) + ".json"));
    before[row] = in ? json::parse(in).value("status", "") : "not run";
  }
  EXPECT_EQ(before["small"], "running");
  const auto r = run_wearknit(command);
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  for (const auto& [row, state] : before) {
    if (state == "ok") {
      EXPECT_NE(r.out.find("skip " + row + ": done"), std::string::npos) << r.out;
    } else {
      EXPECT_NE(r.out.find(row + " ok"), std::string::npos) << r.out;
    }
  }
  const json s = summary();
  EXPECT_EQ(status(s, "small"), "ok");
  EXPECT_EQ(status(s, "large"), "ok");
}

// The process whose command line holds `text`, other than this one; -1 when
// there is none.
pid_t process_with(const std::string& text) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(entry.path() / "cmdline", std::ios::binary);
    std::string line((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::replace(line.begin(), line.end(), '\0', ' ');
    const pid_t pid = static_cast<pid_t>(std::stol(name));
    if (pid != ::getpid() && line.find(text) != std::string::npos) return pid;
  }
  return -1;
}

TEST_F(BatchRunTest, ARowStoppedFromOutsideIsUnfinishedNotFailed) {
  // The first row's plan is sent SIGTERM while the batch goes on (as
  // scancel or a hang-up would): the row is left unfinished, not failed,
  // and the next batch runs it again.
  write(manifest_,
        "name,garment,wearer,size_mm,wear_trials,resolution,cloth_vertices\n"
        "small,garment.obj,wearer.obj,40,1,32,0\n"
        "large,garment.obj,wearer.obj,45,1,32,0\n");
  const std::string command =
      "batch '" + manifest_.string() + "' -o '" + out_.string() + "' --jobs 1";
  CommandResult first;
  std::thread batch([&] { first = run_wearknit(command); });
  const std::string child = "-o " + (out_ / "small").string();
  bool stopped = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (!stopped && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (!fs::exists(out_ / "small" / "plan.log")) continue;
    const pid_t pid = process_with(child);
    stopped = pid > 0 && ::kill(pid, SIGTERM) == 0;
  }
  batch.join();
  ASSERT_TRUE(stopped);
  EXPECT_NE(first.out.find("small stopped by signal 15, unfinished"), std::string::npos)
      << first.out;
  EXPECT_NE(first.out.find("large ok"), std::string::npos) << first.out;
  json s = summary();
  EXPECT_EQ(status(s, "small"), "unfinished");
  EXPECT_EQ(status(s, "large"), "ok");
  const auto second = run_wearknit(command);
  EXPECT_EQ(second.exit_code, 0) << second.out << second.err;
  EXPECT_NE(second.out.find("small ok"), std::string::npos) << second.out;
  EXPECT_NE(second.out.find("skip large: done"), std::string::npos) << second.out;
  s = summary();
  EXPECT_EQ(status(s, "small"), "ok");
}

}  // namespace
}  // namespace wearknit::test
