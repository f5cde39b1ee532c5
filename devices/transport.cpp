#include "devices/transport.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <charconv>
#include <chrono>
#include <filesystem>

#include "devices/debug.hpp"
#include "devices/loopback.hpp"
#include "devices/serial.hpp"
#include "devices/usb.hpp"

namespace devices {
namespace {

bool parse_hex16(std::string_view text, std::uint16_t& out) {
  if (text.empty() || text.size() > 4) return false;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), out, 16);
  return ec == std::errc() && ptr == text.data() + text.size();
}

class FdTransport final : public Transport {
 public:
  FdTransport(int fd, std::string description, bool is_socket)
      : fd_(fd), description_(std::move(description)), is_socket_(is_socket) {}
  ~FdTransport() override { ::close(fd_); }

  Outcome write_all(std::span<const std::uint8_t> bytes, int timeout_ms) override {
    std::size_t done = 0;
    while (done < bytes.size()) {
      pollfd p{fd_, POLLOUT, 0};
      const int ready = ::poll(&p, 1, std::max(timeout_ms, 1));
      if (ready < 0 && errno == EINTR) continue;
      if (ready < 0) return os_error("poll on " + description_);
      if (ready == 0) {
        return make_error(ErrorClass::Timeout, description_ + ": the peer took no data for " +
                                                   std::to_string(timeout_ms) + " ms");
      }
      const ssize_t n = is_socket_
                            ? ::send(fd_, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL)
                            : ::write(fd_, bytes.data() + done, bytes.size() - done);
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (n < 0 && (errno == EPIPE || errno == ECONNRESET || errno == EIO)) {
        return make_error(ErrorClass::Disconnected, description_ + ": connection lost");
      }
      if (n < 0) return os_error("write to " + description_);
      done += static_cast<std::size_t>(n);
    }
    debug_line("fd write " + description_ + " " + std::to_string(bytes.size()) + " bytes");
    return Ok{};
  }

  Result<std::size_t> read_some(std::span<std::uint8_t> buffer, int timeout_ms) override {
    for (;;) {
      pollfd p{fd_, POLLIN, 0};
      const int ready = ::poll(&p, 1, std::max(timeout_ms, 1));
      if (ready < 0 && errno == EINTR) continue;
      if (ready < 0) return os_error("poll on " + description_);
      if (ready == 0) return std::size_t{0};
      const ssize_t n = ::read(fd_, buffer.data(), buffer.size());
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (n == 0 || (n < 0 && (errno == ECONNRESET || errno == EIO))) {
        return make_error(ErrorClass::Disconnected, description_ + ": connection closed");
      }
      if (n < 0) return os_error("read from " + description_);
      return static_cast<std::size_t>(n);
    }
  }

  std::string describe() const override { return description_; }

 private:
  int fd_;
  std::string description_;
  bool is_socket_;
};

Result<std::unique_ptr<Transport>> open_tcp(const DeviceUri& uri) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const std::string port = std::to_string(uri.port);
  const int rc = ::getaddrinfo(uri.host.c_str(), port.c_str(), &hints, &found);
  if (rc != 0) {
    return make_error(ErrorClass::InvalidArgument,
                      "cannot resolve " + uri.host + ": " + ::gai_strerror(rc));
  }
  int saved = 0;
  for (addrinfo* a = found; a != nullptr; a = a->ai_next) {
    const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      saved = errno;
      continue;
    }
    debug_line("tcp connect " + uri.host + ":" + port);
    if (::connect(fd, a->ai_addr, a->ai_addrlen) == 0) {
      ::freeaddrinfo(found);
      const int one = 1;
      // Small frames wait behind Nagle's algorithm for ~40-90 ms otherwise
      // (transport notes §2c).
      ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      return make_fd_transport(fd, uri.text, true);
    }
    saved = errno;
    ::close(fd);
  }
  ::freeaddrinfo(found);
  if (saved == ECONNREFUSED) {
    return Error{ErrorClass::Disconnected, "cannot connect to " + uri.text + ": nothing listens",
                 saved};
  }
  return os_error("cannot connect to " + uri.text, saved);
}

}  // namespace

std::unique_ptr<Transport> make_fd_transport(int fd, std::string description, bool is_socket) {
  return std::make_unique<FdTransport>(fd, std::move(description), is_socket);
}

Result<DeviceUri> parse_uri(const std::string& text) {
  DeviceUri uri;
  uri.text = text;
  const auto bad = [&](const std::string& why) {
    return make_error(ErrorClass::InvalidArgument, "device URI '" + text + "': " + why);
  };
  const auto starts = [&](std::string_view prefix) { return text.rfind(prefix, 0) == 0; };
  if (starts("tcp://")) {
    uri.kind = DeviceUri::Kind::Tcp;
    const std::string rest = text.substr(6);
    const auto colon = rest.rfind(':');
    if (colon == std::string::npos || colon == 0) return bad("expected tcp://HOST:PORT");
    uri.host = rest.substr(0, colon);
    if (uri.host.size() > 2 && uri.host.front() == '[' && uri.host.back() == ']') {
      uri.host = uri.host.substr(1, uri.host.size() - 2);
    }
    const std::string port = rest.substr(colon + 1);
    unsigned value = 0;
    const auto [ptr, ec] = std::from_chars(port.data(), port.data() + port.size(), value);
    if (port.empty() || ec != std::errc() || ptr != port.data() + port.size() || value > 65535) {
      return bad("the port must be a number from 0 to 65535");
    }
    uri.port = static_cast<std::uint16_t>(value);
    return uri;
  }
  if (starts("serial:")) {
    uri.kind = DeviceUri::Kind::Serial;
    std::string rest = text.substr(7);
    const auto q = rest.find('?');
    if (q != std::string::npos) {
      const std::string query = rest.substr(q + 1);
      rest = rest.substr(0, q);
      if (query.rfind("baud=", 0) != 0) return bad("the only option is ?baud=N");
      const std::string baud = query.substr(5);
      const auto [ptr, ec] = std::from_chars(baud.data(), baud.data() + baud.size(), uri.baud);
      if (baud.empty() || ec != std::errc() || ptr != baud.data() + baud.size() || uri.baud <= 0) {
        return bad("baud must be a positive number");
      }
    }
    if (rest.empty()) return bad("expected serial:PATH");
    uri.path = rest;
    return uri;
  }
  if (starts("usb://")) {
    uri.kind = DeviceUri::Kind::Usb;
    std::string rest = text.substr(6);
    const auto slash = rest.find('/');
    if (slash != std::string::npos) {
      uri.serial_number = rest.substr(slash + 1);
      rest = rest.substr(0, slash);
    }
    const auto colon = rest.find(':');
    if (colon == std::string::npos || !parse_hex16(rest.substr(0, colon), uri.vid) ||
        !parse_hex16(rest.substr(colon + 1), uri.pid)) {
      return bad("expected usb://VID:PID[/SERIAL] with VID and PID in hex");
    }
    return uri;
  }
  if (starts("dir:")) {
    uri.kind = DeviceUri::Kind::Dir;
    uri.path = text.substr(4);
    if (uri.path.empty()) return bad("expected dir:PATH");
    return uri;
  }
  if (starts("loopback:")) {
    uri.kind = DeviceUri::Kind::Loopback;
    uri.path = text.substr(9);
    if (uri.path.empty()) {
      uri.path = (std::filesystem::temp_directory_path() / "wearknit-loopback").string();
    }
    return uri;
  }
  if (text == "pty:") {
    uri.kind = DeviceUri::Kind::Pty;
    return uri;
  }
  return bad("expected tcp://HOST:PORT, serial:PATH, usb://VID:PID, dir:PATH or loopback:");
}

Result<std::unique_ptr<Transport>> open_transport(const DeviceUri& uri) {
  switch (uri.kind) {
    case DeviceUri::Kind::Tcp:
      return open_tcp(uri);
    case DeviceUri::Kind::Serial:
      return open_serial(real_serial_api(), uri.path, uri.baud);
    case DeviceUri::Kind::Usb:
      return open_usb(real_usb_api(), uri.vid, uri.pid, uri.serial_number);
    case DeviceUri::Kind::Loopback:
      return open_loopback(uri.path);
    case DeviceUri::Kind::Dir:
      return make_error(ErrorClass::Unsupported,
                        uri.text + ": a dir: target takes whole files, not a stream");
    case DeviceUri::Kind::Pty:
      return make_error(ErrorClass::Unsupported,
                        "pty: is for `mock-device --listen`; send to the serial:PATH it prints");
  }
  return make_error(ErrorClass::InvalidArgument, "unknown URI kind");
}

}  // namespace devices
