// wearknit send: send a job to a machine, with progress, reconnection and
// resume.
#include <chrono>
#include <cstdio>
#include <iostream>

#include "apps/wearknit/cli.hpp"
#include "devices/folder_drop.hpp"
#include "devices/sender.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

namespace {

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string clock_text(double seconds) {
  if (!(seconds >= 0) || seconds > 360000) return "--:--";
  const long s = static_cast<long>(seconds + 0.5);
  char text[32];
  if (s >= 3600) {
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  } else {
    std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  }
  return text;
}

// Rows per second over a sliding start point; ETA from the phase's rate.
class ProgressPrinter {
 public:
  ProgressPrinter(Context& context, bool quiet, std::string uri)
      : context_(context), quiet_(quiet), uri_(std::move(uri)) {}

  void update(const devices::Progress& p, const std::string& note) {
    const double now = seconds_now();
    if (!note.empty()) {
      end_bar();
      context_.err << "wearknit send: " << note << '\n';
    }
    if (p.device_state != last_state_) {
      // The operator must act on these; say so even with --quiet.
      if (p.device_state == devices::JobState::Alarm) {
        end_bar();
        context_.err << "wearknit send: the machine stopped (" << devices::to_string(p.alarm)
                     << ") after row " << p.rows_knitted << " of " << p.rows_total
                     << "; clear it and run `wearknit status --to " << uri_ << " --continue`\n";
      } else if (p.device_state == devices::JobState::Paused) {
        end_bar();
        context_.err << "wearknit send: the job is paused at the machine after row "
                     << p.rows_knitted << "; `wearknit status --to " << uri_
                     << " --continue` resumes it\n";
      }
      last_state_ = p.device_state;
    }
    if (quiet_) return;
    if (start_ < 0) start_ = now;
    if (knit_start_ < 0 && p.rows_knitted > 0) {
      knit_start_ = now;
      knit_start_rows_ = p.rows_knitted;
    }
    const bool changed = p.rows_received != last_.rows_received ||
                         p.rows_knitted != last_.rows_knitted || p.phase != last_.phase;
    if (context_.out_is_terminal) {
      if (!changed || now - last_print_ < 0.1) return;
      draw_bar(p, now);
    } else {
      // Plain lines: at most one a second, plus every phase change.
      if (!changed || (now - last_print_ < 1.0 && p.phase == last_.phase)) return;
      context_.out << "progress: " << devices::to_string(p.phase) << ", " << p.rows_received << "/"
                   << p.rows_total << " rows received, " << p.rows_knitted << "/" << p.rows_total
                   << " knitted, ETA " << clock_text(eta(p, now)) << '\n';
      context_.out.flush();
    }
    last_ = p;
    last_print_ = now;
  }

  // Shows the final counters (on a terminal the bar may lag by 0.1 s).
  void finish(const devices::Progress& p) {
    if (!quiet_ && context_.out_is_terminal) draw_bar(p, seconds_now());
    end_bar();
  }

  void end_bar() {
    if (bar_shown_) {
      context_.out << '\n';
      context_.out.flush();
      bar_shown_ = false;
    }
  }

 private:
  double eta(const devices::Progress& p, double now) const {
    if (p.rows_total == 0) return -1;
    const std::uint32_t left = p.rows_total - std::min(p.rows_knitted, p.rows_total);
    if (knit_start_ >= 0 && now > knit_start_ && p.rows_knitted > knit_start_rows_) {
      return left / ((p.rows_knitted - knit_start_rows_) / (now - knit_start_));
    }
    if (now > start_ && p.rows_received > 0) {
      // Before knitting starts, assume the machine keeps the link's pace.
      return (2.0 * p.rows_total - p.rows_received) / (p.rows_received / (now - start_));
    }
    return -1;
  }

  void draw_bar(const devices::Progress& p, double now) {
    constexpr int kWidth = 30;
    const double knitted = p.rows_total ? double(p.rows_knitted) / p.rows_total : 0;
    const double received = p.rows_total ? double(p.rows_received) / p.rows_total : 0;
    std::string bar(kWidth, '.');
    for (int i = 0; i < kWidth; ++i) {
      if (i < static_cast<int>(received * kWidth)) bar[static_cast<std::size_t>(i)] = '-';
      if (i < static_cast<int>(knitted * kWidth)) bar[static_cast<std::size_t>(i)] = '#';
    }
    context_.out << "\r[" << bar << "] " << p.rows_knitted << "/" << p.rows_total
                 << " rows knitted (" << p.rows_received << " received) "
                 << devices::to_string(p.phase) << "  ETA " << clock_text(eta(p, now)) << "   ";
    context_.out.flush();
    bar_shown_ = true;
  }

  Context& context_;
  bool quiet_;
  std::string uri_;
  devices::JobState last_state_ = devices::JobState::Idle;
  devices::Progress last_;
  double last_print_ = -1e9;
  double start_ = -1;
  double knit_start_ = -1;
  std::uint32_t knit_start_rows_ = 0;
  bool bar_shown_ = false;
};

}  // namespace

int run_send(const std::vector<std::string>& args, Context& context) {
  std::string job_path;
  std::string to;
  int attempts = 8;
  po::options_description options("options");
  options.add_options()("job", po::value<std::string>(&job_path)->required(),
                        "DAT (.dat) or knitout (.k) file")(
      "to", po::value<std::string>(&to)->required(),
      "tcp://HOST:PORT, serial:PATH[?baud=N], usb://VID:PID[/SERIAL], dir:PATH or loopback:")(
      "resume", "finish this job where the device left it")(
      "attempts", po::value<int>(&attempts)->default_value(8),
      "reconnection attempts in a row before giving up")("quiet,q", "no progress output");
  po::positional_options_description positional;
  positional.add("job", 1);
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("send"), options, positional, values, context)) {
    return *code;
  }
  return send_file(job_path, to,
                   {values.count("resume") != 0, attempts, values.count("quiet") != 0}, context);
}

int send_file(const std::string& job_path, const std::string& to, const SendFileOptions& options,
              Context& context) {
  auto uri = devices::parse_uri(to);
  if (!uri) {
    context.err << "wearknit send: " << uri.error().text() << '\n';
    return kExitUsage;
  }
  auto job = devices::load_job(job_path);
  if (!job) {
    context.err << "wearknit send: " << job.error().text() << '\n';
    return job.error().error_class == devices::ErrorClass::OsFailure ? kExitUsage : kExitInvalid;
  }
  if (uri.value().kind == devices::DeviceUri::Kind::Dir) {
    devices::Outcome stored = devices::deliver_to_folder(job.value(), uri.value().path);
    if (!stored) {
      context.err << "wearknit send: " << stored.error().text() << '\n';
      return kExitUsage;
    }
    context.out << "stored " << uri.value().path << "/" << job.value().name << " ("
                << job.value().bytes.size() << " bytes, " << job.value().row_count()
                << " rows, read back with SHA-256 " << devices::to_hex(job.value().sha256) << ")\n";
    return kExitOk;
  }
  devices::SendOptions send_options;
  send_options.resume = options.resume;
  devices::LinkOptions link;
  link.max_attempts = std::max(options.attempts, 0);
  link.loopback_checkers = project_job_checkers();
  ProgressPrinter printer(context, options.quiet, to);
  auto report = devices::send_job(
      uri.value(), job.value(), send_options, link,
      [&](const devices::Progress& p, const std::string& note) { printer.update(p, note); });
  if (report) {
    printer.finish(report.value().progress);
  } else {
    printer.end_bar();
  }
  if (!report) {
    context.err << "wearknit send: " << job_path << ": " << report.error().text() << '\n';
    return kExitUsage;
  }
  const devices::SendReport& r = report.value();
  if (!r.done) {
    context.err << "wearknit send: " << job_path << ": " << r.message << '\n';
    return kExitInvalid;
  }
  if (!r.message.empty()) context.out << r.message << '\n';
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.2f", r.seconds);
  context.out << "done: " << job.value().name << " -> " << to << ": " << r.progress.rows_knitted
              << "/" << r.progress.rows_total << " rows knitted (device confirmed), "
              << r.reconnects << " reconnects, " << seconds << " s\n";
  return kExitOk;
}

}  // namespace wearknit::cli
