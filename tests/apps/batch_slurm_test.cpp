#include "apps/wearknit/batch_slurm.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "tests/test_support.hpp"

namespace wearknit::cli {
namespace {

namespace fs = std::filesystem;
using test::read_file;
using test::TempDir;
using test::write_file;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

SlurmOptions options_in(const fs::path& root) {
  SlurmOptions o;
  o.wearknit = (root / "stand-in.sh").string();
  o.manifest = (root / "manifest.csv").string();
  o.dir = (root / "out").string();
  o.rows = 4;
  o.throttle = 1;
  o.partition = "debug";
  o.time_limit = "5";
  o.cpus_per_task = "1";
  o.mem = "100M";
  o.threads = 1;
  return o;
}

TEST(BatchSlurmTest, ArrayScriptRunsOneRowPerTaskWithTheOptionsGiven) {
  SlurmOptions o = options_in("/data/run");
  o.throttle = 3;
  const std::string script = slurm_array_script(o);
  EXPECT_TRUE(contains(script, "#SBATCH --array=0-3%3\n")) << script;
  EXPECT_TRUE(contains(script, "#SBATCH --output=/data/run/out/.batch/slurm-%A_%a.out\n"));
  EXPECT_TRUE(contains(script, "#SBATCH --job-name=wearknit-out\n"));
  EXPECT_TRUE(contains(script, "#SBATCH --partition=debug\n"));
  EXPECT_TRUE(contains(script, "#SBATCH --time=5\n"));
  EXPECT_TRUE(contains(script, "#SBATCH --cpus-per-task=1\n"));
  EXPECT_TRUE(contains(script, "#SBATCH --mem=100M\n"));
  EXPECT_TRUE(contains(script,
                       "exec '/data/run/stand-in.sh' batch '/data/run/manifest.csv' -o "
                       "'/data/run/out' --row \"$SLURM_ARRAY_TASK_ID\" --threads 1\n"))
      << script;
}

TEST(BatchSlurmTest, ArrayScriptLeavesOutWhatIsNotGiven) {
  SlurmOptions o;
  o.wearknit = "/bin/wearknit";
  o.manifest = "/m.csv";
  o.dir = "/d";
  o.rows = 1;
  const std::string script = slurm_array_script(o);
  EXPECT_TRUE(contains(script, "#SBATCH --array=0-0\n")) << script;
  for (const char* option : {"--partition", "--time", "--cpus-per-task", "--mem", "--threads"}) {
    EXPECT_FALSE(contains(script, option)) << option;
  }
}

TEST(BatchSlurmTest, CollectScriptWaitsForEveryTaskToEnd) {
  const std::string script = slurm_collect_script(options_in("/data/run"), "42");
  EXPECT_TRUE(contains(script, "#SBATCH --dependency=afterany:42\n")) << script;
  EXPECT_TRUE(contains(script, "#SBATCH --kill-on-invalid-dep=no\n"));
  EXPECT_TRUE(contains(script, "-o '/data/run/out' --collect\n"));
  EXPECT_FALSE(contains(script, "--array"));
}

TEST(BatchSlurmTest, SubmitRejectsWhatSbatchCannotCarry) {
  std::string array_id, collect_id;
  SlurmOptions o = options_in("/data/run");
  o.dir = "/data/my run";
  EXPECT_EQ(slurm_submit(o, &array_id, &collect_id),
            "the output folder '/data/my run' has a blank, a quote, a backslash or a % that an "
            "#SBATCH line cannot carry");
  o = options_in("/data/run");
  o.manifest = "manifest.csv";
  EXPECT_EQ(slurm_submit(o, &array_id, &collect_id), "the manifest 'manifest.csv' is not absolute");
  o = options_in("/data/run");
  o.rows = 0;
  EXPECT_EQ(slurm_submit(o, &array_id, &collect_id), "the manifest has no rows: nothing to submit");
  EXPECT_EQ(array_id, "");
}

TEST(BatchSlurmTest, SubmitSaysWhenSbatchIsNotOnThePath) {
  TempDir root("wearknit-slurm");
  const char* path = std::getenv("PATH");
  const std::string saved = path ? path : "";
  ::setenv("PATH", (root.path() / "empty").c_str(), 1);
  std::string array_id, collect_id;
  const std::string error = slurm_submit(options_in(root.path()), &array_id, &collect_id);
  ::setenv("PATH", saved.c_str(), 1);
  EXPECT_EQ(error, "'sbatch' is not on the PATH: is Slurm's client installed here?");
  EXPECT_TRUE(fs::exists(root.path() / "out/.batch/slurm-array.sh"));
}

TEST(BatchSlurmTest, StatusWithoutSubmissionIsAnError) {
  TempDir root("wearknit-slurm");
  std::ostringstream out;
  EXPECT_EQ(slurm_status(root.path().string(), out),
            "no Slurm submission in " + root.path().string() + " (" +
                (root.path() / ".batch/slurm.json").string() + ")");
}

TEST(BatchSlurmTest, RunCommandCapturesBothStreamsAndTheExitCode) {
  const CommandOutput result = run_command({"sh", "-c", "echo out; echo err >&2; exit 3"});
  EXPECT_EQ(result.error, "");
  EXPECT_EQ(result.exit_code, 3);
  EXPECT_EQ(result.out, "out\n");
  EXPECT_EQ(result.err, "err\n");
}

// tests/slurm/cluster.sh's single-node cluster, started for one test and
// stopped when it ends, whatever the assertions did.
class Cluster {
 public:
  explicit Cluster(const fs::path& dir) : dir_(dir) {
    result_ = run_command({"bash", script(), "start", dir_.string()});
    started_ = result_.error.empty() && result_.exit_code == 0;
  }
  ~Cluster() {
    if (started_ || result_.exit_code == 77) run_command({"bash", script(), "stop", dir_.string()});
  }
  Cluster(const Cluster&) = delete;
  Cluster& operator=(const Cluster&) = delete;
  const CommandOutput& result() const { return result_; }
  // The file cluster.sh prints in its `export SLURM_CONF=...` line.
  std::string slurm_conf() const {
    const std::string prefix = "export SLURM_CONF=";
    const auto at = result_.out.find(prefix);
    if (at == std::string::npos) return "";
    const std::string rest = result_.out.substr(at + prefix.size());
    return rest.substr(0, rest.find('\n'));
  }

 private:
  static std::string script() { return (test::source_dir() / "tests/slurm/cluster.sh").string(); }
  fs::path dir_;
  CommandOutput result_;
  bool started_ = false;
};

// Every row's task waits for DIR/go, then writes its row file; row 1 fails.
constexpr const char* kStandIn = R"(#!/bin/sh
# batch MANIFEST -o DIR --row I --threads T, or batch MANIFEST -o DIR --collect
dir=$4
case "$5" in
  --row)
    while [ ! -e "$dir/go" ]; do sleep 0.1; done
    if [ "$6" = 1 ]; then
      echo '{"status": "failed"}' > "$dir/.batch/row-$6.json"
      exit 1
    fi
    echo '{"status": "ok", "threads": "'"$8"'"}' > "$dir/.batch/row-$6.json" ;;
  --collect)
    ls "$dir/.batch" > "$dir/collected.txt" ;;
esac
)";

// Waits up to `seconds` for `done` to hold, polling every 200 ms.
template <typename Done>
bool wait_for(int seconds, Done done) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(seconds);
  while (std::chrono::steady_clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  return done();
}

// A test on a cluster of its own, in a temporary folder: skipped, saying
// why, where Slurm cannot start; SLURM_CONF points at it while the test runs.
class BatchSlurmClusterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    cluster_.emplace(root_.path() / "cluster");
    const CommandOutput& started = cluster_->result();
    if (started.exit_code == 77 || !started.error.empty()) {
      GTEST_SKIP() << "no single-node Slurm here: " << started.err << started.error;
    }
    ASSERT_EQ(started.exit_code, 0) << started.err;
    ASSERT_NE(cluster_->slurm_conf(), "") << started.out;
    ::setenv("SLURM_CONF", cluster_->slurm_conf().c_str(), 1);
  }
  void TearDown() override { ::unsetenv("SLURM_CONF"); }
  const fs::path& root() const { return root_.path(); }

 private:
  TempDir root_{"wearknit-slurm"};
  std::optional<Cluster> cluster_;
};

TEST_F(BatchSlurmClusterTest, ArrayRunsEveryRowThrottledAndThenTheCollectJob) {
  const SlurmOptions o = options_in(root());
  write_file(o.wearknit, kStandIn);
  fs::permissions(o.wearknit, fs::perms::owner_all, fs::perm_options::add);
  write_file(o.manifest, "name,garment,wearer\n");
  std::string array_id, collect_id;
  ASSERT_EQ(slurm_submit(o, &array_id, &collect_id), "");
  ASSERT_NE(array_id, "");
  ASSERT_NE(collect_id, "");

  const fs::path state = fs::path(o.dir) / ".batch";
  const std::string array_script = read_file(state / "slurm-array.sh");
  EXPECT_TRUE(contains(array_script, "#SBATCH --array=0-3%1\n")) << array_script;
  const std::string collect_script = read_file(state / "slurm-collect.sh");
  EXPECT_TRUE(contains(collect_script, "#SBATCH --dependency=afterany:" + array_id + "\n"))
      << collect_script;
  const std::string record = read_file(state / "slurm.json");
  EXPECT_TRUE(contains(record, "\"array_job\": \"" + array_id + "\"")) << record;
  EXPECT_TRUE(contains(record, "\"collect_job\": \"" + collect_id + "\"")) << record;

  const auto status = [&] {
    std::ostringstream out;
    const std::string error = slurm_status(o.dir, out, [&](int row) {
      const fs::path file = state / ("row-" + std::to_string(row) + ".json");
      if (!fs::exists(file)) return std::string();
      return contains(read_file(file), "\"ok\"") ? std::string("ok") : std::string("failed");
    });
    return error.empty() ? out.str() : "error: " + error;
  };

  // Two CPUs, but the throttle lets one task run at a time: the others wait
  // for it, the collect job for all of them.
  std::string seen;
  EXPECT_TRUE(wait_for(60, [&] {
    seen = status();
    return contains(seen, "4 tasks, 3 pending, 1 running, 0 done");
  })) << seen;
  EXPECT_TRUE(contains(seen, "collect job " + collect_id + ": PENDING (Dependency)\n")) << seen;
  EXPECT_TRUE(contains(seen, "rows: 0 ok, 0 failed, 0 running, 4 not run\n")) << seen;

  write_file(fs::path(o.dir) / "go", "");
  EXPECT_TRUE(wait_for(120, [&] {
    const CommandOutput listed = run_command({"squeue", "-h", "-j", array_id + "," + collect_id});
    return listed.exit_code != 0 || listed.out.empty();
  })) << status();

  for (int row = 0; row < 4; ++row) {
    const fs::path file = state / ("row-" + std::to_string(row) + ".json");
    ASSERT_TRUE(fs::exists(file)) << file;
    if (row != 1) {
      EXPECT_EQ(read_file(file), "{\"status\": \"ok\", \"threads\": \"1\"}\n");
    }
  }
  ASSERT_TRUE(fs::exists(fs::path(o.dir) / "collected.txt"));
  EXPECT_TRUE(contains(read_file(fs::path(o.dir) / "collected.txt"), "row-3.json\n"));
  EXPECT_TRUE(fs::exists(state / ("slurm-" + array_id + "_0.out")));

  const std::string end = status();
  EXPECT_TRUE(contains(end, "array job " + array_id +
                                ": 4 tasks, 0 pending, 0 running, 4 done (3 completed, 1 failed: "
                                "FAILED)\n"))
      << end;
  EXPECT_TRUE(contains(end, "collect job " + collect_id + ": COMPLETED\n")) << end;
  EXPECT_TRUE(contains(end, "rows: 3 ok, 1 failed, 0 unfinished, 0 not run\n")) << end;
}

// The real `wearknit batch --slurm` on the demo's shapes: the rows that run
// give pieces byte for byte those of a local batch of the same manifest, the
// row with a missing input fails cleanly, the collect job writes the
// summary; a task cancelled midway (scancel) is run again by the next batch,
// which skips the rows done.
TEST_F(BatchSlurmClusterTest, TheSameManifestThroughSlurmGivesTheSamePieces) {
  // The demo's shapes, written by the demo itself.
  const fs::path demo = root() / "demo";
  ASSERT_EQ(test::run_wearknit("demo -q -o '" + demo.string() + "'").exit_code, 0);
  const fs::path manifest = root() / "m.csv";
  write_file(manifest,
             "name,garment,wearer,size_mm,wear_trials,resolution,cloth_vertices\n"
             "small,demo/input/garment.obj,demo/input/wearer.obj,40,1,32,0\n"
             "large,demo/input/garment.obj,demo/input/wearer.obj,55,1,32,0\n"
             "missing,nothere.obj,demo/input/wearer.obj,40,1,32,0\n");
  const fs::path local = root() / "local";
  const fs::path remote = root() / "slurm";
  EXPECT_EQ(test::run_wearknit("batch '" + manifest.string() + "' -o '" + local.string() +
                               "' --jobs 2 --threads 1 -q")
                .exit_code,
            1);

  // Submitted, then the large row's task cancelled as soon as it runs.
  const std::string submit =
      "batch '" + manifest.string() + "' -o '" + remote.string() + "' --slurm --jobs 2";
  auto r = test::run_wearknit(submit);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string array_id = r.out.substr(r.out.find("job array ") + 10);
  const std::string id = array_id.substr(0, array_id.find(' '));
  ASSERT_TRUE(wait_for(120, [&] {
    return read_file(remote / ".batch" / "large.json").find("running") != std::string::npos;
  }));
  EXPECT_EQ(run_command({"scancel", id + "_1"}).exit_code, 0);
  ASSERT_TRUE(wait_for(300, [&] { return fs::exists(remote / "batch.csv"); }));
  std::string csv = read_file(remote / "batch.csv");
  EXPECT_TRUE(contains(csv, "\nsmall,ok,")) << csv;
  EXPECT_TRUE(contains(csv, "\nlarge,unfinished,")) << csv;
  EXPECT_TRUE(contains(csv, "\nmissing,failed,")) << csv;

  // Submitted again: only the cancelled row and the failed one run.
  r = test::run_wearknit(submit);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(wait_for(300, [&] {
    return read_file(remote / "batch.csv").find("\nlarge,ok,") != std::string::npos;
  }));
  const std::string second = r.out.substr(r.out.find("job array ") + 10);
  const std::string log =
      read_file(remote / ".batch" / ("slurm-" + second.substr(0, second.find(' ')) + "_0.out"));
  EXPECT_TRUE(contains(log, "skip small: done with the same inputs")) << log;
  csv = read_file(remote / "batch.csv");
  EXPECT_TRUE(contains(csv, "\nmissing,failed,")) << csv;

  // Byte for byte the local batch's pieces.
  for (const char* row : {"small", "large"}) {
    int pieces = 0;
    for (const auto& entry : fs::directory_iterator(local / row / "pieces")) {
      if (entry.path().extension() != ".k") continue;
      ++pieces;
      EXPECT_EQ(read_file(entry.path()),
                read_file(remote / row / "pieces" / entry.path().filename()))
          << row << " " << entry.path().filename();
    }
    EXPECT_GT(pieces, 0) << row;
  }
}

}  // namespace
}  // namespace wearknit::cli
