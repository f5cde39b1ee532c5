// DAT machine profiles: what differs between the machines the DAT format
// serves, kept as data (DESIGN.md: "profiles are data, not code paths").
// The one profile is swg091n2, the machine knitout-to-dat.js writes for.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

namespace dat {

// `stitch L T` (leading value L, stitch value T) selects machine stitch
// number `number`.
struct StitchEntry {
  int stitch;
  int leading;
  int number;
};

struct Profile {
  std::string_view name;
  std::string_view carriers_header;    // the exact `;;Carriers:` value required
  int carrier_count = 0;               // carriers are named "1" .. carrier_count
  std::int64_t default_bed_width = 0;  // needles, when `;;Width:` is absent
  double max_racking = 0;              // |racking| allowed on a pass
  std::int64_t default_stitch = 0;     // stitch number (R6) before any stitch setting
  std::span<const StitchEntry> stitch_table;
};

// Shima Seiki SWG091N2: 15 gauge, 540 needles, carriers 1-10, racking -8..8
// with quarter pitch.
const Profile& swg091n2();

// The profile called `name`, or nullptr.
const Profile* find_profile(std::string_view name);
std::vector<std::string_view> profile_names();

}  // namespace dat
