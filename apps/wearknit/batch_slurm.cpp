#include "apps/wearknit/batch_slurm.hpp"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <sstream>
#include <system_error>
#include <tuple>
#include <utility>

extern char** environ;

namespace wearknit::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path state_dir(const std::string& dir) {
  return fs::path(dir) / ".batch";
}

// For the command lines of the scripts: a word the shell takes as is.
std::string shell_quote(const std::string& word) {
  std::string quoted = "'";
  for (const char c : word) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

// sbatch reads an #SBATCH line up to the first blank, and takes % in
// --output as a pattern: values with those cannot be carried there.
std::string check_sbatch_value(const std::string& what, const std::string& value,
                               bool is_output_path) {
  for (const char c : value) {
    const bool blank = c == ' ' || c == '\t' || c == '\n' || c == '\r';
    if (blank || c == '"' || c == '\'' || c == '\\' || (is_output_path && c == '%')) {
      return what + " '" + value +
             "' has a blank, a quote, a backslash or a % that an #SBATCH line cannot carry";
    }
  }
  return "";
}

// A job name from DIR's last component: letters, digits, '.', '_', '-'.
std::string job_name(const std::string& dir) {
  std::string name = fs::path(dir).lexically_normal().filename().string();
  if (name.empty()) name = fs::path(dir).lexically_normal().parent_path().filename().string();
  for (char& c : name) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '.' || c == '_' || c == '-';
    if (!plain) c = '_';
  }
  return "wearknit-" + (name.empty() ? std::string("batch") : name);
}

// Writes `content` to `path` through a temporary file and a rename.
std::string write_text(const fs::path& path, const std::string& content) {
  const fs::path tmp = path.string() + ".tmp";
  {
    std::ofstream file(tmp, std::ios::binary | std::ios::trunc);
    file << content;
    file.close();
    if (!file) return "cannot write " + tmp.string();
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) return "cannot write " + path.string() + ": " + ec.message();
  return "";
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  ::gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return "";
  const auto last = text.find_last_not_of(" \t\r\n");
  return text.substr(first, last - first + 1);
}

// The first line of a command's stderr (else stdout), for messages.
std::string first_line(const CommandOutput& result) {
  std::string text = trim(result.err);
  if (text.empty()) text = trim(result.out);
  const auto newline = text.find('\n');
  if (newline != std::string::npos) text = text.substr(0, newline);
  return text.empty() ? "exit " + std::to_string(result.exit_code) : text;
}

// Submits `script` with `sbatch --parsable`; the job id, or the error.
std::string sbatch(const fs::path& script, std::string* job_id) {
  const CommandOutput result = run_command({"sbatch", "--parsable", script.string()});
  if (!result.error.empty()) return result.error;
  if (result.exit_code != 0) return "sbatch " + script.string() + ": " + first_line(result);
  // --parsable prints "ID" or "ID;CLUSTER".
  std::string id = trim(result.out);
  id = id.substr(0, id.find(';'));
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos) {
    return "sbatch " + script.string() + ": unexpected output '" + trim(result.out) + "'";
  }
  *job_id = id;
  return "";
}

// The #SBATCH lines both scripts share.
std::string common_lines(const SlurmOptions& o) {
  std::string text;
  text += "#SBATCH --chdir=" + o.dir + "\n";
  if (!o.partition.empty()) text += "#SBATCH --partition=" + o.partition + "\n";
  if (!o.time_limit.empty()) text += "#SBATCH --time=" + o.time_limit + "\n";
  return text;
}

std::string write_record(const SlurmOptions& o, const std::string& array_id,
                         const std::string& collect_id) {
  json record = {{"array_job", array_id},
                 {"collect_job", collect_id},
                 {"rows", o.rows},
                 {"throttle", o.throttle},
                 {"manifest", o.manifest},
                 {"wearknit", o.wearknit},
                 {"partition", o.partition},
                 {"time", o.time_limit},
                 {"cpus_per_task", o.cpus_per_task},
                 {"mem", o.mem},
                 {"threads", o.threads},
                 {"submitted", utc_now()}};
  return write_text(state_dir(o.dir) / "slurm.json", record.dump(2) + "\n");
}

// A job's state as squeue or sacct gives it ("CANCELLED by 0" -> CANCELLED).
struct JobStates {
  std::map<int, std::string> tasks;  // the array's, by task index
  std::string collect;               // the collect job's; "" when not listed
  std::string collect_reason;        // squeue's %R
};

// Adds the tasks named by `id` ("5_3", "5_[2-7%2]", "5_[1,4-6]") or the
// collect job ("6") with `state`.
void add_state(const std::string& id, const std::string& state, const std::string& reason,
               const std::string& array_id, const std::string& collect_id, JobStates* states) {
  if (id == collect_id) {
    states->collect = state;
    states->collect_reason = reason;
    return;
  }
  const std::string prefix = array_id + "_";
  if (id.rfind(prefix, 0) != 0) return;
  std::string tasks = id.substr(prefix.size());
  if (!tasks.empty() && tasks.front() == '[') {
    tasks = tasks.substr(1, tasks.find(']') - 1);
    tasks = tasks.substr(0, tasks.find('%'));
  }
  std::stringstream ranges(tasks);
  std::string range;
  while (std::getline(ranges, range, ',')) {
    const auto dash = range.find('-');
    try {
      const int first = std::stoi(range.substr(0, dash));
      const int last = dash == std::string::npos ? first : std::stoi(range.substr(dash + 1));
      for (int task = first; task <= last; ++task) states->tasks[task] = state;
    } catch (const std::exception&) {
      // Not a task list: an id of another form, ignored.
    }
  }
}

bool is_pending(const std::string& state) {
  return state == "PENDING" || state == "REQUEUED";
}
bool is_running(const std::string& state) {
  return state == "RUNNING" || state == "CONFIGURING" || state == "COMPLETING" ||
         state == "SUSPENDED" || state == "RESIZING" || state == "SIGNALING" ||
         state == "STAGE_OUT";
}

}  // namespace

CommandOutput run_command(const std::vector<std::string>& argv) {
  CommandOutput result;
  int out_pipe[2];
  int err_pipe[2];
  if (::pipe2(out_pipe, O_CLOEXEC) != 0) {
    result.error = std::string("cannot create a pipe: ") + std::strerror(errno);
    return result;
  }
  if (::pipe2(err_pipe, O_CLOEXEC) != 0) {
    result.error = std::string("cannot create a pipe: ") + std::strerror(errno);
    ::close(out_pipe[0]);
    ::close(out_pipe[1]);
    return result;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], 1);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], 2);
  std::vector<std::string> args = argv;
  std::vector<char*> pointers;
  for (std::string& arg : args) pointers.push_back(arg.data());
  pointers.push_back(nullptr);
  pid_t pid = -1;
  const int spawned =
      ::posix_spawnp(&pid, pointers[0], &actions, nullptr, pointers.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  if (spawned != 0) {
    ::close(out_pipe[0]);
    ::close(err_pipe[0]);
    result.error = spawned == ENOENT
                       ? "'" + argv[0] + "' is not on the PATH: is Slurm's client installed here?"
                       : "cannot run " + argv[0] + ": " + std::strerror(spawned);
    return result;
  }
  // Both pipes at once, so that a child filling one is not blocked.
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&result.out, &result.err};
  int open_pipes = 2;
  while (open_pipes > 0) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      char buffer[4096];
      const ssize_t n = ::read(fds[i].fd, buffer, sizeof buffer);
      if (n > 0) {
        sinks[i]->append(buffer, static_cast<std::size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open_pipes;
      }
    }
  }
  for (const pollfd& fd : fds) {
    if (fd.fd >= 0) ::close(fd.fd);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

std::string slurm_array_script(const SlurmOptions& o) {
  std::string text = "#!/bin/sh\n";
  text += "# wearknit batch: one array task per manifest row (written by wearknit batch --slurm)\n";
  text += "#SBATCH --job-name=" + job_name(o.dir) + "\n";
  text += "#SBATCH --array=0-" + std::to_string(o.rows - 1);
  if (o.throttle > 0) text += "%" + std::to_string(o.throttle);
  text += "\n";
  text += "#SBATCH --output=" + (state_dir(o.dir) / "slurm-%A_%a.out").string() + "\n";
  text += common_lines(o);
  if (!o.cpus_per_task.empty()) text += "#SBATCH --cpus-per-task=" + o.cpus_per_task + "\n";
  if (!o.mem.empty()) text += "#SBATCH --mem=" + o.mem + "\n";
  text += "exec " + shell_quote(o.wearknit) + " batch " + shell_quote(o.manifest) + " -o " +
          shell_quote(o.dir) + " --row \"$SLURM_ARRAY_TASK_ID\"";
  if (o.threads > 0) text += " --threads " + std::to_string(o.threads);
  return text + "\n";
}

std::string slurm_collect_script(const SlurmOptions& o, const std::string& array_job_id) {
  std::string text = "#!/bin/sh\n";
  text += "# wearknit batch: the summary, once every array task has ended\n";
  text += "#SBATCH --job-name=" + job_name(o.dir) + "-collect\n";
  text += "#SBATCH --dependency=afterany:" + array_job_id + "\n";
  text += "#SBATCH --kill-on-invalid-dep=no\n";
  text += "#SBATCH --output=" + (state_dir(o.dir) / "slurm-collect-%j.out").string() + "\n";
  text += common_lines(o);
  text += "exec " + shell_quote(o.wearknit) + " batch " + shell_quote(o.manifest) + " -o " +
          shell_quote(o.dir) + " --collect\n";
  return text;
}

std::string slurm_submit(const SlurmOptions& o, std::string* array_job_id,
                         std::string* collect_job_id) {
  if (o.rows <= 0) return "the manifest has no rows: nothing to submit";
  for (const auto& [what, path] :
       {std::pair{"the binary", &o.wearknit}, std::pair{"the manifest", &o.manifest},
        std::pair{"the output folder", &o.dir}}) {
    if (!fs::path(*path).is_absolute())
      return std::string(what) + " '" + *path + "' is not absolute";
  }
  for (const auto& [what, value, is_path] :
       {std::tuple{"the output folder", &o.dir, true},
        std::tuple{"--partition", &o.partition, false}, std::tuple{"--time", &o.time_limit, false},
        std::tuple{"--cpus-per-task", &o.cpus_per_task, false},
        std::tuple{"--mem", &o.mem, false}}) {
    const std::string problem = check_sbatch_value(what, *value, is_path);
    if (!problem.empty()) return problem;
  }
  const fs::path state = state_dir(o.dir);
  std::error_code ec;
  fs::create_directories(state, ec);
  if (ec) return "cannot create " + state.string() + ": " + ec.message();

  const fs::path array_script = state / "slurm-array.sh";
  std::string problem = write_text(array_script, slurm_array_script(o));
  if (!problem.empty()) return problem;
  std::string array_id;
  problem = sbatch(array_script, &array_id);
  if (!problem.empty()) return problem;
  *array_job_id = array_id;

  const fs::path collect_script = state / "slurm-collect.sh";
  std::string collect_id;
  problem = write_text(collect_script, slurm_collect_script(o, array_id));
  if (problem.empty()) problem = sbatch(collect_script, &collect_id);
  *collect_job_id = collect_id;
  // The record is written even when the collect job failed: the array runs.
  const std::string recorded = write_record(o, array_id, collect_id);
  if (!problem.empty()) {
    return problem + " (array job " + array_id + " is submitted; `wearknit batch --collect` " +
           "writes the summary once it has ended)";
  }
  return recorded;
}

std::string slurm_status(const std::string& dir, std::ostream& out,
                         const SlurmRowStatus& row_status) {
  const fs::path record_path = state_dir(dir) / "slurm.json";
  std::ifstream record_file(record_path);
  if (!record_file) return "no Slurm submission in " + dir + " (" + record_path.string() + ")";
  json record;
  try {
    record_file >> record;
  } catch (const json::exception& e) {
    return record_path.string() + ": " + e.what();
  }
  const std::string array_id = record.value("array_job", "");
  const std::string collect_id = record.value("collect_job", "");
  const int rows = record.value("rows", 0);
  if (array_id.empty()) return record_path.string() + ": no array job id";

  std::string ids = array_id;
  if (!collect_id.empty()) ids += "," + collect_id;
  JobStates states;
  // sacct first (it keeps every job's end), then squeue, which knows the live
  // ones best; without accounting storage sacct fails and squeue alone
  // speaks, forgetting a job MinJobAge seconds after its end.
  const CommandOutput sacct =
      run_command({"sacct", "-n", "-P", "-X", "-j", ids, "-o", "JobID,State"});
  const bool have_sacct = sacct.error.empty() && sacct.exit_code == 0;
  if (have_sacct) {
    std::stringstream lines(sacct.out);
    std::string line;
    while (std::getline(lines, line)) {
      const auto bar = line.find('|');
      if (bar == std::string::npos) continue;
      std::string state = line.substr(bar + 1);
      state = state.substr(0, state.find(' '));
      add_state(line.substr(0, bar), trim(state), "", array_id, collect_id, &states);
    }
  }
  const CommandOutput squeue =
      run_command({"squeue", "-h", "-r", "-t", "all", "-j", ids, "-o", "%i %T %R"});
  if (!squeue.error.empty()) return squeue.error;
  // squeue fails with "Invalid job id specified" once no job is left.
  if (squeue.exit_code != 0 && squeue.err.find("Invalid job id") == std::string::npos) {
    return "squeue: " + first_line(squeue);
  }
  std::stringstream lines(squeue.out);
  std::string line;
  while (std::getline(lines, line)) {
    std::stringstream words(line);
    std::string id, state, reason;
    words >> id >> state;
    std::getline(words, reason);
    add_state(id, state, trim(reason), array_id, collect_id, &states);
  }

  int pending = 0, running = 0, completed = 0, failed = 0, gone = 0;
  std::map<std::string, int> failures;
  for (int task = 0; task < rows; ++task) {
    const auto found = states.tasks.find(task);
    if (found == states.tasks.end()) {
      ++gone;
    } else if (is_pending(found->second)) {
      ++pending;
    } else if (is_running(found->second)) {
      ++running;
    } else if (found->second == "COMPLETED") {
      ++completed;
    } else {
      ++failed;
      ++failures[found->second];
    }
  }
  out << "array job " << array_id << ": " << rows << " tasks, " << pending << " pending, "
      << running << " running, " << completed + failed + gone << " done (" << completed
      << " completed, " << failed << " failed";
  // The scheduler's own words for the tasks that did not complete, when more
  // than one kind (FAILED, TIMEOUT, NODE_FAIL, CANCELLED, ...).
  if (failures.size() > 1) {
    for (const auto& [state, count] : failures) out << ", " << count << ' ' << state;
  } else if (failures.size() == 1) {
    out << ": " << failures.begin()->first;
  }
  if (gone > 0) {
    out << ", " << gone << " ended and no longer listed"
        << (have_sacct ? "" : " (no accounting here: see the rows)");
  }
  out << ")\n";
  if (collect_id.empty()) {
    out << "collect job: not submitted (`wearknit batch MANIFEST -o DIR --collect` writes the "
           "summary)\n";
  } else if (states.collect.empty()) {
    out << "collect job " << collect_id << ": ended and no longer listed\n";
  } else {
    out << "collect job " << collect_id << ": " << states.collect;
    if (is_pending(states.collect) && !states.collect_reason.empty()) {
      out << ' ' << states.collect_reason;
    }
    out << '\n';
  }
  if (row_status) {
    int ok = 0, row_failed = 0, row_running = 0, not_done = 0;
    for (int row = 0; row < rows; ++row) {
      const std::string status = row_status(row);
      if (status == "ok") {
        ++ok;
      } else if (status == "failed") {
        ++row_failed;
      } else if (status == "running") {
        ++row_running;
      } else {
        ++not_done;
      }
    }
    // A row still "running" when no task runs was cut short (a node lost, a
    // time limit): running the batch again runs it again.
    out << "rows: " << ok << " ok, " << row_failed << " failed, " << row_running
        << (running > 0 ? " running, " : " unfinished, ") << not_done << " not run\n";
  }
  return "";
}

}  // namespace wearknit::cli
