// Knitout -> carriage passes, the first half of the DAT backend.
//
// `PassBuilder` takes knitout instructions one at a time (so a file can be
// streamed through knitout::Reader) and forms the carriage passes the
// reference backend knitout-to-dat.js forms, with the same decisions:
// each operation becomes a one-slot pass that is merged into the previous
// pass when type, racking, stitch, speed, direction and carriers agree and
// the slot fits; carriers are kicked out of the way (implicit kickbacks);
// `in`/`inhook`/`out`/`outhook`/`releasehook` become gripper and hook
// options. Rules and their reasons: docs/dat.md.
//
// Everything the reference rejects is an error diagnostic D001-D039 at the
// instruction's FILE:LINE (docs/diagnostics.md); the first error ends pass
// formation (like the reference, which stops at its first error). Where
// the reference crashes (three or more carriers in one pass, a program
// without passes) the builder reports a clear error instead.
//
// PassBuilder is in passes.cpp (pass formation, settings, stitches, splits)
// and pass_carriers.cpp (carriers in and out, the hook, kicks); the
// summaries of carriage_passes() in carriage_passes.cpp.
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "backends/dat/profile.hpp"
#include "knitout/diagnostic.hpp"
#include "knitout/parser.hpp"
#include "knitout/program.hpp"

namespace dat {

// The kinds of pass the swg091n2 profile writes.
enum class PassType : std::uint8_t {
  KnitTuck,         // knit, tuck, miss, drop, kicks, gripper/hook passes
  AMiss,            // tuck without carriers
  Split,            // split with yarn, needle to needle
  SplitViaSliders,  // split with yarn to the opposite slider, returned later
  Xfer,             // transfer needle to needle
  XferToSliders,
  XferFromSliders,
};
std::string_view pass_type_name(PassType type);  // "knit-tuck", "a-miss", ...

enum class Hook : std::uint8_t { None, In, Release, Out };
enum class Gripper : std::uint8_t { None, In, Out };
// `Unset` = the pass carries no presser setting (kicks, hook passes, xfers).
enum class Presser : std::uint8_t { Unset, Off, On, Auto };

// What one slot of a pass does. Distinct kinds may share a colour: the
// reference merges by operation, not by colour (a knit-front merged with a
// miss-back is still colour 51 but no longer merges with a back knit).
enum class SlotOp : std::uint8_t {
  SoftMiss,  // carrier move only; any op in the same slot replaces it
  MissFront,
  MissBack,
  TuckFront,
  TuckBack,
  KnitFront,
  KnitBack,
  KnitFrontKnitBack,
  KnitFrontTuckBack,
  KnitFrontMissBack,
  TuckFrontKnitBack,
  TuckFrontTuckBack,
  TuckFrontMissBack,
  MissFrontKnitBack,
  MissFrontTuckBack,
  MissFrontMissBack,
  XferToBack,
  XferToFront,
  SplitToBack,
  SplitToFront,
};
std::uint8_t slot_op_colour(SlotOp op);

// Carrier numbers 1..10 of a pass, leading carrier first.
struct CarrierSet {
  std::uint8_t size = 0;
  std::array<std::uint8_t, knitout::kMaxCarriersPerInstruction> ids{};

  bool empty() const { return size == 0; }
  const std::uint8_t* begin() const { return ids.data(); }
  const std::uint8_t* end() const { return ids.data() + size; }
  bool contains(std::uint8_t id) const;
  bool operator==(const CarrierSet& other) const;
};
// "3", "3 10", "" for none.
std::string to_string(const CarrierSet& carriers);

struct SlotEntry {
  std::int64_t slot = 0;  // front needle n -> n; back needle b -> b + floor(racking)
  SlotOp op = SlotOp::SoftMiss;
};

struct Pass {
  PassType type = PassType::KnitTuck;
  knitout::Direction direction = knitout::Direction::None;
  Hook hook = Hook::None;
  Gripper gripper = Gripper::None;
  Presser presser = Presser::Unset;
  bool pause = false;
  bool has_front = false;  // some slot op knits or tucks on the front bed
  bool has_back = false;
  bool has_return_racking = false;  // split-via-sliders only
  double racking = 0;
  double return_racking = 0;
  std::int64_t stitch = 0;
  std::int64_t speed = 0;
  CarrierSet carriers;
  std::uint32_t first_entry = 0;  // into PassList::entries
  std::uint32_t entry_count = 0;
  std::int64_t min_slot = 0;
  std::int64_t max_slot = 0;
  std::uint32_t line = 0;  // source line of the instruction that opened the pass
};

enum class Position : std::uint8_t { Center, Keep, Left, Right };

// The passes of a program and the header values the raster needs.
struct PassList {
  std::vector<Pass> passes;
  std::vector<SlotEntry> entries;  // each pass's slots, contiguous
  const Profile* profile = &swg091n2();
  std::int64_t bed_width = 540;  // `;;Width:` header, else the profile's bed
  Position position = Position::Center;
  std::string source;

  std::span<const SlotEntry> slots(const Pass& pass) const {
    return std::span(entries).subspan(pass.first_entry, pass.entry_count);
  }
};

class PassBuilder {
 public:
  // `source` names the input in diagnostics.
  PassBuilder(std::string source, knitout::DiagnosticSink& sink,
              const Profile& profile = swg091n2());

  // Checks the magic line and headers as the reference does (call once,
  // before `add`). False after an error.
  bool begin(bool has_magic, const std::vector<knitout::Header>& headers);
  // Adds one instruction; `carriers` resolves its carrier ids to names.
  // False after an error (this one or an earlier one); later calls do nothing.
  // `text` is the instruction's text (for unknown extensions: "x-name args").
  bool add(const knitout::Instruction& instruction, const knitout::CarrierTable& carriers,
           std::string_view text = {});
  // Ends the program (every carrier must be out). `last_line` is the file's
  // last line, for the diagnostic. False after an error.
  bool finish(std::uint32_t last_line);

  bool failed() const { return failed_; }
  const PassList& passes() const { return list_; }
  PassList take_passes() { return std::move(list_); }

 private:
  struct NeedleRef {
    knitout::Bed bed = knitout::Bed::Front;
    std::int64_t index = 0;  // kicks park carriers at slots, which may exceed int32
    bool operator==(const NeedleRef&) const = default;
  };
  struct CarrierState {
    bool active = false;
    bool has_last = false;
    bool used_hook = false;
    int in_info = -1;  // index into in_infos_, while the `in` is pending
    NeedleRef last_needle;
    knitout::Direction last_direction = knitout::Direction::None;
    NeedleRef kick_needle;
    knitout::Direction kick_direction = knitout::Direction::None;
    std::uint32_t in_line = 0;
  };
  struct InInfo {
    bool hook = false;  // inhook
    CarrierSet carriers;
  };
  // A one-slot pass about to be merged.
  struct Candidate {
    Pass pass;
    SlotEntry entry;
  };
  struct SplitViaSliders {
    std::set<std::pair<int, std::int32_t>> needles;  // slider needles split to
    double racking = 0;
    bool has_return = false;
    double return_racking = 0;
  };

  bool error(std::uint32_t line, std::string_view code, std::string message);
  void warning(std::uint32_t line, std::string_view code, std::string message);
  std::int64_t slot_number(NeedleRef needle) const;
  std::uint8_t carrier_number(knitout::CarrierId id, const knitout::CarrierTable& table);
  std::string name_list(const CarrierSet& carriers) const;
  std::string instruction_carriers() const;  // the current instruction's carrier names
  Candidate make_candidate(PassType type, knitout::Direction direction, const CarrierSet& carriers,
                           std::int64_t slot, SlotOp op, std::int64_t stitch) const;

  // One `add` per kind of instruction; false after an error.
  bool add_extension(const knitout::Instruction& in, std::uint32_t line, std::string_view text);
  bool add_rack(const knitout::Instruction& in, std::uint32_t line);
  bool add_stitch_setting(const knitout::Instruction& in, std::uint32_t line);
  bool add_stitch_op(const knitout::Instruction& in, const CarrierSet& cs, std::uint32_t line);
  bool add_split(const knitout::Instruction& in, const CarrierSet& cs, std::uint32_t line);
  bool return_from_slider(const knitout::Needle& n, std::uint32_t line);
  bool split_to_slider(const knitout::Needle& n, const knitout::Needle& t, std::uint32_t line);
  // Carriers in and out, and the hook (pass_carriers.cpp).
  bool add_in(const knitout::Instruction& in, const CarrierSet& cs, std::uint32_t line);
  bool add_releasehook(const CarrierSet& cs, std::uint32_t line);
  bool add_out(const knitout::Instruction& in, const CarrierSet& cs, std::uint32_t line);
  bool check_pass_carriers(const CarrierSet& cs, std::uint32_t line);
  bool handle_in(const CarrierSet& cs, Candidate& candidate, std::uint32_t line);
  void kick_others(NeedleRef needle, const CarrierSet& cs);
  void merge(Candidate candidate);
  bool append(Pass& last, const Candidate& next);
  void push(const Candidate& candidate);
  void set_last(const CarrierSet& cs, knitout::Direction direction, NeedleRef needle);
  bool reject_if_split_via_sliders(std::uint32_t line, std::string_view op);

  std::string source_;
  knitout::DiagnosticSink& sink_;
  const Profile& profile_;
  bool failed_ = false;
  PassList list_;
  std::array<CarrierState, 11> carriers_{};  // by carrier number 1..10
  std::vector<InInfo> in_infos_;
  std::vector<std::uint8_t> id_numbers_;  // CarrierId -> 1..10, 0 = not a swg carrier name
  std::optional<std::pair<knitout::Direction, CarrierSet>> hook_;  // what the hook holds
  std::optional<SplitViaSliders> svs_;
  double racking_ = 0;
  std::int64_t stitch_ = 5;
  std::int64_t speed_ = 0;
  Presser presser_ = Presser::Off;
  bool pause_pending_ = false;
  std::uint32_t line_ = 0;  // line of the instruction being added
  std::unordered_map<std::int64_t, std::uint32_t> open_slots_;  // slot -> entry, last pass
  std::vector<std::string> warned_extensions_;
  const knitout::Instruction* current_ = nullptr;
  const knitout::CarrierTable* table_ = nullptr;
};

// Streams a knitout file through knitout::Reader into passes. Parser
// diagnostics (K codes) and backend diagnostics (D codes) go to `sink`.
// nullopt on any error.
std::optional<PassList> form_passes(std::istream& in, std::string source,
                                    knitout::DiagnosticSink& sink,
                                    const Profile& profile = swg091n2());
std::optional<PassList> form_passes(const knitout::Program& program, std::string source,
                                    knitout::DiagnosticSink& sink,
                                    const Profile& profile = swg091n2());

// One carriage pass as `wearknit simulate --stats` reports it.
struct CarriagePass {
  PassType type = PassType::KnitTuck;
  knitout::Direction direction = knitout::Direction::None;  // None: xfer, drop, a-miss
  std::vector<std::string> carriers;                        // names, leading first
  double racking = 0;
  std::size_t slots = 0;   // needle slots the pass acts on (kick-only slots included)
  std::uint32_t line = 0;  // source line of the instruction that opened it
};

// The carriage passes the DAT backend forms for `program`, in order (the
// rows of the DAT between its fixed courses). Diagnostics as for
// form_passes; nullopt when the program is rejected.
//
// To report them while streaming a file through another consumer (as
// `simulate` streams into the VM), feed the same instructions to a
// PassBuilder with a sink of its own: begin(reader.has_magic(),
// reader.headers()), add(instruction, reader.carriers(), reader.text()) per
// instruction, finish(reader.lines_read()), then summarize(builder.passes())
// unless builder.failed().
std::optional<std::vector<CarriagePass>> carriage_passes(const knitout::Program& program,
                                                         std::string source,
                                                         knitout::DiagnosticSink& sink,
                                                         const Profile& profile = swg091n2());
std::vector<CarriagePass> summarize(const PassList& passes);

// "carriage passes: 6 (4 knit-tuck, 1 xfer, 1 a-miss)" and, when
// `each_pass`, one line per pass: "  pass 1 (line 4): + carriers 3 racking 0
// knit-tuck, 2 slots".
void write_carriage_passes_text(std::ostream& out, const std::vector<CarriagePass>& passes,
                                bool each_pass);
// {"count": N, "passes": [{"type": "knit-tuck", "direction": "+", "carriers":
// ["3"], "racking": 0, "slots": 2, "line": 4}, ...]}
void write_carriage_passes_json(std::ostream& out, const std::vector<CarriagePass>& passes);

}  // namespace dat
