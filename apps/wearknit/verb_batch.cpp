// wearknit batch: every row of a manifest as a plan into DIR/NAME/, as many
// at a time as --jobs, each a `wearknit plan` process of its own (a row that
// crashes cannot take the others with it); the summary in DIR/batch.json,
// batch.csv and index.html; run again, only the rows not done with the same
// inputs run (docs/batch.md).
#include <fcntl.h>
#include <sys/file.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <thread>
#include <utility>

#include "apps/wearknit/batch.hpp"
#include "apps/wearknit/batch_slurm.hpp"
#include "apps/wearknit/cli.hpp"

namespace wearknit::cli {

namespace fs = std::filesystem;
namespace po = boost::program_options;

namespace {

using Clock = std::chrono::steady_clock;

std::string self_binary() {
  std::error_code error;
  const fs::path self = fs::read_symlink("/proc/self/exe", error);
  return error ? std::string("wearknit") : self.string();
}

// The first line of a row's log that reports an error, else its last line.
std::string first_error(const fs::path& log) {
  std::ifstream in(log);
  std::string line, last;
  while (std::getline(in, line)) {
    const auto text = line.find_first_not_of(" \t");
    if (text != std::string::npos) line.erase(0, text);
    if (line.find("error") != std::string::npos) return line.substr(0, 400);
    if (!line.empty()) last = line;
  }
  return last.substr(0, 400);
}

// Holds an exclusive lock on `path` while it lives (flock: released by the
// kernel when the process ends, however it ends).
class FileLock {
 public:
  explicit FileLock(const fs::path& path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ >= 0 && ::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      fd_ = -1;
    }
  }
  ~FileLock() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;
  bool held() const { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

// Starts `wearknit plan` for a row, its output into DIR/.batch/NAME.log; the
// child is killed if the batch ends first (PR_SET_PDEATHSIG), so that no plan
// goes on writing a folder a later batch runs again. Returns the pid or -1.
pid_t start_row(const std::string& binary, const BatchRow& row, const fs::path& dir, int threads) {
  std::vector<std::string> args = plan_arguments(row, dir, threads);
  args.insert(args.begin(), binary);
  const fs::path log = batch_state_dir(dir) / (row.name + ".log");
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(127);
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  if (fd >= 0) {
    ::dup2(fd, 1);
    ::dup2(fd, 2);
  }
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  ::execv(binary.c_str(), argv.data());
  ::_exit(127);
}

struct Running {
  const BatchRow* row = nullptr;
  std::uint64_t fingerprint = 0;
  Clock::time_point start;
  std::string started;
};

// Records a row's end and says so.
void finish_row(const fs::path& dir, const Running& r, int status, std::size_t done,
                std::size_t total, bool quiet, Context& context, int* failed) {
  if (WIFSIGNALED(status)) {
    const int signal = WTERMSIG(status);
    if (signal == SIGTERM || signal == SIGINT || signal == SIGHUP || signal == SIGKILL) {
      // Stopped from outside (scancel, Ctrl-C, a hang-up, a time limit), not
      // failed: the row keeps its "running" state, which the summary calls
      // unfinished, and the next batch runs it again.
      context.out << '[' << done << '/' << total << "] " << r.row->name << " stopped by signal "
                  << signal << ", unfinished\n"
                  << std::flush;
      return;
    }
  }
  RowState state;
  state.fingerprint = r.fingerprint;
  state.started = r.started;
  state.seconds = std::chrono::duration<double>(Clock::now() - r.start).count();
  state.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  state.status = state.exit_code == 0 ? "ok" : "failed";
  if (state.exit_code != 0) {
    state.error = first_error(batch_state_dir(dir) / (r.row->name + ".log"));
    if (state.error.empty()) state.error = "exit " + std::to_string(state.exit_code);
    ++*failed;
  }
  const std::string failure = write_row_state(dir, r.row->name, state);
  if (!failure.empty()) context.err << "wearknit batch: " << failure << '\n';
  if (quiet && state.exit_code == 0) return;
  context.out << '[' << done << '/' << total << "] " << r.row->name << ' ' << state.status << " in "
              << std::fixed << std::setprecision(1) << state.seconds << " s";
  if (state.exit_code != 0) context.out << " (exit " << state.exit_code << "): " << state.error;
  context.out << '\n' << std::flush;
}

}  // namespace

int run_batch(const std::vector<std::string>& args, Context& context) {
  std::string manifest_path;
  std::string dir_text;
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  int jobs = cores;
  int threads = 0;
  int row_index = -1;
  SlurmOptions slurm;
  po::options_description options("options");
  options.add_options()("manifest", po::value<std::string>(&manifest_path),
                        "the manifest: CSV with a header (docs/batch.md)")(
      "output,o", po::value<std::string>(&dir_text), "the batch folder: one plan folder per row")(
      "jobs,j", po::value<int>(&jobs)->default_value(cores),
      "plans at once (default: the machine's cores)")(
      "threads", po::value<int>(&threads)->default_value(0),
      "threads of each plan (0: the cores divided among the jobs)")(
      "row", po::value<int>(&row_index),
      "run only this row (0-based; what a Slurm array task does)")(
      "collect", "write the summary from the rows' states, running nothing")(
      "slurm", "submit the batch to Slurm: a job array, one task per row, and a collect job")(
      "partition", po::value<std::string>(&slurm.partition), "--slurm: sbatch --partition")(
      "time", po::value<std::string>(&slurm.time_limit), "--slurm: sbatch --time, per row")(
      "cpus-per-task", po::value<std::string>(&slurm.cpus_per_task),
      "--slurm: sbatch --cpus-per-task (and each plan's --threads)")(
      "mem", po::value<std::string>(&slurm.mem), "--slurm: sbatch --mem, per row")(
      "status",
      "report a batch folder's Slurm submission and its rows: wearknit batch --status DIR")(
      "quiet,q", "print only failures and the summary line");
  po::positional_options_description positional;
  positional.add("manifest", 1);
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("batch"), options, positional, values, context)) {
    return *code;
  }
  if (values.count("status") != 0) {
    // The batch folder is the positional argument, or -o.
    const std::string status_dir = !dir_text.empty() ? dir_text : manifest_path;
    if (status_dir.empty()) {
      context.err << "wearknit batch: --status takes the batch folder: wearknit batch --status "
                     "DIR\n";
      return kExitUsage;
    }
    const fs::path dir = fs::absolute(status_dir);
    std::vector<std::string> problems;
    std::optional<Manifest> manifest;
    std::ifstream recorded(batch_state_dir(dir) / "slurm.json");
    if (recorded) {
      const auto value = nlohmann::json::parse(recorded, nullptr, false);
      if (value.is_object() && value.contains("manifest")) {
        manifest = read_manifest(value["manifest"].get<std::string>(), problems);
      }
    }
    SlurmRowStatus rows = nullptr;
    if (manifest) {
      rows = [&](int i) {
        const auto state = read_row_state(dir, manifest->rows[static_cast<std::size_t>(i)].name);
        return state ? state->status : std::string();
      };
    }
    if (!fs::exists(batch_state_dir(dir) / "slurm.json")) {
      // A local batch: its rows' states only.
      if (!fs::is_directory(batch_state_dir(dir))) {
        context.err << dir.string()
                    << ": error: not a batch folder (no " + batch_state_dir(dir).string() + ")\n";
        return kExitUsage;
      }
      std::map<std::string, int> counts;
      for (const auto& entry : fs::directory_iterator(batch_state_dir(dir))) {
        if (entry.path().extension() != ".json") continue;
        if (const auto state = read_row_state(dir, entry.path().stem().string())) {
          ++counts[state->status];
        }
      }
      context.out << "no Slurm submission (a local batch); rows: " << counts["ok"] << " ok, "
                  << counts["failed"] << " failed, " << counts["running"]
                  << " running or unfinished\n";
      return kExitOk;
    }
    const std::string failure = slurm_status(dir.string(), context.out, rows);
    if (!failure.empty()) {
      context.err << dir.string() << ": error: " << failure << '\n';
      return kExitUsage;
    }
    return kExitOk;
  }
  if (manifest_path.empty() || dir_text.empty()) {
    context.err << "wearknit batch: give the manifest and the batch folder: wearknit batch "
                   "MANIFEST.csv -o DIR\n";
    return kExitUsage;
  }
  if (jobs < 1 || threads < 0) {
    context.err << "wearknit batch: --jobs must be at least 1 and --threads at least 0\n";
    return kExitUsage;
  }
  if (threads == 0) threads = std::max(1, cores / jobs);

  std::vector<std::string> problems;
  const auto manifest = read_manifest(manifest_path, problems);
  if (!manifest) {
    for (const std::string& p : problems) context.err << p << '\n';
    return kExitInvalid;
  }
  const fs::path dir = fs::absolute(dir_text);
  std::error_code error;
  fs::create_directories(batch_state_dir(dir), error);
  if (error) {
    context.err << dir.string() << ": error: cannot make the batch folder: " << error.message()
                << '\n';
    return kExitUsage;
  }
  const std::size_t total = manifest->rows.size();
  if (row_index >= 0 && static_cast<std::size_t>(row_index) >= total) {
    context.err << "wearknit batch: --row " << row_index << ": the manifest has " << total
                << " rows (0 to " << total - 1 << ")\n";
    return kExitUsage;
  }

  if (values.count("slurm") != 0) {
    slurm.wearknit = self_binary();
    slurm.manifest = fs::absolute(manifest_path).string();
    slurm.dir = dir.string();
    slurm.rows = static_cast<int>(total);
    // --jobs throttles the array; each task's plan gets --threads, else the
    // CPUs Slurm gives the task (--cpus-per-task), else one.
    slurm.throttle = jobs;
    if (!values["threads"].defaulted()) {
      slurm.threads = threads;
    } else {
      slurm.threads = std::max(1, std::atoi(slurm.cpus_per_task.c_str()));
    }
    std::string array_id, collect_id;
    const std::string failure = slurm_submit(slurm, &array_id, &collect_id);
    if (!array_id.empty()) {
      context.out << "submitted job array " << array_id << " (" << total << " rows"
                  << (slurm.throttle > 0
                          ? ", at most " + std::to_string(slurm.throttle) + " at once"
                          : std::string())
                  << ")";
      if (!collect_id.empty()) context.out << " and collect job " << collect_id;
      context.out << "; wearknit batch --status " << dir.string() << '\n';
    }
    if (!failure.empty()) {
      context.err << "wearknit batch: " << failure << '\n';
      return kExitUsage;
    }
    return kExitOk;
  }

  // One batch at a time runs the whole folder; an array task locks its row.
  const fs::path lock_path =
      row_index >= 0 ? batch_state_dir(dir) /
                           (manifest->rows[static_cast<std::size_t>(row_index)].name + ".lock")
                     : batch_state_dir(dir) / "batch.lock";
  FileLock lock(lock_path);
  if (!lock.held()) {
    context.err << dir.string() << ": error: another wearknit batch is running "
                << (row_index >= 0 ? "this row" : "in this folder") << " (" << lock_path.string()
                << " is locked)\n";
    return kExitUsage;
  }

  const bool quiet = values.count("quiet") != 0;
  int failed = 0;
  if (values.count("collect") == 0) {
    // Each row with its fingerprint, made once (it reads the row's files).
    std::deque<std::pair<const BatchRow*, std::uint64_t>> queue;
    std::size_t skipped = 0;
    for (std::size_t i = 0; i < total; ++i) {
      if (row_index >= 0 && static_cast<int>(i) != row_index) continue;
      const BatchRow& row = manifest->rows[i];
      const auto fingerprint = row_fingerprint(row);
      if (row_done(dir, row, fingerprint)) {
        ++skipped;
        if (!quiet) context.out << "skip " << row.name << ": done with the same inputs\n";
        continue;
      }
      queue.emplace_back(&row, fingerprint.value_or(0));
    }
    const std::size_t to_run = queue.size();
    if (!quiet && to_run > 0) {
      context.out << "batch: " << to_run << " of " << total << " rows to run, " << jobs
                  << " at a time, " << threads << " thread" << (threads == 1 ? "" : "s")
                  << " each\n"
                  << std::flush;
    }
    const std::string binary = self_binary();
    std::map<pid_t, Running> running;
    std::size_t done = 0;
    while (!queue.empty() || !running.empty()) {
      while (!queue.empty() && running.size() < static_cast<std::size_t>(jobs)) {
        const auto [row, fingerprint] = queue.front();
        queue.pop_front();
        Running r;
        r.row = row;
        r.fingerprint = fingerprint;
        r.start = Clock::now();
        RowState state;
        state.status = "running";
        state.fingerprint = r.fingerprint;
        write_row_state(dir, row->name, state);
        r.started = read_row_state(dir, row->name).value_or(RowState{}).started;
        const pid_t pid = start_row(binary, *row, dir, threads);
        if (pid < 0) {
          context.err << "wearknit batch: cannot start a process for row " << row->name << '\n';
          finish_row(dir, r, 127 << 8, ++done, to_run, quiet, context, &failed);
          continue;
        }
        running.emplace(pid, r);
      }
      int status = 0;
      const pid_t pid = ::waitpid(-1, &status, 0);
      if (pid < 0) break;
      const auto it = running.find(pid);
      if (it == running.end()) continue;
      finish_row(dir, it->second, status, ++done, to_run, quiet, context, &failed);
      running.erase(it);
    }
    if (!quiet && skipped > 0 && to_run == 0) {
      context.out << "batch: every row is done with the same inputs\n";
    }
  }

  // A single array task leaves the summary to the collect job.
  if (row_index >= 0) return failed == 0 ? kExitOk : kExitInvalid;
  std::size_t ok = 0;
  const std::string failure = write_batch_summary(dir, *manifest, &ok);
  if (!failure.empty()) {
    context.err << "wearknit batch: " << failure << '\n';
    return kExitUsage;
  }
  context.out << "batch: " << total << " rows, " << ok << " ok, " << total - ok
              << " not ok; summary " << (dir / "batch.csv").string() << ", open "
              << (dir / "index.html").string() << '\n';
  // The collect job has done its work once the summary is written; whether
  // every row passed is in the summary and --status.
  if (values.count("collect") != 0) return kExitOk;
  return ok == total ? kExitOk : kExitInvalid;
}

}  // namespace wearknit::cli
