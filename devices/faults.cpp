#include "devices/faults.hpp"

#include <charconv>
#include <sstream>

namespace devices {

Result<FaultSpec> parse_fault_spec(const std::string& text) {
  FaultSpec spec;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item.empty()) continue;
    const auto eq = item.find('=');
    if (eq == std::string::npos) {
      return make_error(ErrorClass::InvalidArgument,
                        "fault '" + item + "' needs a value (KEY=VALUE)");
    }
    const std::string key = item.substr(0, eq);
    const std::string value = item.substr(eq + 1);
    const auto bad = [&](const char* what) {
      return make_error(ErrorClass::InvalidArgument,
                        "fault " + key + "=" + value + ": the value must be " + what);
    };
    if (key == "corrupt" || key == "drop" || key == "dup") {
      char* end = nullptr;
      const double p = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || !(p >= 0 && p <= 1)) {
        return bad("a probability from 0 to 1");
      }
      (key == "corrupt" ? spec.corrupt : key == "drop" ? spec.drop : spec.dup) = p;
      continue;
    }
    std::uint32_t n = 0;
    const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), n);
    const bool is_count = ec == std::errc() && ptr == value.data() + value.size();
    if (key == "disconnect-every" || key == "reboot-every" || key == "stall-ms" ||
        key == "yarn-break-at" || key == "stop-at") {
      if (!is_count) return bad("a whole number");
      if (key == "disconnect-every") spec.disconnect_every = n;
      if (key == "reboot-every") spec.reboot_every = n;
      if (key == "stall-ms") spec.stall_ms = n;
      if (key == "yarn-break-at") spec.yarn_break_at = n;
      if (key == "stop-at") spec.stop_at = n;
      continue;
    }
    return make_error(ErrorClass::InvalidArgument,
                      "unknown fault '" + key +
                          "' (known: corrupt, drop, dup, disconnect-every, reboot-every, "
                          "stall-ms, yarn-break-at, stop-at)");
  }
  return spec;
}

bool FaultInjector::chance(double p) {
  if (p <= 0) return false;
  return std::uniform_real_distribution<double>(0, 1)(rng_) < p;
}

std::vector<Bytes> FaultInjector::pass(Bytes bytes) {
  std::vector<Bytes> out;
  if (chance(spec_.drop)) return out;
  const int copies = chance(spec_.dup) ? 2 : 1;
  for (int i = 0; i < copies; ++i) {
    Bytes copy = bytes;
    if (!copy.empty() && chance(spec_.corrupt)) {
      const std::size_t at = rng_() % copy.size();
      copy[at] = static_cast<std::uint8_t>(copy[at] ^ (1u << (rng_() % 8)));
    }
    out.push_back(std::move(copy));
  }
  return out;
}

FaultInjector::Event FaultInjector::after_received_frame() {
  ++received_;
  if (spec_.reboot_every != 0 && received_ % spec_.reboot_every == 0) return Event::Reboot;
  if (spec_.disconnect_every != 0 && received_ % spec_.disconnect_every == 0) {
    return Event::Disconnect;
  }
  return Event::None;
}

std::uint32_t FaultInjector::stall_now() {
  return spec_.stall_ms != 0 && received_ != 0 && received_ % 50 == 0 ? spec_.stall_ms : 0;
}

}  // namespace devices
