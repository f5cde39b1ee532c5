// Fault injection for the mock device (`--fault SPEC`) and the simulations:
//   corrupt=P          each frame, either way, has one bit flipped with probability P
//   drop=P             each frame, either way, is lost with probability P
//   dup=P              each frame, either way, arrives twice with probability P
//   disconnect-every=N the link is cut after every N-th frame received
//   reboot-every=N     the device power-cycles after every N-th frame received
//   stall-ms=N         the device stops reading for N ms after every 50th frame
//   yarn-break-at=ROW  a yarn-break alarm when the knitted count reaches ROW
//   stop-at=ROW        a stop alarm when the knitted count reaches ROW
// Randomness comes from one seeded generator, so a run is repeatable.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "devices/framing.hpp"
#include "devices/result.hpp"

namespace devices {

struct FaultSpec {
  double corrupt = 0;
  double drop = 0;
  double dup = 0;
  std::uint32_t disconnect_every = 0;
  std::uint32_t reboot_every = 0;
  std::uint32_t stall_ms = 0;
  std::uint32_t yarn_break_at = 0;
  std::uint32_t stop_at = 0;
};

// Parses "key=value,..."; an unknown key or a bad value is an
// InvalidArgument error naming it.
Result<FaultSpec> parse_fault_spec(const std::string& text);

class FaultInjector {
 public:
  enum class Event { None, Disconnect, Reboot };

  FaultInjector(FaultSpec spec, std::uint64_t seed) : spec_(spec), rng_(seed) {}

  // What becomes of one frame crossing the link (`bytes` is the frame before
  // or after SLIP): zero, one or two copies, maybe with a flipped bit.
  std::vector<Bytes> pass(Bytes bytes);
  // Counts a frame the device received; says whether the link is cut or the
  // device power-cycles now.
  Event after_received_frame();
  // Milliseconds the device should stall now (0 most of the time).
  std::uint32_t stall_now();
  const FaultSpec& spec() const { return spec_; }

 private:
  bool chance(double p);
  FaultSpec spec_;
  std::mt19937_64 rng_;
  std::uint64_t received_ = 0;
};

}  // namespace devices
