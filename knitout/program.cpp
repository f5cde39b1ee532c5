#include "knitout/program.hpp"

#include <algorithm>

#include "knitout/writer.hpp"

namespace knitout {
namespace {

constexpr std::array<std::string_view, kOpCount> kOpNames = {
    "",     "in",    "inhook", "releasehook", "out",  "outhook", "stitch", "rack", "knit",
    "tuck", "split", "drop",   "amiss",       "xfer", "miss",    "pause",  ""};

constexpr std::array<std::string_view, 9> kExtensionNames = {"",
                                                             "x-stitch-number",
                                                             "x-speed-number",
                                                             "x-presser-mode",
                                                             "x-sub-roller-number",
                                                             "x-xfer-stitch-number",
                                                             "x-carrier-spacing",
                                                             "x-vis-color",
                                                             ""};

}  // namespace

std::string_view op_name(Op op) {
  return kOpNames[static_cast<std::size_t>(op)];
}

std::optional<Op> op_from_name(std::string_view name) {
  for (std::size_t i = 1; i + 1 < kOpNames.size(); ++i) {
    if (kOpNames[i] == name) return static_cast<Op>(i);
  }
  return std::nullopt;
}

std::string_view extension_name(Extension extension) {
  return kExtensionNames[static_cast<std::size_t>(extension)];
}

Extension extension_from_name(std::string_view name) {
  for (std::size_t i = 1; i + 1 < kExtensionNames.size(); ++i) {
    if (kExtensionNames[i] == name) return static_cast<Extension>(i);
  }
  return Extension::Unknown;
}

std::string_view presser_mode_name(PresserMode mode) {
  switch (mode) {
    case PresserMode::On:
      return "on";
    case PresserMode::Auto:
      return "auto";
    case PresserMode::Off:
      break;
  }
  return "off";
}

std::string to_string(Needle needle) {
  static constexpr std::array<std::string_view, 4> kBeds = {"f", "b", "fs", "bs"};
  std::string out(kBeds[static_cast<std::size_t>(needle.bed)]);
  out += std::to_string(needle.index);
  return out;
}

char direction_char(Direction direction) {
  switch (direction) {
    case Direction::Plus:
      return '+';
    case Direction::Minus:
      return '-';
    case Direction::None:
      break;
  }
  return '?';
}

bool CarrierList::contains(CarrierId id) const {
  return std::find(begin(), end(), id) != end();
}

bool CarrierList::push_back(CarrierId id) {
  if (count_ == kMaxCarriersPerInstruction) return false;
  ids_[count_++] = id;
  return true;
}

bool CarrierList::operator==(const CarrierList& other) const {
  return count_ == other.count_ && std::equal(begin(), end(), other.begin());
}

std::optional<CarrierId> CarrierTable::find(std::string_view name) const {
  for (std::size_t i = 0; i < names_.size(); ++i) {
    if (names_[i] == name) return static_cast<CarrierId>(i);
  }
  return std::nullopt;
}

std::optional<CarrierId> CarrierTable::intern(std::string_view name) {
  if (auto id = find(name)) return id;
  if (names_.size() >= kMaxCarrierNames) return std::nullopt;
  names_.emplace_back(name);
  return static_cast<CarrierId>(names_.size() - 1);
}

std::optional<std::string_view> Program::header(std::string_view key) const {
  for (auto it = headers.rbegin(); it != headers.rend(); ++it) {
    if (it->key == key) return std::string_view(it->value);
  }
  return std::nullopt;
}

std::string_view Program::comment(const Instruction& instruction) const {
  return instruction.comment == kNoText ? std::string_view() : texts[instruction.comment];
}

std::string_view Program::text(const Instruction& instruction) const {
  return instruction.text == kNoText ? std::string_view() : texts[instruction.text];
}

std::uint32_t Program::add_text(std::string_view text) {
  texts.emplace_back(text);
  return static_cast<std::uint32_t>(texts.size() - 1);
}

bool same_instruction(const Program& a, const Instruction& x, const Program& b,
                      const Instruction& y) {
  if (x.op != y.op || x.direction != y.direction || x.extension != y.extension ||
      x.needle != y.needle || x.needle2 != y.needle2 || x.value != y.value ||
      x.carriers.size() != y.carriers.size() || x.has_comment() != y.has_comment()) {
    return false;
  }
  for (std::size_t i = 0; i < x.carriers.size(); ++i) {
    if (a.carrier_name(x.carriers[i]) != b.carrier_name(y.carriers[i])) return false;
  }
  return a.comment(x) == b.comment(y) && a.text(x) == b.text(y);
}

bool Program::operator==(const Program& other) const {
  if (version != other.version || headers != other.headers ||
      instructions.size() != other.instructions.size()) {
    return false;
  }
  for (std::size_t i = 0; i < instructions.size(); ++i) {
    if (!same_instruction(*this, instructions[i], other, other.instructions[i])) return false;
  }
  return true;
}

std::string describe(const Program& program, const Instruction& instruction) {
  std::string out;
  append_instruction(out, program.carriers, instruction, {}, program.text(instruction));
  return out;
}

}  // namespace knitout
