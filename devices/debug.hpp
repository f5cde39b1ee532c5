// Call tracing for the device layer: with WEARKNIT_DEVICE_DEBUG=1 in the
// environment every seam call (libserialport, libusb, sockets) and every
// protocol frame is written to stderr as one line `wearknit-dev: ...`,
// the way LIBSERIALPORT_DEBUG does for libserialport.
#pragma once

#include <string_view>

namespace devices {

bool debug_enabled();
void debug_line(std::string_view text);

}  // namespace devices
