// Transports: byte streams to a machine, named by URIs (docs/devices.md).
//
//   tcp://HOST:PORT          a TCP connection (TCP_NODELAY: frames are small)
//   serial:PATH?baud=N       a serial port through libserialport (default 115200 8N1)
//   usb://VID:PID[/SERIAL]   USB bulk endpoints through libusb-1.0 (hex VID:PID)
//   dir:PATH                 a mounted USB stick or network folder: file drop, no stream
//   loopback:[STORE]         the mock machine, in this process
//   pty:                     listening only: the mock machine on a new pseudo-terminal
//
// Every call returns a Result; nothing throws on I/O failure.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "devices/result.hpp"

namespace devices {

struct DeviceUri {
  enum class Kind { Tcp, Serial, Usb, Dir, Loopback, Pty };
  Kind kind = Kind::Tcp;
  std::string text;  // as given
  std::string host;
  std::uint16_t port = 0;
  std::string path;  // serial device, dir folder, loopback store
  int baud = 115200;
  std::uint16_t vid = 0;
  std::uint16_t pid = 0;
  std::string serial_number;
};

// InvalidArgument naming what is wrong with the URI.
Result<DeviceUri> parse_uri(const std::string& text);

class Transport {
 public:
  virtual ~Transport() = default;
  // Writes every byte or fails (Timeout when the peer does not drain within
  // timeout_ms, Disconnected when it is gone).
  virtual Outcome write_all(std::span<const std::uint8_t> bytes, int timeout_ms) = 0;
  // Reads what arrives within timeout_ms (at least 1 ms): 0 bytes means
  // nothing came; Disconnected means the peer or the cable went away.
  virtual Result<std::size_t> read_some(std::span<std::uint8_t> buffer, int timeout_ms) = 0;
  virtual std::string describe() const = 0;
};

// Opens a stream transport (tcp, serial, usb, loopback). dir: is a file
// drop and has no stream: see folder_drop.hpp.
Result<std::unique_ptr<Transport>> open_transport(const DeviceUri& uri);

// A stream over a connected file descriptor (a socket or a terminal),
// which it owns and closes.
std::unique_ptr<Transport> make_fd_transport(int fd, std::string description, bool is_socket);

}  // namespace devices
