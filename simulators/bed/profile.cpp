#include "simulators/bed/profile.hpp"

#include <algorithm>

namespace bed {

bool MachineProfile::carrier_exists(std::string_view carrier) const {
  if (carriers.empty()) return true;
  return std::find(carriers.begin(), carriers.end(), carrier) != carriers.end();
}

namespace {

std::vector<std::string> numbered_carriers(int count) {
  std::vector<std::string> names;
  for (int i = 1; i <= count; ++i) names.push_back(std::to_string(i));
  return names;
}

std::vector<MachineProfile> make_profiles() {
  std::vector<MachineProfile> profiles;

  // Shima Seiki SWG091N2: 15 gauge, 540 needles per bed, racking -8..+8
  // with quarter pitch, carriers 1-10, sliders and a yarn-inserting hook
  // (DESIGN.md "Machine profiles"; racking rules as knitout-to-dat.js checks
  // them, notes/knitout-and-dat.md section 2).
  MachineProfile swg;
  swg.name = "swg091n2";
  swg.description = "Shima Seiki SWG091N2 WholeGarment, 15 gauge, 540 needles, carriers 1-10";
  swg.machine_headers = {"SWG091N2"};
  swg.gauge = 15;
  swg.needle_count = 540;
  swg.has_sliders = true;
  swg.max_racking = 8;
  swg.racking_fractions = {0.0, 0.25};
  swg.carriers = numbered_carriers(10);
  swg.has_inserting_hook = true;
  swg.max_loops_per_needle = 4;
  swg.long_float_needles = 24;
  profiles.push_back(swg);

  // Kniterate: 7 gauge, 252 needles, carriers 1-6, no sliders, racking up
  // to 4 either way in whole or half pitches (half pitch for full-gauge
  // rib; its backend also reads 0.25 as a half rack, as its test files
  // note). Its backend
  // takes x-speed-number as the carriage speed itself (its test files use
  // 100-300), not a 0-15 table index.
  MachineProfile kniterate;
  kniterate.name = "kniterate";
  kniterate.description = "Kniterate, 7 gauge, 252 needles, carriers 1-6, no sliders";
  kniterate.machine_headers = {"Kniterate", "kniterate"};
  kniterate.gauge = 7;
  kniterate.needle_count = 252;
  kniterate.has_sliders = false;
  kniterate.max_racking = 4;
  kniterate.racking_fractions = {0.0, 0.25, 0.5};
  kniterate.max_speed_number = 600;
  kniterate.carriers = numbered_carriers(6);
  kniterate.has_inserting_hook = true;
  kniterate.max_loops_per_needle = 3;
  kniterate.long_float_needles = 12;
  kniterate.knit_speed_m_per_s = 0.5;
  kniterate.transfer_speed_m_per_s = 0.3;
  kniterate.turnaround_s = 0.6;
  kniterate.rack_s = 0.5;
  kniterate.overrun_needles = 10;
  profiles.push_back(kniterate);

  // Generic: no bed limits, any carrier names, any racking; loop and float
  // rules keep the swg091n2 values so knitting mistakes are still found.
  MachineProfile generic;
  generic.name = "generic";
  generic.description = "generic V-bed: unlimited needles and racking, any carrier names";
  generic.machine_headers = {};
  generic.gauge = 0;
  generic.needle_count = 0;
  generic.has_sliders = true;
  generic.max_racking = -1;
  generic.racking_fractions = {};
  generic.carriers = {};
  generic.has_inserting_hook = true;
  generic.max_loops_per_needle = 4;
  generic.long_float_needles = 24;
  generic.integer_stitch_values = false;
  generic.max_speed_number = 15;
  generic.max_sub_roller_number = 31;
  profiles.push_back(generic);
  return profiles;
}

}  // namespace

const std::vector<MachineProfile>& machine_profiles() {
  static const std::vector<MachineProfile> kProfiles = make_profiles();
  return kProfiles;
}

const MachineProfile& default_profile() {
  return machine_profiles().front();
}

const MachineProfile* find_profile(std::string_view name) {
  for (const MachineProfile& profile : machine_profiles()) {
    if (profile.name == name) return &profile;
  }
  return nullptr;
}

std::string profile_names() {
  std::string out;
  for (const MachineProfile& profile : machine_profiles()) {
    if (!out.empty()) out += ", ";
    out += profile.name;
  }
  return out;
}

}  // namespace bed
