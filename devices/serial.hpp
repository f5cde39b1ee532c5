// Serial ports through libserialport, called only through SerialApi: the
// real implementation forwards to libserialport (tracing each call under
// WEARKNIT_DEVICE_DEBUG=1); tests pass a fake that injects short reads,
// timeouts and unplugs.
#pragma once

#include <libserialport.h>

#include <memory>
#include <string>
#include <vector>

#include "devices/result.hpp"
#include "devices/transport.hpp"

namespace devices {

// The libserialport calls wearknit makes, one virtual per call.
class SerialApi {
 public:
  virtual ~SerialApi() = default;
  virtual sp_return get_port_by_name(const char* name, sp_port** port) = 0;
  virtual void free_port(sp_port* port) = 0;
  virtual sp_return list_ports(sp_port*** list) = 0;
  virtual void free_port_list(sp_port** list) = 0;
  virtual sp_return open(sp_port* port, sp_mode mode) = 0;
  virtual sp_return close(sp_port* port) = 0;
  virtual sp_return set_baudrate(sp_port* port, int baud) = 0;
  virtual sp_return set_bits(sp_port* port, int bits) = 0;
  virtual sp_return set_parity(sp_port* port, sp_parity parity) = 0;
  virtual sp_return set_stopbits(sp_port* port, int stopbits) = 0;
  virtual sp_return set_flowcontrol(sp_port* port, sp_flowcontrol flow) = 0;
  virtual sp_return flush(sp_port* port, sp_buffer buffers) = 0;
  virtual sp_return blocking_write(sp_port* port, const void* buf, size_t count,
                                   unsigned timeout_ms) = 0;
  virtual sp_return blocking_read_next(sp_port* port, void* buf, size_t count,
                                       unsigned timeout_ms) = 0;
  virtual sp_return input_waiting(sp_port* port) = 0;
  virtual const char* port_name(sp_port* port) = 0;
  virtual const char* port_description(sp_port* port) = 0;
  virtual sp_transport port_transport(sp_port* port) = 0;
  virtual sp_return port_usb_vid_pid(sp_port* port, int* vid, int* pid) = 0;
  virtual std::string last_error_message() = 0;
};

SerialApi& real_serial_api();

// Opens PATH at `baud`, 8N1, no flow control.
Result<std::unique_ptr<Transport>> open_serial(SerialApi& api, const std::string& path, int baud);

struct SerialPortInfo {
  std::string name;
  std::string description;
  bool usb = false;
  int vid = -1;
  int pid = -1;
};

Result<std::vector<SerialPortInfo>> list_serial_ports(SerialApi& api);

}  // namespace devices
