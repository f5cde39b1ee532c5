// Diagnostics of one kind, capped: the first 10 are reported, then one
// message says how many more there were (mesh_io.cpp, mesh_scan.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <utility>

#include "knitout/diagnostic.hpp"

namespace planner {

class KindReporter {
 public:
  KindReporter(knitout::DiagnosticSink& sink, const std::string& source, std::string code,
               std::string plural)
      : sink_(sink), source_(source), code_(std::move(code)), plural_(std::move(plural)) {}
  // `line` is the file's line (1-based), or 0 where there is none.
  void report(std::string message, std::uint32_t line = 0) {
    ++count_;
    if (count_ <= kMaxShown) sink_.error(source_, line, 0, code_, std::move(message));
  }
  ~KindReporter() {
    if (count_ > kMaxShown) {
      sink_.error(source_, 0, 0, code_,
                  std::to_string(count_ - kMaxShown) + " more " + plural_ + " not listed (" +
                      std::to_string(count_) + " in all)");
    }
  }
  KindReporter(const KindReporter&) = delete;
  KindReporter& operator=(const KindReporter&) = delete;
  int count() const { return count_; }

 private:
  static constexpr int kMaxShown = 10;
  knitout::DiagnosticSink& sink_;
  const std::string& source_;
  std::string code_;
  std::string plural_;
  int count_ = 0;
};

}  // namespace planner
