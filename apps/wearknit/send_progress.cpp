// The progress of `wearknit send` (send_progress.hpp).
#include "apps/wearknit/send_progress.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace wearknit::cli {

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

}  // namespace

void ProgressPrinter::update(const devices::Progress& p, const std::string& note) {
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
      context_.err << "wearknit send: the job is paused at the machine after row " << p.rows_knitted
                   << "; `wearknit status --to " << uri_ << " --continue` resumes it\n";
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

void ProgressPrinter::finish(const devices::Progress& p) {
  if (!quiet_ && context_.out_is_terminal) draw_bar(p, seconds_now());
  end_bar();
}

void ProgressPrinter::end_bar() {
  if (bar_shown_) {
    context_.out << '\n';
    context_.out.flush();
    bar_shown_ = false;
  }
}

double ProgressPrinter::eta(const devices::Progress& p, double now) const {
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

void ProgressPrinter::draw_bar(const devices::Progress& p, double now) {
  constexpr int kWidth = 30;
  const double knitted = p.rows_total ? double(p.rows_knitted) / p.rows_total : 0;
  const double received = p.rows_total ? double(p.rows_received) / p.rows_total : 0;
  std::string bar(kWidth, '.');
  for (int i = 0; i < kWidth; ++i) {
    if (i < static_cast<int>(received * kWidth)) bar[static_cast<std::size_t>(i)] = '-';
    if (i < static_cast<int>(knitted * kWidth)) bar[static_cast<std::size_t>(i)] = '#';
  }
  context_.out << "\r[" << bar << "] " << p.rows_knitted << "/" << p.rows_total << " rows knitted ("
               << p.rows_received << " received) " << devices::to_string(p.phase) << "  ETA "
               << clock_text(eta(p, now)) << "   ";
  context_.out.flush();
  bar_shown_ = true;
}

}  // namespace wearknit::cli
