#include "apps/wearknit/plan_display.hpp"

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <iomanip>
#include <mutex>
#include <sstream>
#include <thread>

namespace wearknit::cli {

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

std::string format_seconds(double seconds) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(seconds < 10 ? 2 : 1) << seconds << " s";
  return text.str();
}

// The first non-empty line of a stage's output, else of its error text.
std::string first_line(const planner::StageRun& s) {
  for (const std::string* text : {&s.out, &s.err}) {
    std::istringstream lines(*text);
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty()) return line;
    }
  }
  return "";
}

// The progress display: on a terminal one status line (the running stages
// and their time) redrawn four times a second, and a line as each stage
// ends; nothing otherwise.
class StageBoard final : public planner::PlanObserver {
 public:
  StageBoard(Context& context, bool live) : context_(context), live_(live) {
    if (!live_) return;
    ticker_ = std::thread([this] {
      std::unique_lock lock(mutex_);
      while (!stopping_) {
        draw_locked();
        wake_.wait_for(lock, std::chrono::milliseconds(250));
      }
    });
  }
  ~StageBoard() override { stop(); }
  StageBoard(const StageBoard&) = delete;
  StageBoard& operator=(const StageBoard&) = delete;

  void stop() {
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    wake_.notify_all();
    if (ticker_.joinable()) ticker_.join();
    std::lock_guard lock(mutex_);
    clear_locked();
  }

  void stage_started(const std::string& name, const std::string&) override {
    std::lock_guard lock(mutex_);
    running_.push_back({name, Clock::now()});
  }

  void stage_finished(const planner::StageRun& run) override {
    std::lock_guard lock(mutex_);
    std::erase_if(running_, [&](const auto& r) { return r.first == run.name; });
    if (!live_) return;
    clear_locked();
    context_.out << std::left << std::setw(22) << run.name
                 << (run.exit_code == 0 ? "done   " : "FAILED ") << std::right << std::fixed
                 << std::setprecision(1) << std::setw(7) << run.seconds << " s\n";
    draw_locked();
  }

 private:
  void clear_locked() {
    if (live_ && line_shown_) context_.out << "\r\033[K" << std::flush;
    line_shown_ = false;
  }

  void draw_locked() {
    if (!live_ || stopping_) return;
    std::ostringstream line;
    line << "plan:";
    for (const auto& [name, start] : running_) {
      line << "  " << name << ' ' << std::fixed << std::setprecision(0)
           << std::chrono::duration<double>(Clock::now() - start).count() << " s...";
    }
    context_.out << "\r\033[K" << line.str() << std::flush;
    line_shown_ = true;
  }

  Context& context_;
  bool live_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::thread ticker_;
  bool stopping_ = false;
  bool line_shown_ = false;
  std::vector<std::pair<std::string, Clock::time_point>> running_;
};

// Which stage failed and what it printed, and where the outputs of the
// stages that finished are.
void report_failure(const planner::PlanResult& result, const std::string& dir, Context& context) {
  std::vector<std::string> finished;
  for (const planner::StageRun& s : result.stages) {
    if (s.exit_code == 0) {
      finished.push_back(s.name);
      continue;
    }
    context.err << "wearknit plan: the " << s.name << " stage failed (exit " << s.exit_code << ")"
                << (s.err.empty() && s.out.empty() ? "" : ":") << '\n';
    std::istringstream lines(s.err.empty() ? s.out : s.err);
    for (std::string line; std::getline(lines, line);) context.err << "  " << line << '\n';
  }
  if (finished.empty()) {
    context.err << "wearknit plan: no stage finished\n";
    return;
  }
  context.err << "wearknit plan: the outputs of ";
  for (std::size_t i = 0; i < finished.size(); ++i) context.err << (i ? ", " : "") << finished[i];
  context.err << " are in " << dir << '\n';
}

// The last stage of `wearknit plan --send URI`: every piece's DAT, one after
// the other (the next is not knit while one failed).
int send_pieces(const std::string& uri, const std::vector<std::string>& dat_paths,
                planner::StageRun& run, json& sent) {
  for (const std::string& job : dat_paths) {
    std::ostringstream out, err;
    Context send_context{out, err, false};
    const int code = send_file(job, uri, {false, 8, true}, send_context);
    run.out += out.str();
    run.err += err.str();
    std::string message = code == kExitOk ? out.str() : err.str();
    if (!message.empty() && message.back() == '\n') message.pop_back();
    const std::string name = std::filesystem::path(job).stem().string();
    sent.push_back({{"piece", name},
                    {"job", "pieces/" + std::filesystem::path(job).filename().string()},
                    {"to", uri},
                    {"exit", code},
                    {"message", message}});
    if (code != kExitOk) return kExitInvalid;
  }
  return kExitOk;
}

}  // namespace

int run_plan_and_report(const planner::PlanInputs& inputs, planner::PlanParams params,
                        const std::string& dir, const PlanRunOptions& options, Context& context) {
  if (!options.send_uri.empty()) {
    params.deliver = [&](const std::vector<std::string>& dat_paths, planner::StageRun& run,
                         json& sent) {
      return send_pieces(options.send_uri, dat_paths, run, sent);
    };
  }
  StageBoard board(context, context.out_is_terminal && !options.quiet);
  const planner::PlanResult result = planner::run_plan(inputs, params, dir, board);
  board.stop();
  if (!result.ok()) {
    report_failure(result, dir, context);
    bool stage_failed = false;
    for (const planner::StageRun& s : result.stages)
      stage_failed = stage_failed || (s.exit_code != 0 && s.name != "plan files");
    return stage_failed ? kExitInvalid : kExitUsage;
  }
  if (options.quiet) return kExitOk;
  context.out << "plan: " << inputs.garment << " on " << inputs.wearer << " -> " << dir << "/\n";
  for (const planner::StageRun& s : result.stages) {
    context.out << "  " << std::left << std::setw(22) << s.name << std::right << std::setw(9)
                << format_seconds(s.seconds) << "  " << first_line(s) << '\n';
  }
  context.out << "  " << std::left << std::setw(22) << "total" << std::right << std::setw(9)
              << format_seconds(result.total_seconds) << "  " << planner::describe(result) << '\n';
  return kExitOk;
}

}  // namespace wearknit::cli
