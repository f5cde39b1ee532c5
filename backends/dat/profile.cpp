#include "backends/dat/profile.hpp"

#include <array>
#include <string>

#include "simulators/bed/profile.hpp"

namespace dat {

namespace {

// The stitch-number table of the swg091n2 profile (docs/dat.md).
constexpr std::array<StitchEntry, 20> kSwg091n2Stitches = {{
    {10, -10, 81}, {10, 0, 82},  {10, 10, 83}, {15, 5, 84},  {15, 10, 85},
    {15, 15, 86},  {20, 10, 87}, {20, 15, 88}, {20, 20, 89}, {25, 15, 90},
    {25, 20, 91},  {25, 25, 92}, {30, 25, 93}, {35, 25, 94}, {40, 25, 95},
    {45, 25, 96},  {50, 25, 97}, {55, 25, 98}, {60, 25, 99}, {65, 25, 100},
}};

// The machine's facts (carriers, needles, racking) come from the needle-bed
// VM's profile of the same name, so the VM and the DAT backend cannot
// disagree about the machine; only the DAT encoding (the `;;Carriers:`
// header text, the stitch table, the default stitch number) lives here.
Profile make_swg091n2() {
  static const bed::MachineProfile& machine = *bed::find_profile("swg091n2");
  static const std::string carriers_header = [] {
    std::string header;
    for (const std::string& carrier : machine.carriers)
      header += (header.empty() ? "" : " ") + carrier;
    return header;
  }();
  Profile profile;
  profile.name = machine.name;
  profile.carriers_header = carriers_header;
  profile.carrier_count = static_cast<int>(machine.carriers.size());
  profile.default_bed_width = machine.needle_count;
  profile.max_racking = machine.max_racking;
  profile.default_stitch = 5;
  profile.stitch_table = kSwg091n2Stitches;
  return profile;
}

}  // namespace

const Profile& swg091n2() {
  static const Profile profile = make_swg091n2();
  return profile;
}

const Profile* find_profile(std::string_view name) {
  if (name == swg091n2().name) return &swg091n2();
  return nullptr;
}

std::vector<std::string_view> profile_names() {
  return {swg091n2().name};
}

}  // namespace dat
