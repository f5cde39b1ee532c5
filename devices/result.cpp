#include "devices/result.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "devices/debug.hpp"

namespace devices {

std::string_view to_string(ErrorClass error_class) {
  switch (error_class) {
    case ErrorClass::InvalidArgument:
      return "invalid argument";
    case ErrorClass::OsFailure:
      return "OS failure";
    case ErrorClass::Unsupported:
      return "unsupported";
    case ErrorClass::Timeout:
      return "timeout";
    case ErrorClass::Disconnected:
      return "disconnected";
    case ErrorClass::Protocol:
      return "protocol error";
  }
  return "unknown";
}

std::string Error::text() const {
  if (error_class == ErrorClass::OsFailure && os_errno != 0) {
    return message + ": " + std::strerror(os_errno);
  }
  return message;
}

Error make_error(ErrorClass error_class, std::string message) {
  return Error{error_class, std::move(message), 0};
}

Error os_error(std::string message, int saved_errno) {
  return Error{ErrorClass::OsFailure, std::move(message), saved_errno};
}

bool debug_enabled() {
  static const bool enabled = [] {
    const char* value = std::getenv("WEARKNIT_DEVICE_DEBUG");
    return value != nullptr && std::strcmp(value, "0") != 0 && *value != '\0';
  }();
  return enabled;
}

void debug_line(std::string_view text) {
  if (!debug_enabled()) return;
  // One write per line so lines from the mock's threads do not interleave.
  static std::mutex mutex;
  std::lock_guard lock(mutex);
  const double t =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  std::fprintf(stderr, "wearknit-dev: %.6f %.*s\n", t, static_cast<int>(text.size()), text.data());
}

}  // namespace devices
