#include "devices/usb.hpp"

#include <cstdio>

#include "devices/debug.hpp"

namespace devices {
namespace {

int traced(const std::string& call, int result) {
  if (debug_enabled()) {
    debug_line(call + " -> " + (result < 0 ? libusb_error_name(result) : std::to_string(result)));
  }
  return result;
}

class RealUsbApi final : public UsbApi {
 public:
  int init(libusb_context** context) override {
    return traced("libusb_init", libusb_init(context));
  }
  void exit(libusb_context* context) override {
    debug_line("libusb_exit");
    libusb_exit(context);
  }
  ssize_t get_device_list(libusb_context* context, libusb_device*** list) override {
    const ssize_t n = libusb_get_device_list(context, list);
    traced("libusb_get_device_list", static_cast<int>(n));
    return n;
  }
  void free_device_list(libusb_device** list) override { libusb_free_device_list(list, 1); }
  int get_device_descriptor(libusb_device* device, libusb_device_descriptor* out) override {
    return traced("libusb_get_device_descriptor", libusb_get_device_descriptor(device, out));
  }
  int get_active_config_descriptor(libusb_device* device, libusb_config_descriptor** out) override {
    return traced("libusb_get_active_config_descriptor",
                  libusb_get_active_config_descriptor(device, out));
  }
  void free_config_descriptor(libusb_config_descriptor* config) override {
    libusb_free_config_descriptor(config);
  }
  int open(libusb_device* device, libusb_device_handle** handle) override {
    return traced("libusb_open", libusb_open(device, handle));
  }
  void close(libusb_device_handle* handle) override {
    debug_line("libusb_close");
    libusb_close(handle);
  }
  int claim_interface(libusb_device_handle* handle, int interface_number) override {
    return traced("libusb_claim_interface(" + std::to_string(interface_number) + ")",
                  libusb_claim_interface(handle, interface_number));
  }
  int release_interface(libusb_device_handle* handle, int interface_number) override {
    return traced("libusb_release_interface", libusb_release_interface(handle, interface_number));
  }
  int bulk_transfer(libusb_device_handle* handle, unsigned char endpoint, unsigned char* data,
                    int length, int* transferred, unsigned int timeout_ms) override {
    const int r = libusb_bulk_transfer(handle, endpoint, data, length, transferred, timeout_ms);
    if (debug_enabled()) {
      char ep[8];
      std::snprintf(ep, sizeof ep, "0x%02x", endpoint);
      traced(std::string("libusb_bulk_transfer(") + ep + ", " + std::to_string(length) +
                 ") transferred " + std::to_string(*transferred),
             r);
    }
    return r;
  }
  int get_string_descriptor_ascii(libusb_device_handle* handle, uint8_t index, unsigned char* data,
                                  int length) override {
    return traced("libusb_get_string_descriptor_ascii",
                  libusb_get_string_descriptor_ascii(handle, index, data, length));
  }
  uint8_t get_bus_number(libusb_device* device) override { return libusb_get_bus_number(device); }
  uint8_t get_device_address(libusb_device* device) override {
    return libusb_get_device_address(device);
  }
};

Error usb_error(const std::string& what, int code) {
  const ErrorClass c = code == LIBUSB_ERROR_NO_DEVICE       ? ErrorClass::Disconnected
                       : code == LIBUSB_ERROR_TIMEOUT       ? ErrorClass::Timeout
                       : code == LIBUSB_ERROR_NOT_SUPPORTED ? ErrorClass::Unsupported
                       : code == LIBUSB_ERROR_INVALID_PARAM ? ErrorClass::InvalidArgument
                                                            : ErrorClass::OsFailure;
  return make_error(c, what + ": " + libusb_error_name(code));
}

std::string read_string(UsbApi& api, libusb_device_handle* handle, uint8_t index) {
  if (index == 0) return {};
  unsigned char text[256];
  const int n = api.get_string_descriptor_ascii(handle, index, text, sizeof text);
  if (n <= 0) return {};
  return std::string(reinterpret_cast<char*>(text), static_cast<std::size_t>(n));
}

class UsbTransport final : public Transport {
 public:
  UsbTransport(UsbApi& api, libusb_context* context, libusb_device_handle* handle,
               int interface_number, unsigned char in, unsigned char out, std::string name)
      : api_(api),
        context_(context),
        handle_(handle),
        interface_(interface_number),
        in_(in),
        out_(out),
        name_(std::move(name)) {}
  ~UsbTransport() override {
    api_.release_interface(handle_, interface_);
    api_.close(handle_);
    api_.exit(context_);
  }

  Outcome write_all(std::span<const std::uint8_t> bytes, int timeout_ms) override {
    std::size_t done = 0;
    while (done < bytes.size()) {
      int transferred = 0;
      const int chunk = static_cast<int>(std::min<std::size_t>(bytes.size() - done, 1 << 16));
      const int r =
          api_.bulk_transfer(handle_, out_, const_cast<unsigned char*>(bytes.data() + done), chunk,
                             &transferred, static_cast<unsigned>(std::max(timeout_ms, 1)));
      done += static_cast<std::size_t>(std::max(transferred, 0));
      if (r != 0) return usb_error(name_ + ": bulk OUT", r);
    }
    return Ok{};
  }

  Result<std::size_t> read_some(std::span<std::uint8_t> buffer, int timeout_ms) override {
    // A multiple of every bulk packet size, so a packet never overflows.
    const int length = static_cast<int>(std::min<std::size_t>(buffer.size(), 16384) & ~511u);
    int transferred = 0;
    const int r = api_.bulk_transfer(handle_, in_, buffer.data(), length, &transferred,
                                     static_cast<unsigned>(std::max(timeout_ms, 1)));
    if (r == 0 || r == LIBUSB_ERROR_TIMEOUT) return static_cast<std::size_t>(transferred);
    return usb_error(name_ + ": bulk IN", r);
  }

  std::string describe() const override { return name_; }

 private:
  UsbApi& api_;
  libusb_context* context_;
  libusb_device_handle* handle_;
  int interface_;
  unsigned char in_;
  unsigned char out_;
  std::string name_;
};

// First interface with one bulk IN and one bulk OUT endpoint.
bool find_bulk_pair(UsbApi& api, libusb_device* device, int& interface_number, unsigned char& in,
                    unsigned char& out) {
  libusb_config_descriptor* config = nullptr;
  if (api.get_active_config_descriptor(device, &config) != 0) return false;
  bool found = false;
  for (int i = 0; i < config->bNumInterfaces && !found; ++i) {
    const libusb_interface& iface = config->interface[i];
    for (int a = 0; a < iface.num_altsetting && !found; ++a) {
      const libusb_interface_descriptor& alt = iface.altsetting[a];
      int bulk_in = -1;
      int bulk_out = -1;
      for (int e = 0; e < alt.bNumEndpoints; ++e) {
        const libusb_endpoint_descriptor& ep = alt.endpoint[e];
        if ((ep.bmAttributes & 3) != LIBUSB_TRANSFER_TYPE_BULK) continue;
        if (ep.bEndpointAddress & LIBUSB_ENDPOINT_IN) {
          if (bulk_in < 0) bulk_in = ep.bEndpointAddress;
        } else if (bulk_out < 0) {
          bulk_out = ep.bEndpointAddress;
        }
      }
      if (bulk_in >= 0 && bulk_out >= 0) {
        interface_number = alt.bInterfaceNumber;
        in = static_cast<unsigned char>(bulk_in);
        out = static_cast<unsigned char>(bulk_out);
        found = true;
      }
    }
  }
  api.free_config_descriptor(config);
  return found;
}

std::string usb_name(std::uint16_t vid, std::uint16_t pid, const std::string& serial) {
  char text[32];
  std::snprintf(text, sizeof text, "usb://%04x:%04x", vid, pid);
  return std::string(text) + (serial.empty() ? "" : "/" + serial);
}

}  // namespace

UsbApi& real_usb_api() {
  static RealUsbApi api;
  return api;
}

Result<std::unique_ptr<Transport>> open_usb(UsbApi& api, std::uint16_t vid, std::uint16_t pid,
                                            const std::string& serial_number) {
  const std::string name = usb_name(vid, pid, serial_number);
  libusb_context* context = nullptr;
  if (const int r = api.init(&context); r != 0) return usb_error(name + ": libusb_init", r);
  libusb_device** list = nullptr;
  const ssize_t count = api.get_device_list(context, &list);
  if (count < 0) {
    api.exit(context);
    return usb_error(name + ": cannot list USB devices", static_cast<int>(count));
  }
  std::string last_problem = "no such device";
  for (ssize_t i = 0; i < count; ++i) {
    libusb_device_descriptor d{};
    if (api.get_device_descriptor(list[i], &d) != 0 || d.idVendor != vid || d.idProduct != pid) {
      continue;
    }
    libusb_device_handle* handle = nullptr;
    if (const int r = api.open(list[i], &handle); r != 0) {
      last_problem = std::string("cannot open: ") + libusb_error_name(r);
      continue;
    }
    if (!serial_number.empty() && read_string(api, handle, d.iSerialNumber) != serial_number) {
      api.close(handle);
      last_problem = "no device with serial number " + serial_number;
      continue;
    }
    int interface_number = 0;
    unsigned char in = 0;
    unsigned char out = 0;
    if (!find_bulk_pair(api, list[i], interface_number, in, out)) {
      api.close(handle);
      last_problem = "the device has no interface with bulk IN and OUT endpoints";
      continue;
    }
    if (const int r = api.claim_interface(handle, interface_number); r != 0) {
      api.close(handle);
      last_problem = std::string("cannot claim its interface: ") + libusb_error_name(r);
      continue;
    }
    api.free_device_list(list);
    return std::unique_ptr<Transport>(
        std::make_unique<UsbTransport>(api, context, handle, interface_number, in, out, name));
  }
  api.free_device_list(list);
  api.exit(context);
  return make_error(ErrorClass::Disconnected, name + ": " + last_problem);
}

Result<std::vector<UsbDeviceInfo>> list_usb_devices(UsbApi& api) {
  libusb_context* context = nullptr;
  if (const int r = api.init(&context); r != 0) return usb_error("libusb_init", r);
  libusb_device** list = nullptr;
  const ssize_t count = api.get_device_list(context, &list);
  if (count < 0) {
    api.exit(context);
    return usb_error("cannot list USB devices", static_cast<int>(count));
  }
  std::vector<UsbDeviceInfo> devices;
  for (ssize_t i = 0; i < count; ++i) {
    libusb_device_descriptor d{};
    if (api.get_device_descriptor(list[i], &d) != 0) continue;
    UsbDeviceInfo info;
    info.bus = api.get_bus_number(list[i]);
    info.address = api.get_device_address(list[i]);
    info.vid = d.idVendor;
    info.pid = d.idProduct;
    libusb_device_handle* handle = nullptr;
    if (api.open(list[i], &handle) == 0) {
      info.manufacturer = read_string(api, handle, d.iManufacturer);
      info.product = read_string(api, handle, d.iProduct);
      info.serial_number = read_string(api, handle, d.iSerialNumber);
      api.close(handle);
    }
    devices.push_back(std::move(info));
  }
  api.free_device_list(list);
  api.exit(context);
  return devices;
}

}  // namespace devices
