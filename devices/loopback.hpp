// loopback: the mock machine inside this process, as a Transport. Bytes
// written are de-framed and handed to a DeviceEngine on the store folder;
// its answers are read back. No faults: see mock_server.hpp for those.
#pragma once

#include <memory>
#include <string>

#include "devices/job.hpp"
#include "devices/transport.hpp"

namespace devices {

Result<std::unique_ptr<Transport>> open_loopback(const std::string& store,
                                                 const JobCheckers& checkers = {});

}  // namespace devices
