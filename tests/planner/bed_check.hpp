// A small needle-bed checker for the scheduler's tests: the rules of the
// machine that the planner's knitout must never break (racking range and
// alignment, transfers and knits on empty needles, stack height, the
// carrier's and the hook's life cycle, needle range, nothing left on the back
// bed). It tracks loop counts per needle only; the needle-bed VM
// (simulators/bed) is the full judge.
#pragma once

#include <cmath>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "knitout/program.hpp"

namespace planner::testing {

struct BedCheck {
  std::vector<std::string> errors;
  int knits = 0;
  int tucks = 0;
  int transfers = 0;
  int loops_left = 0;  // loops on the front bed at the end
};

inline BedCheck check_bed(const knitout::Program& program, int needles = 540) {
  using knitout::Op;
  BedCheck result;
  std::map<std::pair<bool, int>, int> loops;  // (back?, index) -> loops
  double racking = 0;
  bool in = false, stitched = false;
  int hook = 0;  // 0 empty, 1 inhook waiting for the first stitch, 2 holding
  auto fail = [&](const knitout::Instruction& i, const std::string& what) {
    result.errors.push_back("line " + std::to_string(i.line) + ": " + what);
  };
  auto needle_ok = [&](const knitout::Instruction& i, knitout::Needle n) {
    if (n.is_slider()) fail(i, "slider used");
    if (n.index < 1 || n.index > needles)
      fail(i, "needle " + knitout::to_string(n) + " off the bed");
  };
  for (const auto& i : program.instructions) {
    switch (i.op) {
      case Op::Inhook:
        if (in) fail(i, "inhook of a carrier that is in");
        in = true;
        stitched = false;
        hook = 1;
        break;
      case Op::Releasehook:
        if (hook != 2) fail(i, "releasehook while the hook holds nothing");
        hook = 0;
        break;
      case Op::Outhook:
        if (!in) fail(i, "outhook of a carrier that is out");
        if (!stitched) fail(i, "outhook of a carrier that never stitched");
        if (hook != 0) fail(i, "outhook while the hook holds the yarn");
        in = false;
        break;
      case Op::Rack:
        racking = i.value[0];
        if (std::abs(racking) > 8 || racking != std::floor(racking)) fail(i, "bad racking");
        break;
      case Op::Knit:
      case Op::Tuck: {
        needle_ok(i, i.needle);
        if (!in || i.carriers.empty()) fail(i, "stitch without a carrier in");
        if (hook == 1) hook = 2;
        stitched = true;
        int& n = loops[{i.needle.is_back(), i.needle.index}];
        if (i.op == Op::Knit) {
          if (n == 0) fail(i, "knit on an empty needle");
          n = 1;
          ++result.knits;
        } else {
          ++n;
          ++result.tucks;
        }
        if (n > 4) fail(i, "more than four loops on a needle");
        break;
      }
      case Op::Xfer: {
        needle_ok(i, i.needle);
        needle_ok(i, i.needle2);
        if (i.needle.is_back() == i.needle2.is_back()) fail(i, "xfer on one bed");
        const int f = i.needle.is_back() ? i.needle2.index : i.needle.index;
        const int b = i.needle.is_back() ? i.needle.index : i.needle2.index;
        if (f != b + static_cast<int>(racking)) fail(i, "xfer needles not aligned");
        int& from = loops[{i.needle.is_back(), i.needle.index}];
        int& to = loops[{i.needle2.is_back(), i.needle2.index}];
        if (from == 0) fail(i, "xfer from an empty needle");
        to += from;
        from = 0;
        if (to > 4) fail(i, "more than four loops on a needle");
        ++result.transfers;
        break;
      }
      case Op::Drop:
        loops[{i.needle.is_back(), i.needle.index}] = 0;
        break;
      case Op::Comment:
        break;
      default:
        fail(i, "unexpected operation");
    }
  }
  if (in) result.errors.push_back("end: the carrier is still in");
  for (const auto& [key, n] : loops) {
    if (key.first && n > 0) result.errors.push_back("end: loops left on the back bed");
    if (!key.first) result.loops_left += n;
  }
  return result;
}

}  // namespace planner::testing
