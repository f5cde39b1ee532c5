#include "backends/dat/profile.hpp"

#include <array>

namespace dat {

namespace {

// The stitch-number table of the swg091n2 profile (docs/dat.md).
constexpr std::array<StitchEntry, 20> kSwg091n2Stitches = {{
    {10, -10, 81}, {10, 0, 82},  {10, 10, 83}, {15, 5, 84},  {15, 10, 85},
    {15, 15, 86},  {20, 10, 87}, {20, 15, 88}, {20, 20, 89}, {25, 15, 90},
    {25, 20, 91},  {25, 25, 92}, {30, 25, 93}, {35, 25, 94}, {40, 25, 95},
    {45, 25, 96},  {50, 25, 97}, {55, 25, 98}, {60, 25, 99}, {65, 25, 100},
}};

const Profile kSwg091n2 = {
    "swg091n2", "1 2 3 4 5 6 7 8 9 10", 10, 540, 8, 5, kSwg091n2Stitches,
};

}  // namespace

const Profile& swg091n2() {
  return kSwg091n2;
}

const Profile* find_profile(std::string_view name) {
  if (name == kSwg091n2.name) return &kSwg091n2;
  return nullptr;
}

std::vector<std::string_view> profile_names() {
  return {kSwg091n2.name};
}

}  // namespace dat
