// `wearknit batch --slurm`: a batch as a Slurm job array, one array task per
// manifest row (`wearknit batch MANIFEST -o DIR --row I`), and a collect job
// that writes the summary once every task has ended (`--collect`), and the
// state of such a submission (docs/batch.md, "On a Slurm cluster").
//
// The Slurm commands (sbatch, squeue, sacct) run as child processes with
// argument vectors, no shell; they find the cluster as they would from a
// terminal (SLURM_CONF, /etc/slurm).
#pragma once

#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

namespace wearknit::cli {

struct SlurmOptions {
  std::string wearknit;  // absolute path of the binary the tasks run
  std::string manifest;  // absolute
  std::string dir;       // absolute; DIR/.batch/ is created if needed
  int rows = 0;          // the manifest's data rows: tasks 0..rows-1
  int throttle = 0;      // at most this many tasks at once (--array's %K); <= 0: no limit
  // Passed through to sbatch as given; empty: not given.
  std::string partition;      // --partition
  std::string time_limit;     // --time, per task
  std::string cpus_per_task;  // --cpus-per-task
  std::string mem;            // --mem, per task
  int threads = 0;            // the rows' --threads; <= 0: not passed
};

// The sbatch scripts slurm_submit writes: DIR/.batch/slurm-array.sh, and
// DIR/.batch/slurm-collect.sh depending on `array_job_id` (afterany).
std::string slurm_array_script(const SlurmOptions& options);
std::string slurm_collect_script(const SlurmOptions& options, const std::string& array_job_id);

// Writes the two scripts, submits the array then the collect job with
// `sbatch --parsable`, and records both job ids in DIR/.batch/slurm.json.
// Returns "" and the ids, or what failed: an option sbatch's #SBATCH lines
// cannot carry (whitespace, quotes or % in DIR), sbatch missing from the
// PATH, sbatch's own message. When the collect job cannot be submitted, the
// array stays submitted and its id is returned with the error.
std::string slurm_submit(const SlurmOptions& options, std::string* array_job_id,
                         std::string* collect_job_id);

// What is known of one row from its state file, for slurm_status: "ok",
// "failed", "running", or "" when it has none (not run yet).
using SlurmRowStatus = std::function<std::string(int row)>;

// Prints the state of the submission recorded in DIR/.batch/slurm.json: the
// array's tasks pending, running and done (completed, failed, or ended and no
// longer listed by the scheduler), from squeue and, where accounting works,
// sacct; the collect job's state; and, when `row_status` is given, the rows
// ok, failed and not done. Returns "" or why it could not (no slurm.json,
// squeue missing or failing).
std::string slurm_status(const std::string& dir, std::ostream& out,
                         const SlurmRowStatus& row_status = nullptr);

// A command's result: its exit code (128 + the signal when killed), stdout
// and stderr; `error` is set, and nothing ran, when it could not start.
struct CommandOutput {
  int exit_code = -1;
  std::string out;
  std::string err;
  std::string error;
};

// Runs argv[0], looked up on the PATH, with argv, standard input from
// /dev/null, and waits for it.
CommandOutput run_command(const std::vector<std::string>& argv);

}  // namespace wearknit::cli
