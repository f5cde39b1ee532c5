#include "backends/dat/reader.hpp"

#include <algorithm>
#include <cmath>

#include "backends/dat/raster.hpp"

namespace dat {

namespace {

using knitout::Direction;

constexpr int kLeftOptionBase = kLeftSpace - 5;
constexpr int kFirstPassRow = kBottomSpace + kFixedCourses;
constexpr int kLayoutRows = kTopSpace + kBottomSpace + 2 * kFixedCourses;

std::string format_racking(double racking) {
  std::string text = std::to_string(racking);
  while (!text.empty() && text.back() == '0') text.pop_back();
  if (!text.empty() && text.back() == '.') text.pop_back();
  return text;
}

}  // namespace

std::int64_t carrier_code(const Pass& pass) {
  const CarrierSet& cs = pass.carriers;
  if (cs.size == 0) return pass.type == PassType::KnitTuck ? 255 : 0;
  if (cs.size == 1) return cs.ids[0];
  // Two carriers: their digits, leading carrier first; carrier 10 counts as
  // "1" in the lead and as "0" when it follows, except after carrier 1.
  const std::int64_t a = cs.ids[0];
  const std::int64_t b = cs.ids[1];
  if (a == 10) return b == 10 ? 110 : 10 + b;
  if (b == 10 && a != 1) return a * 10;
  return b == 10 ? 110 : a * 10 + b;
}

std::string carrier_code_text(int code) {
  if (code == 0 || code == 255) return "-";
  if (code <= 10) return std::to_string(code);
  if (code == 110) return "1 10";
  if (code < 100) {
    const int a = code / 10;
    const int b = code % 10;
    if (b == 0) return std::to_string(a) + " 10";
    if (a == 1) return "1 " + std::to_string(b) + "|10 " + std::to_string(b);
    return std::to_string(a) + " " + std::to_string(b);
  }
  return "code " + std::to_string(code);
}

std::string colour_name(std::uint8_t colour) {
  switch (colour) {
    case 51:
      return "knit-front";
    case 52:
      return "knit-back";
    case 11:
      return "tuck-front";
    case 12:
      return "tuck-back";
    case 216:
      return "miss-front";
    case 217:
      return "miss-back";
    case 16:
      return "miss";
    case 3:
      return "knit-front-knit-back";
    case 41:
      return "knit-front-tuck-back";
    case 42:
      return "tuck-front-knit-back";
    case 88:
      return "tuck-front-tuck-back";
    case 20:
      return "xfer-to-back";
    case 30:
      return "xfer-to-front";
    case 101:
      return "split-to-back";
    case 102:
      return "split-to-front";
    case 106:
    case 107:
    case 126:
    case 127:
    case 146:
    case 147:
      return "split-front-via-slider-" + std::string(colour % 2 == 0 ? "L" : "R") +
             std::to_string(colour < 120   ? 1
                            : colour < 140 ? 2
                                           : 4);
    case 108:
    case 109:
    case 128:
    case 129:
    case 148:
    case 149:
      return "split-back-via-slider-" + std::string(colour % 2 == 0 ? "L" : "R") +
             std::to_string(colour < 120   ? 1
                            : colour < 140 ? 2
                                           : 4);
    default:
      return "colour " + std::to_string(colour);
  }
}

std::optional<DatLayout> read_layout(const Raster& raster, std::string_view source,
                                     knitout::DiagnosticSink& sink) {
  if (raster.width < kLeftSpace + kRightSpace + 1 || raster.height < kLayoutRows) {
    sink.error(source, 0, 0, "D046",
               "a " + std::to_string(raster.width) + " x " + std::to_string(raster.height) +
                   " raster is too small for the swg091n2 layout (at least " +
                   std::to_string(kLeftSpace + kRightSpace + 1) + " x " +
                   std::to_string(kLayoutRows) + ")");
    return std::nullopt;
  }
  DatLayout layout;
  layout.width = raster.width;
  layout.height = raster.height;
  layout.slots = raster.width - kLeftSpace - kRightSpace;
  layout.position =
      raster.at(kPositionColumn, raster.height - kTopSpace + 1) +
      100 * static_cast<std::int64_t>(raster.at(kPositionColumn, raster.height - kTopSpace + 2));
  const int right_base = kLeftSpace + layout.slots + 4;
  const int last_pass_row = raster.height - kLayoutRows + kFirstPassRow - 1;
  for (int y = kFirstPassRow; y <= last_pass_row; ++y) {
    DecodedPass pass;
    pass.row = y;
    for (int o = 2; o <= 20; ++o) {
      if (raster.at(kLeftOptionBase - 2 * o + 1, y) != o ||
          raster.at(right_base + 2 * o - 1, y) != o) {
        sink.error(source, 0, 0, "D046",
                   "row " + std::to_string(y) + " (pass " + std::to_string(y - kFirstPassRow + 1) +
                       ") has no option lines where the swg091n2 layout puts them");
        return std::nullopt;
      }
    }
    for (int o = 1; o <= 20; ++o) {
      pass.left[static_cast<std::size_t>(o)] = raster.at(kLeftOptionBase - 2 * o, y);
      pass.right[static_cast<std::size_t>(o)] = raster.at(right_base + 2 * o, y);
    }
    const std::uint8_t mark = raster.at(kLeftOptionBase - 1, y);
    pass.direction = mark == 6 ? Direction::Plus : mark == 7 ? Direction::Minus : Direction::None;
    const double quarter = pass.left[3] != 0 ? 0.25 : 0.0;
    pass.racking = pass.left[4] == 11 ? pass.left[2] + 1.0 + quarter : -pass.left[2] + quarter;
    for (int x = kLeftSpace; x < kLeftSpace + layout.slots; ++x) {
      const std::uint8_t colour = raster.at(x, y);
      if (colour != 0 && colour != kStopMark) pass.ops.emplace_back(x - kLeftSpace, colour);
    }
    layout.passes.push_back(std::move(pass));
  }
  return layout;
}

std::vector<std::string> compare_passes(const PassList& list, const DatLayout& layout) {
  std::vector<std::string> problems;
  if (list.passes.size() != layout.passes.size()) {
    problems.push_back("the DAT holds " + std::to_string(layout.passes.size()) +
                       " passes, the program forms " + std::to_string(list.passes.size()));
    return problems;
  }
  std::int64_t min_slot = list.passes.empty() ? 0 : list.passes.front().min_slot;
  for (const Pass& pass : list.passes) min_slot = std::min(min_slot, pass.min_slot);
  for (std::size_t i = 0; i < list.passes.size() && problems.size() < 20; ++i) {
    const Pass& pass = list.passes[i];
    const DecodedPass& got = layout.passes[i];
    const std::string where = "pass " + std::to_string(i + 1) + " (line " +
                              std::to_string(pass.line) + ", row " + std::to_string(got.row) + ")";
    const bool directed = pass.direction != Direction::None;
    const bool xfer = pass.type == PassType::Xfer || pass.type == PassType::XferToSliders ||
                      pass.type == PassType::XferFromSliders || pass.type == PassType::Split ||
                      pass.type == PassType::SplitViaSliders;
    if ((directed && got.direction != pass.direction) ||
        (!directed && xfer && got.direction != Direction::None)) {
      problems.push_back(where + ": direction " + knitout::direction_char(got.direction) +
                         ", expected " + knitout::direction_char(pass.direction));
    }
    if (got.carriers() != (carrier_code(pass) & 0xFF)) {
      problems.push_back(where + ": carriers " + carrier_code_text(got.carriers()) + ", expected " +
                         to_string(pass.carriers));
    }
    if (got.racking != pass.racking) {
      problems.push_back(where + ": racking " + format_racking(got.racking) + ", expected " +
                         format_racking(pass.racking));
    }
    if (got.stitch() != (pass.stitch & 0xFF)) {
      problems.push_back(where + ": stitch number " + std::to_string(got.stitch()) + ", expected " +
                         std::to_string(pass.stitch));
    }
    const std::int64_t speed = pass.speed == 0 ? 0 : pass.speed + 10;
    if (got.left[5] != (speed & 0xFF)) {
      problems.push_back(where + ": speed " + std::to_string(got.speed()) + ", expected " +
                         std::to_string(pass.speed));
    }
    std::vector<std::pair<int, std::uint8_t>> expected;
    const auto colours = pass.type == PassType::SplitViaSliders
                             ? split_via_sliders_colours(pass)
                             : std::optional<std::pair<std::uint8_t, std::uint8_t>>{};
    for (const SlotEntry& entry : list.slots(pass)) {
      std::uint8_t colour = slot_op_colour(entry.op);
      if (colours && entry.op == SlotOp::SplitToBack) colour = colours->first;
      if (colours && entry.op == SlotOp::SplitToFront) colour = colours->second;
      expected.emplace_back(static_cast<int>(entry.slot - min_slot), colour);
    }
    std::sort(expected.begin(), expected.end());
    if (expected != got.ops) {
      std::size_t k = 0;
      while (k < expected.size() && k < got.ops.size() && expected[k] == got.ops[k]) ++k;
      std::string detail;
      if (k < expected.size()) {
        detail = "expected " + colour_name(expected[k].second) + " at slot column " +
                 std::to_string(expected[k].first);
      } else {
        detail = "unexpected " + colour_name(got.ops[k].second) + " at slot column " +
                 std::to_string(got.ops[k].first);
      }
      problems.push_back(where + ": operations differ (" + detail + ")");
    }
  }
  return problems;
}

}  // namespace dat
