// USB bulk transport through libusb-1.0, called only through UsbApi (the
// real one forwards to libusb and traces under WEARKNIT_DEVICE_DEBUG=1;
// tests may pass fakes). A machine is found by VID:PID (and serial number
// when given); the first interface with a bulk IN and a bulk OUT endpoint
// carries the protocol's byte stream.
#pragma once

#include <libusb-1.0/libusb.h>

#include <memory>
#include <string>
#include <vector>

#include "devices/result.hpp"
#include "devices/transport.hpp"

namespace devices {

class UsbApi {
 public:
  virtual ~UsbApi() = default;
  virtual int init(libusb_context** context) = 0;
  virtual void exit(libusb_context* context) = 0;
  virtual ssize_t get_device_list(libusb_context* context, libusb_device*** list) = 0;
  virtual void free_device_list(libusb_device** list) = 0;
  virtual int get_device_descriptor(libusb_device* device, libusb_device_descriptor* out) = 0;
  virtual int get_active_config_descriptor(libusb_device* device,
                                           libusb_config_descriptor** out) = 0;
  virtual void free_config_descriptor(libusb_config_descriptor* config) = 0;
  virtual int open(libusb_device* device, libusb_device_handle** handle) = 0;
  virtual void close(libusb_device_handle* handle) = 0;
  virtual int claim_interface(libusb_device_handle* handle, int interface_number) = 0;
  virtual int release_interface(libusb_device_handle* handle, int interface_number) = 0;
  virtual int bulk_transfer(libusb_device_handle* handle, unsigned char endpoint,
                            unsigned char* data, int length, int* transferred,
                            unsigned int timeout_ms) = 0;
  virtual int get_string_descriptor_ascii(libusb_device_handle* handle, uint8_t index,
                                          unsigned char* data, int length) = 0;
  virtual uint8_t get_bus_number(libusb_device* device) = 0;
  virtual uint8_t get_device_address(libusb_device* device) = 0;
};

UsbApi& real_usb_api();

Result<std::unique_ptr<Transport>> open_usb(UsbApi& api, std::uint16_t vid, std::uint16_t pid,
                                            const std::string& serial_number);

struct UsbDeviceInfo {
  int bus = 0;
  int address = 0;
  std::uint16_t vid = 0;
  std::uint16_t pid = 0;
  std::string manufacturer;  // empty when the device could not be opened
  std::string product;
  std::string serial_number;
};

Result<std::vector<UsbDeviceInfo>> list_usb_devices(UsbApi& api);

}  // namespace devices
