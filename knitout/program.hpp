// knitout::Program: one knitout file in memory.
//
// A Program holds the version from the magic line, the `;;Key: value`
// header lines in their order, the carrier names, and one Instruction per
// non-blank source line (comment-only lines included, so comments survive a
// round trip). Every Instruction keeps the line it came from.
//
// Instructions are small fixed-size values: carriers are ids into the
// program's carrier table and text (comments, unknown extension arguments)
// lives in a side table, so building a Program allocates nothing per
// ordinary instruction. Specification: knitout v2, notes in docs/knitout.md.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace knitout {

inline constexpr int kKnownVersion = 2;

enum class Op : std::uint8_t {
  Comment,  // a line holding only a comment
  In,
  Inhook,
  Releasehook,
  Out,
  Outhook,
  Stitch,
  Rack,
  Knit,
  Tuck,
  Split,
  Drop,
  Amiss,
  Xfer,
  Miss,
  Pause,
  Extension,  // any x-* operation, see Instruction::extension
};
inline constexpr int kOpCount = static_cast<int>(Op::Extension) + 1;

std::string_view op_name(Op op);  // "knit", ...; "" for Comment and Extension
std::optional<Op> op_from_name(std::string_view name);

// The extensions wearknit understands; anything else starting with "x-" is
// kept as Unknown with its name and arguments as text.
enum class Extension : std::uint8_t {
  None,
  StitchNumber,      // x-stitch-number N
  SpeedNumber,       // x-speed-number N
  PresserMode,       // x-presser-mode on|off|auto
  SubRollerNumber,   // x-sub-roller-number N
  XferStitchNumber,  // x-xfer-stitch-number N
  CarrierSpacing,    // x-carrier-spacing N
  VisColor,          // x-vis-color #RRGGBB CARRIER
  Unknown,
};
std::string_view extension_name(Extension extension);  // "x-stitch-number", ...
Extension extension_from_name(std::string_view name);

enum class PresserMode : std::uint8_t { Off, On, Auto };
std::string_view presser_mode_name(PresserMode mode);

enum class Bed : std::uint8_t { Front, Back, FrontSlider, BackSlider };

struct Needle {
  Bed bed = Bed::Front;
  std::int32_t index = 0;

  bool is_front() const { return bed == Bed::Front || bed == Bed::FrontSlider; }
  bool is_back() const { return !is_front(); }
  bool is_slider() const { return bed == Bed::FrontSlider || bed == Bed::BackSlider; }
  bool operator==(const Needle&) const = default;
};
std::string to_string(Needle needle);  // "f10", "bs-2"

enum class Direction : std::uint8_t { None, Plus, Minus };
char direction_char(Direction direction);  // '+', '-', or '?' for None
// Plus for Minus, Minus for Plus, None for None.
inline Direction opposite(Direction direction) {
  if (direction == Direction::Minus) return Direction::Plus;
  if (direction == Direction::Plus) return Direction::Minus;
  return Direction::None;
}

using CarrierId = std::uint8_t;
inline constexpr std::size_t kMaxCarriersPerInstruction = 15;
inline constexpr std::size_t kMaxCarrierNames = 255;

// An ordered list of carriers (order matters: the first is the leading yarn).
class CarrierList {
 public:
  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  CarrierId operator[](std::size_t i) const { return ids_[i]; }
  const CarrierId* begin() const { return ids_.data(); }
  const CarrierId* end() const { return ids_.data() + count_; }
  bool contains(CarrierId id) const;
  // False when the list is full (kMaxCarriersPerInstruction).
  bool push_back(CarrierId id);
  void clear() { count_ = 0; }
  bool operator==(const CarrierList& other) const;

 private:
  std::uint8_t count_ = 0;
  std::array<CarrierId, kMaxCarriersPerInstruction> ids_{};
};

// Carrier names in order of first appearance (the Carriers header first).
class CarrierTable {
 public:
  // The id of `name`, adding it when new; nullopt when the table is full.
  std::optional<CarrierId> intern(std::string_view name);
  std::optional<CarrierId> find(std::string_view name) const;
  const std::string& name(CarrierId id) const { return names_[id]; }
  std::size_t size() const { return names_.size(); }
  const std::vector<std::string>& names() const { return names_; }

 private:
  std::vector<std::string> names_;
};

inline constexpr std::uint32_t kNoText = std::numeric_limits<std::uint32_t>::max();

struct Instruction {
  Op op = Op::Comment;
  Direction direction = Direction::None;  // knit, tuck, split, miss
  Extension extension = Extension::None;  // when op == Extension
  Needle needle;                          // knit tuck split drop amiss xfer miss
  Needle needle2;                         // split, xfer: the target needle
  CarrierList carriers;                   // in* out* releasehook knit tuck split miss
  // rack: value[0] = racking. stitch: value[0] = L, value[1] = T.
  // Numeric extensions: value[0]. x-presser-mode: value[0] = PresserMode.
  std::array<double, 2> value{};
  std::uint32_t line = 0;           // 1-based source line
  std::uint32_t comment = kNoText;  // index into Program::texts
  // Unknown extensions: "name args" as written; x-vis-color: the colour.
  std::uint32_t text = kNoText;

  double racking() const { return value[0]; }
  bool has_comment() const { return comment != kNoText; }
};

struct Header {
  std::string key;
  std::string value;
  std::uint32_t line = 0;
  bool operator==(const Header& other) const { return key == other.key && value == other.value; }
};

class Program {
 public:
  int version = kKnownVersion;
  bool has_magic = true;  // false when the file lacked `;!knitout-N`
  std::vector<Header> headers;
  CarrierTable carriers;
  std::vector<Instruction> instructions;
  std::vector<std::string> texts;

  // The value of the last header called `key`, if any.
  std::optional<std::string_view> header(std::string_view key) const;
  std::string_view comment(const Instruction& instruction) const;
  std::string_view text(const Instruction& instruction) const;
  std::uint32_t add_text(std::string_view text);
  std::string_view carrier_name(CarrierId id) const { return carriers.name(id); }

  // Content equality: version, headers, and instructions with their carrier
  // names, values, comments and texts. Source line numbers are not compared
  // (reformatting moves lines), nor is `has_magic`.
  bool operator==(const Program& other) const;
};

// Content equality of two instructions of possibly different programs.
bool same_instruction(const Program& a, const Instruction& x, const Program& b,
                      const Instruction& y);

// A readable one-line description of the instruction, as the writer emits it.
std::string describe(const Program& program, const Instruction& instruction);

}  // namespace knitout
