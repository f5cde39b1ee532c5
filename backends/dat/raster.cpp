#include "backends/dat/raster.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <string>
#include <tuple>
#include <utility>

#include "backends/dat/reader.hpp"
#include "knitout/writer.hpp"

namespace dat {

namespace {

using knitout::Direction;

std::int64_t floor_div(std::int64_t a, std::int64_t b) {
  std::int64_t q = a / b;
  if ((a % b != 0) && ((a < 0) != (b < 0))) --q;
  return q;
}

// Option values are bytes; the reference stores them into a byte array,
// which keeps the low eight bits.
std::uint8_t byte_of(std::int64_t value) {
  return static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) & 0xFFu);
}

struct Options {
  std::array<std::optional<std::int64_t>, 21> left{};
  std::array<std::optional<std::int64_t>, 21> right{};
  Direction direction = Direction::None;
};

class RowWriter {
 public:
  RowWriter(const PassList& list, std::int64_t min_slot, std::int64_t max_slot,
            std::function<void(std::span<const std::uint8_t>)> emit)
      : list_(list),
        min_slot_(min_slot),
        slots_(static_cast<int>(max_slot - min_slot + 1)),
        width_(kLeftSpace + slots_ + kRightSpace),
        emit_(std::move(emit)),
        row_(static_cast<std::size_t>(width_), 0) {}

  int width() const { return width_; }

  void blank_rows(int count) {
    std::fill(row_.begin(), row_.end(), 0);
    for (int i = 0; i < count; ++i) emit_(row_);
  }

  void full_course(std::uint8_t colour, const Options& options) {
    std::fill(row_.begin(), row_.end(), 0);
    std::fill_n(row_.begin() + kLeftSpace, slots_, colour);
    row_[kLeftSpace - 1] = kStopMark;
    row_[static_cast<std::size_t>(kLeftSpace + slots_)] = kStopMark;
    option_lines(options);
    emit_(row_);
  }

  void pass_row(const Pass& pass, std::span<const std::uint8_t> colours, const Options& options) {
    std::fill(row_.begin(), row_.end(), 0);
    const auto slots = list_.slots(pass);
    for (std::size_t i = 0; i < slots.size(); ++i) {
      row_[column(slots[i].slot)] = colours[i];
    }
    row_[column(pass.min_slot) - 1] = kStopMark;
    row_[column(pass.max_slot) + 1] = kStopMark;
    option_lines(options);
    emit_(row_);
  }

  // The width line (colour 1 from five columns left of the first slot to
  // five right of the last) and the low two digits of the position code.
  void width_line(std::int64_t position) {
    std::fill(row_.begin(), row_.end(), 0);
    row_[kPositionColumn] = byte_of(position % 100);
    std::fill(row_.begin() + kLeftSpace - 5, row_.begin() + kLeftSpace + slots_ + 5, 1);
    emit_(row_);
  }

  void position_high(std::int64_t position) {
    std::fill(row_.begin(), row_.end(), 0);
    row_[kPositionColumn] = byte_of(floor_div(position, 100));
    emit_(row_);
  }

 private:
  std::size_t column(std::int64_t slot) const {
    return static_cast<std::size_t>(kLeftSpace + (slot - min_slot_));
  }

  // Option line o's number sits in its own column beside its value: left
  // lines count outwards from column 49, right lines from the right of the
  // design. Line 1's number is replaced by the direction mark.
  void option_lines(const Options& options) {
    const std::size_t left_base = kLeftSpace - 5;
    const std::size_t right_base = static_cast<std::size_t>(kLeftSpace + slots_ + 4);
    for (std::size_t o = 1; o <= 20; ++o) {
      row_[left_base - 2 * o + 1] = static_cast<std::uint8_t>(o);
      if (options.left[o]) row_[left_base - 2 * o] = byte_of(*options.left[o]);
      row_[right_base + 2 * o - 1] = static_cast<std::uint8_t>(o);
      if (options.right[o]) row_[right_base + 2 * o] = byte_of(*options.right[o]);
    }
    std::uint8_t mark = 1;
    if (options.direction == Direction::Minus) mark = 7;
    if (options.direction == Direction::Plus) mark = 6;
    row_[left_base - 1] = mark;
    row_[right_base + 1] = mark;
  }

  const PassList& list_;
  std::int64_t min_slot_;
  int slots_;
  int width_;
  std::function<void(std::span<const std::uint8_t>)> emit_;
  std::vector<std::uint8_t> row_;
};

Options fixed_options(Direction direction) {
  Options options;
  options.direction = direction;
  options.right[3] = 255;
  options.right[9] = 1;
  options.left[4] = 10;
  return options;
}

bool is_xfer(PassType type) {
  return type == PassType::Xfer || type == PassType::XferToSliders ||
         type == PassType::XferFromSliders;
}

// The needle slots the passes use, checked against what a DAT can hold
// (D030) and, for Position Keep, against the bed (D028); the raster's
// width and height. False after an error.
bool design_size(const PassList& list, knitout::DiagnosticSink& sink, std::int64_t& min_slot,
                 std::int64_t& max_slot, std::int64_t& width, std::int64_t& height) {
  if (list.passes.empty()) {
    sink.error(list.source, 0, 0, "D029", "nothing to knit: the program forms no carriage pass");
    return false;
  }
  // The raster grows with every pass: the first pass that makes it too
  // large for a DAT header (or for kMaxRasterPixels) is the line named.
  min_slot = list.passes.front().min_slot;
  max_slot = list.passes.front().max_slot;
  auto size_at = [](std::int64_t low, std::int64_t high, std::size_t passes) {
    return std::pair<std::int64_t, std::int64_t>(
        kLeftSpace + (high - low + 1) + kRightSpace,
        kTopSpace + static_cast<std::int64_t>(passes) + kBottomSpace + 2 * kFixedCourses);
  };
  auto too_large = [](std::pair<std::int64_t, std::int64_t> size) {
    return size.first > kMaxDimension + 1 || size.second > kMaxDimension + 1 ||
           static_cast<std::uint64_t>(size.first) * static_cast<std::uint64_t>(size.second) >
               kMaxRasterPixels;
  };
  std::uint32_t first_line = 0;
  for (std::size_t i = 0; i < list.passes.size(); ++i) {
    const Pass& pass = list.passes[i];
    min_slot = std::min(min_slot, pass.min_slot);
    max_slot = std::max(max_slot, pass.max_slot);
    if (first_line == 0 && too_large(size_at(min_slot, max_slot, i + 1))) first_line = pass.line;
  }
  std::tie(width, height) = size_at(min_slot, max_slot, list.passes.size());
  if (too_large({width, height})) {
    sink.error(list.source, first_line, 0, "D030",
               "the design needs a " + std::to_string(width) + " x " + std::to_string(height) +
                   " raster (needle slots " + std::to_string(min_slot) + ".." +
                   std::to_string(max_slot) + ", " + std::to_string(list.passes.size()) +
                   " passes); a DAT holds at most 65536 x 65536 and " +
                   std::to_string(kMaxRasterPixels) +
                   " pixels, and this pass is the first "
                   "beyond that");
    return false;
  }
  if (list.position == Position::Keep && !(min_slot > 0 && max_slot <= list.bed_width)) {
    sink.error(list.source, list.passes.front().line, 0, "D028",
               "Position Keep: needle slots " + std::to_string(min_slot) + ".." +
                   std::to_string(max_slot) + " lie outside the bed 1.." +
                   std::to_string(list.bed_width));
    return false;
  }
  return true;
}

// The colours of a pass's slots. A split-via-sliders split's colour also
// encodes the return from the slider: which way (L/R) and how far (1, 2,
// 4) the return racking lies; false (D027) when it cannot.
bool pass_colours(const PassList& list, const Pass& pass, knitout::DiagnosticSink& sink,
                  std::vector<std::uint8_t>& colours) {
  const auto slots = list.slots(pass);
  colours.resize(slots.size());
  for (std::size_t i = 0; i < slots.size(); ++i) colours[i] = slot_op_colour(slots[i].op);
  if (pass.type != PassType::SplitViaSliders) return true;
  const auto pair = split_via_sliders_colours(pass);
  const std::uint8_t front = pair ? pair->first : 0;
  const std::uint8_t back = pair ? pair->second : 0;
  if (front == 0) {
    sink.error(list.source, pass.line, 0, "D027",
               pass.has_return_racking
                   ? "split-via-sliders at racking " + knitout::format_number(pass.racking) +
                         " returned at racking " + knitout::format_number(pass.return_racking) +
                         ": the return must be 1, 2 or 4 needles away"
                   : std::string("split-via-sliders pass whose loops are never returned "
                                 "from the sliders (xfer them back in the next passes)"));
    return false;
  }
  for (std::size_t i = 0; i < slots.size(); ++i) {
    if (slots[i].op == SlotOp::SplitToBack) colours[i] = front;
    if (slots[i].op == SlotOp::SplitToFront) colours[i] = back;
  }
  return true;
}

// The option lines of a pass's row but its direction and carriage move;
// `hook_active`: whether the yarn-inserting hook holds a yarn, kept from
// pass to pass.
Options pass_options(const Pass& pass, bool& hook_active) {
  Options options;
  options.right[9] = 1;  // ignore the links process
  options.right[3] = carrier_code(pass);
  if (pass.type == PassType::XferToSliders) options.left[13] = 1;
  if (pass.type == PassType::XferFromSliders) options.left[13] = 3;
  if (pass.type == PassType::Split) options.left[12] = 10;
  if (pass.gripper == Gripper::In) options.right[10] = carrier_code(pass);
  if (pass.gripper == Gripper::Out) options.right[10] = 100 + carrier_code(pass);
  if (pass.pause) options.left[7] = 20;
  const bool presser = pass.presser == Presser::On ||
                       (pass.presser == Presser::Auto && !hook_active && pass.hook == Hook::None &&
                        !(pass.has_front && pass.has_back));
  if (presser) options.right[11] = 101;
  if (pass.hook == Hook::In) {
    options.right[15] = 10;
    hook_active = true;
  } else if (pass.hook == Hook::Out) {
    options.right[15] = 20;
  } else if (pass.hook == Hook::Release) {
    options.right[15] = 90;
    hook_active = false;
  }
  options.right[6] = pass.stitch;
  const std::int64_t speed = pass.speed == 0 ? 0 : pass.speed + 10;
  options.left[5] = speed;
  options.left[6] = speed;
  if (is_xfer(pass.type)) {
    options.right[5] = 1;  // knit cancel: transfers use knit+xfer stitches
    if (pass.stitch != 0) options.right[13] = 100;
  }
  if (pass.type == PassType::AMiss) options.left[12] = 20;
  if (pass.racking >= 1.0) {
    options.left[4] = 11;
    options.left[2] = static_cast<std::int64_t>(std::floor(pass.racking - 1.0));
  } else {
    options.left[4] = 10;
    options.left[2] = -static_cast<std::int64_t>(std::floor(pass.racking));
  }
  options.left[3] = pass.racking == std::floor(pass.racking) ? 0 : 1;
  return options;
}

// Draws everything; `begin` gets the raster size before the first row.
bool draw(const PassList& list, knitout::DiagnosticSink& sink,
          const std::function<void(int, int)>& begin,
          const std::function<void(std::span<const std::uint8_t>)>& emit) {
  std::int64_t min_slot = 0, max_slot = 0, width = 0, height = 0;
  if (!design_size(list, sink, min_slot, max_slot, width, height)) return false;
  const std::int64_t position = position_code(list, min_slot, max_slot);
  begin(static_cast<int>(width), static_cast<int>(height));

  RowWriter rows(list, min_slot, max_slot, emit);
  rows.blank_rows(kBottomSpace);
  rows.full_course(216, fixed_options(Direction::Plus));
  rows.full_course(51, fixed_options(Direction::Minus));
  rows.full_course(52, fixed_options(Direction::Plus));
  bool carriage_left = false;  // after the fixed courses the carriage is on the right
  bool hook_active = false;
  std::vector<std::uint8_t> colours;
  for (const Pass& pass : list.passes) {
    if (!pass_colours(list, pass, sink, colours)) return false;
    if (std::abs(pass.racking) > 8) {
      sink.error(list.source, pass.line, 0, "D021",
                 "racking " + knitout::format_number(pass.racking) +
                     " is beyond the machine's range -8..8");
      return false;
    }
    Options options = pass_options(pass, hook_active);
    // Drops and a-misses have no direction but still move the carriage: away
    // from the side it is on.
    Direction direction = pass.direction;
    if (direction == Direction::None &&
        (pass.type == PassType::KnitTuck || pass.type == PassType::AMiss)) {
      direction = carriage_left ? Direction::Plus : Direction::Minus;
    }
    // A pass that starts on the side the carriage is not on needs an empty
    // carriage move first (R5 = 2).
    if ((direction == Direction::Minus && carriage_left) ||
        (direction == Direction::Plus && !carriage_left)) {
      options.right[5] = 2;
      carriage_left = !carriage_left;
    }
    options.direction = direction;
    rows.pass_row(pass, colours, options);
    if (direction == Direction::Minus) carriage_left = true;
    if (direction == Direction::Plus) carriage_left = false;
  }

  Options end = fixed_options(Direction::Minus);
  end.right[5] = carriage_left ? 2 : 0;
  rows.full_course(51, end);
  rows.full_course(52, fixed_options(Direction::Plus));
  Options last = fixed_options(Direction::Minus);
  last.left[3] = 1;
  last.right[7] = 11;  // drop-failure detection on
  rows.full_course(3, last);
  rows.blank_rows(1);
  rows.width_line(position);
  rows.position_high(position);
  rows.blank_rows(kTopSpace - 3);
  return true;
}

}  // namespace

std::optional<std::pair<std::uint8_t, std::uint8_t>> split_via_sliders_colours(const Pass& pass) {
  if (!pass.has_return_racking) return std::nullopt;
  const double offset = pass.return_racking - pass.racking;
  // Front splits return to the right (R) for a positive offset, back
  // splits to the left (L).
  if (offset == 1) return std::pair<std::uint8_t, std::uint8_t>{107, 108};
  if (offset == 2) return std::pair<std::uint8_t, std::uint8_t>{127, 128};
  if (offset == 4) return std::pair<std::uint8_t, std::uint8_t>{147, 148};
  if (offset == -1) return std::pair<std::uint8_t, std::uint8_t>{106, 109};
  if (offset == -2) return std::pair<std::uint8_t, std::uint8_t>{126, 129};
  if (offset == -4) return std::pair<std::uint8_t, std::uint8_t>{146, 149};
  return std::nullopt;
}

std::int64_t position_code(const PassList& passes, std::int64_t min_slot, std::int64_t max_slot) {
  const std::int64_t slots = max_slot - min_slot + 1;
  switch (passes.position) {
    case Position::Center:
      // Half-way, rounding halves up (as JavaScript's Math.round does).
      return floor_div(passes.bed_width - slots + 1, 2);
    case Position::Keep:
      return min_slot;
    case Position::Left:
      return 1;
    case Position::Right:
      return 0;
  }
  return 0;
}

std::optional<std::vector<std::uint8_t>> write_dat(const PassList& passes,
                                                   knitout::DiagnosticSink& sink) {
  std::vector<std::uint8_t> bytes;
  const bool ok = draw(
      passes, sink,
      [&](int width, int height) {
        bytes = file_prefix(width, height);
        bytes.reserve(bytes.size() + static_cast<std::size_t>(height) * 64);
      },
      [&](std::span<const std::uint8_t> row) { encode_row(row, bytes); });
  if (!ok) return std::nullopt;
  return bytes;
}

std::optional<Raster> rasterize(const PassList& passes, knitout::DiagnosticSink& sink) {
  Raster raster;
  raster.palette = kPalette;
  const bool ok = draw(
      passes, sink,
      [&](int width, int height) {
        raster.width = width;
        raster.height = height;
        raster.pixels.reserve(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
      },
      [&](std::span<const std::uint8_t> row) {
        raster.pixels.insert(raster.pixels.end(), row.begin(), row.end());
      });
  if (!ok) return std::nullopt;
  return raster;
}

}  // namespace dat
