// The progress of `wearknit send` (and of `wearknit plan --send`) on the
// terminal: a bar on a terminal, a plain line at most once a second
// otherwise, and the states an operator must act on even with --quiet.
#pragma once

#include <cstdint>
#include <string>

#include "apps/wearknit/cli.hpp"
#include "devices/sender.hpp"

namespace wearknit::cli {

// Rows per second over a sliding start point; ETA from the phase's rate.
class ProgressPrinter {
 public:
  ProgressPrinter(Context& context, bool quiet, std::string uri)
      : context_(context), quiet_(quiet), uri_(std::move(uri)) {}

  void update(const devices::Progress& p, const std::string& note);
  // Shows the final counters (on a terminal the bar may lag by 0.1 s).
  void finish(const devices::Progress& p);
  void end_bar();

 private:
  double eta(const devices::Progress& p, double now) const;
  void draw_bar(const devices::Progress& p, double now);

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

}  // namespace wearknit::cli
