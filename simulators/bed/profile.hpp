// bed::MachineProfile: what the virtual machine knows about one knitting
// machine, as plain data.
//
// The machine model (machine.hpp) never branches on a machine's name: every
// difference between machines is a field here. The built-in profiles are
// `swg091n2` (the default: Shima Seiki SWG091N2), `kniterate` and `generic`
// (no bed limits, any carrier name); docs/vm.md lists their values and the
// sources they come from.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bed {

struct MachineProfile {
  std::string name;         // "swg091n2"
  std::string description;  // one line, for --help and listings
  // Values of the `;;Machine:` header that name this machine; another value
  // gets a warning (V073). Empty: any value is accepted silently.
  std::vector<std::string> machine_headers;
  double gauge = 15;  // needles per inch; 0 = unknown (no Gauge check)

  // Needles per bed; 0 = unlimited. Knitout needle numbers are placed on the
  // machine by the backend (SWG `;;Position:`, kniterate positions), so the
  // limit is on the span the program uses: max - min + 1 <= needle_count,
  // measured in front-bed slots (back needle b n at racking r sits at slot
  // n + floor(r)).
  int needle_count = 540;
  bool has_sliders = true;

  double max_racking = 8;  // |racking| <= max_racking; <0 = unlimited
  // Allowed values of racking - floor(racking): {0} integer only, {0, 0.25}
  // quarter pitch (Shima all-needle). Empty = any.
  std::vector<double> racking_fractions = {0.0, 0.25};

  // Carrier names on the machine, front to back. Empty = any name.
  std::vector<std::string> carriers;
  bool has_inserting_hook = true;

  int max_loops_per_needle = 4;       // more is an error (V037)
  int long_float_needles = 24;        // a float longer than this many needle pitches warns (V054)
  bool integer_stitch_values = true;  // `stitch L T` takes integers (V041)
  int max_speed_number = 15;          // x-speed-number 0..max
  int max_sub_roller_number = 31;     // x-sub-roller-number 0..max

  // Machine-time model (docs/vm.md, "Estimated machine time").
  double knit_speed_m_per_s = 0.8;      // carriage speed on knitting sweeps
  double transfer_speed_m_per_s = 0.5;  // carriage speed on transfer and drop sweeps
  double turnaround_s = 0.5;            // carriage reversal and carrier pick-up per sweep
  double rack_s = 0.3;                  // one racking change
  int overrun_needles = 20;             // the carriage runs past the last needle on each side
  // Yarn model: yarn in one loop, in needle pitches (a plain stitch takes
  // about three pitches of yarn at medium stitch size).
  double loop_yarn_pitches = 3.0;

  double pitch_mm() const { return gauge > 0 ? 25.4 / gauge : 25.4 / 15.0; }
  bool carrier_exists(std::string_view carrier) const;
};

// The built-in profiles, `swg091n2` first (the default).
const std::vector<MachineProfile>& machine_profiles();
const MachineProfile& default_profile();
// The profile named `name`; nullptr when there is none.
const MachineProfile* find_profile(std::string_view name);
// "swg091n2, kniterate, generic": for error messages.
std::string profile_names();

}  // namespace bed
