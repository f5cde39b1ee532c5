// The mock knitting machine as a server on a real link: `wearknit
// mock-device --listen URI`. It listens on tcp://HOST:PORT (any number of
// hosts at once; port 0 picks a free port), on a new pseudo-terminal (pty:)
// or on a serial device (serial:PATH), feeds every frame to a DeviceEngine
// and applies the faults of FaultSpec to what crosses the link.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "devices/device_engine.hpp"
#include "devices/faults.hpp"
#include "devices/transport.hpp"

namespace devices {

struct MockServerOptions {
  DeviceUri listen;
  DeviceConfig device;
  FaultSpec faults;
  std::uint64_t seed = 1;
  // Called once listening, with the URI hosts should use (real port, pty path).
  std::function<void(const std::string& uri)> on_listening;
  // Stop when this turns true (checked every few milliseconds).
  const std::atomic<bool>* stop = nullptr;
  // Return once a job reaches done, refused or cancelled (after a grace
  // period in which hosts still get answers).
  bool exit_when_job_ends = false;
};

// Runs until stopped. Errors: the listen URI cannot be served.
Outcome run_mock_server(MockServerOptions options);

}  // namespace devices
