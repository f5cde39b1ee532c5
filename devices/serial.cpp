#include "devices/serial.hpp"

#include <cstdio>

#include "devices/debug.hpp"

namespace devices {
namespace {

std::string rc(sp_return r) {
  return std::to_string(static_cast<int>(r));
}

class RealSerialApi final : public SerialApi {
 public:
  sp_return get_port_by_name(const char* name, sp_port** port) override {
    return traced("sp_get_port_by_name(" + std::string(name) + ")",
                  sp_get_port_by_name(name, port));
  }
  void free_port(sp_port* port) override {
    debug_line("sp_free_port");
    sp_free_port(port);
  }
  sp_return list_ports(sp_port*** list) override {
    return traced("sp_list_ports", sp_list_ports(list));
  }
  void free_port_list(sp_port** list) override {
    debug_line("sp_free_port_list");
    sp_free_port_list(list);
  }
  sp_return open(sp_port* port, sp_mode mode) override {
    return traced("sp_open", sp_open(port, mode));
  }
  sp_return close(sp_port* port) override { return traced("sp_close", sp_close(port)); }
  sp_return set_baudrate(sp_port* port, int baud) override {
    return traced("sp_set_baudrate(" + std::to_string(baud) + ")", sp_set_baudrate(port, baud));
  }
  sp_return set_bits(sp_port* port, int bits) override {
    return traced("sp_set_bits", sp_set_bits(port, bits));
  }
  sp_return set_parity(sp_port* port, sp_parity parity) override {
    return traced("sp_set_parity", sp_set_parity(port, parity));
  }
  sp_return set_stopbits(sp_port* port, int stopbits) override {
    return traced("sp_set_stopbits", sp_set_stopbits(port, stopbits));
  }
  sp_return set_flowcontrol(sp_port* port, sp_flowcontrol flow) override {
    return traced("sp_set_flowcontrol", sp_set_flowcontrol(port, flow));
  }
  sp_return flush(sp_port* port, sp_buffer buffers) override {
    return traced("sp_flush", sp_flush(port, buffers));
  }
  sp_return blocking_write(sp_port* port, const void* buf, size_t count,
                           unsigned timeout_ms) override {
    return traced("sp_blocking_write(" + std::to_string(count) + ")",
                  sp_blocking_write(port, buf, count, timeout_ms));
  }
  sp_return blocking_read_next(sp_port* port, void* buf, size_t count,
                               unsigned timeout_ms) override {
    return traced("sp_blocking_read_next(" + std::to_string(count) + ")",
                  sp_blocking_read_next(port, buf, count, timeout_ms));
  }
  sp_return input_waiting(sp_port* port) override {
    return traced("sp_input_waiting", sp_input_waiting(port));
  }
  const char* port_name(sp_port* port) override { return sp_get_port_name(port); }
  const char* port_description(sp_port* port) override { return sp_get_port_description(port); }
  sp_transport port_transport(sp_port* port) override { return sp_get_port_transport(port); }
  sp_return port_usb_vid_pid(sp_port* port, int* vid, int* pid) override {
    return sp_get_port_usb_vid_pid(port, vid, pid);
  }
  std::string last_error_message() override {
    char* message = sp_last_error_message();
    std::string text = message != nullptr ? message : "unknown error";
    sp_free_error_message(message);
    return text;
  }

 private:
  static sp_return traced(const std::string& call, sp_return result) {
    if (debug_enabled()) debug_line(call + " -> " + rc(result));
    return result;
  }
};

class SerialTransport final : public Transport {
 public:
  SerialTransport(SerialApi& api, sp_port* port, std::string path)
      : api_(api), port_(port), path_(std::move(path)) {}
  ~SerialTransport() override {
    api_.close(port_);
    api_.free_port(port_);
  }

  Outcome write_all(std::span<const std::uint8_t> bytes, int timeout_ms) override {
    const sp_return n = api_.blocking_write(port_, bytes.data(), bytes.size(),
                                            static_cast<unsigned>(std::max(timeout_ms, 1)));
    if (n < 0) {
      // After a hang-up libserialport fails every call with SP_ERR_FAIL.
      return make_error(ErrorClass::Disconnected,
                        "serial:" + path_ + ": write failed: " + api_.last_error_message());
    }
    if (static_cast<std::size_t>(n) < bytes.size()) {
      return make_error(ErrorClass::Timeout, "serial:" + path_ + ": wrote " + std::to_string(n) +
                                                 " of " + std::to_string(bytes.size()) +
                                                 " bytes in " + std::to_string(timeout_ms) + " ms");
    }
    return Ok{};
  }

  Result<std::size_t> read_some(std::span<std::uint8_t> buffer, int timeout_ms) override {
    const sp_return n = api_.blocking_read_next(port_, buffer.data(), buffer.size(),
                                                static_cast<unsigned>(std::max(timeout_ms, 1)));
    if (n < 0) {
      return make_error(ErrorClass::Disconnected,
                        "serial:" + path_ + ": read failed: " + api_.last_error_message());
    }
    if (n == 0 && api_.input_waiting(port_) < 0) {
      // A hung-up port reads as "no data" forever; only input_waiting tells
      // (transport notes §2a).
      return make_error(ErrorClass::Disconnected, "serial:" + path_ + ": the port hung up");
    }
    return static_cast<std::size_t>(n);
  }

  std::string describe() const override { return "serial:" + path_; }

 private:
  SerialApi& api_;
  sp_port* port_;
  std::string path_;
};

}  // namespace

SerialApi& real_serial_api() {
  static RealSerialApi api;
  return api;
}

Result<std::unique_ptr<Transport>> open_serial(SerialApi& api, const std::string& path, int baud) {
  sp_port* port = nullptr;
  if (api.get_port_by_name(path.c_str(), &port) != SP_OK) {
    return make_error(ErrorClass::InvalidArgument, "serial:" + path + ": no such serial port (" +
                                                       api.last_error_message() + ")");
  }
  if (const sp_return r = api.open(port, SP_MODE_READ_WRITE); r != SP_OK) {
    const std::string why = api.last_error_message();
    api.free_port(port);
    return make_error(r == SP_ERR_SUPP ? ErrorClass::Unsupported : ErrorClass::OsFailure,
                      "serial:" + path + ": cannot open: " + why);
  }
  if (api.set_baudrate(port, baud) != SP_OK || api.set_bits(port, 8) != SP_OK ||
      api.set_parity(port, SP_PARITY_NONE) != SP_OK || api.set_stopbits(port, 1) != SP_OK ||
      api.set_flowcontrol(port, SP_FLOWCONTROL_NONE) != SP_OK) {
    const std::string why = api.last_error_message();
    api.close(port);
    api.free_port(port);
    return make_error(ErrorClass::Unsupported,
                      "serial:" + path + ": cannot set " + std::to_string(baud) + " 8N1: " + why);
  }
  // Bytes from before this connection answer questions nobody asks any more.
  api.flush(port, SP_BUF_BOTH);
  return std::unique_ptr<Transport>(std::make_unique<SerialTransport>(api, port, path));
}

Result<std::vector<SerialPortInfo>> list_serial_ports(SerialApi& api) {
  sp_port** list = nullptr;
  if (api.list_ports(&list) != SP_OK) {
    return make_error(ErrorClass::OsFailure,
                      "cannot list serial ports: " + api.last_error_message());
  }
  std::vector<SerialPortInfo> ports;
  for (sp_port** p = list; p != nullptr && *p != nullptr; ++p) {
    SerialPortInfo info;
    const char* name = api.port_name(*p);
    const char* description = api.port_description(*p);
    info.name = name != nullptr ? name : "";
    info.description = description != nullptr ? description : "";
    info.usb = api.port_transport(*p) == SP_TRANSPORT_USB;
    if (info.usb) api.port_usb_vid_pid(*p, &info.vid, &info.pid);
    ports.push_back(std::move(info));
  }
  if (list != nullptr) api.free_port_list(list);
  return ports;
}

}  // namespace devices
