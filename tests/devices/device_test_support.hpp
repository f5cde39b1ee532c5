// Jobs and helpers shared by the device tests.
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "backends/dat/format.hpp"
#include "devices/device_engine.hpp"
#include "devices/job.hpp"

namespace devices::test {

// A plain stockinette sheet: cast-on tucks, then `passes` knit passes over
// needles 1..width alternating direction, then outhook.
inline std::string sheet_knitout(int width, int passes) {
  std::string k = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n;;Gauge: 15\ninhook 3\n";
  for (int n = width; n >= 1; --n) k += "tuck - f" + std::to_string(n) + " 3\n";
  k += "releasehook 3\n";
  for (int p = 0; p < passes; ++p) {
    const bool plus = p % 2 == 0;
    for (int i = 1; i <= width; ++i) {
      const int n = plus ? i : width + 1 - i;
      k += std::string("knit ") + (plus ? "+" : "-") + " f" + std::to_string(n) + " 3\n";
    }
    if (p % 3 == 2) k += "; pass " + std::to_string(p) + " done\n";
  }
  k += "outhook 3\n";
  return k;
}

inline Job make_sheet_job(const std::string& name, int width, int passes) {
  const std::string text = sheet_knitout(width, passes);
  auto job = make_job(name, Bytes(text.begin(), text.end()));
  if (!job) throw std::runtime_error(job.error().text());
  return std::move(job.value());
}

inline JobCheckers test_checkers() {
  JobCheckers c;
  c.knitout = check_knitout_syntax;
  return c;
}

// The DAT bomb: 34 MB of valid runs that fill a 65536 x 65536 raster
// (4 GiB of pixels once decoded).
inline Bytes make_dat_bomb() {
  Bytes bomb = dat::file_prefix(65536, 65536);
  Bytes row;
  for (int i = 0; i < 65536 / 255; ++i) row.insert(row.end(), {1, 255});
  row.insert(row.end(), {1, static_cast<std::uint8_t>(65536 % 255)});
  bomb.reserve(bomb.size() + row.size() * 65536);
  for (int y = 0; y < 65536; ++y) bomb.insert(bomb.end(), row.begin(), row.end());
  return bomb;
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace devices::test
