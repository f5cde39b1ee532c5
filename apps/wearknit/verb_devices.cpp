// wearknit devices: list serial ports and USB devices.
#include <cstdio>
#include <iostream>

#include "apps/wearknit/cli.hpp"
#include "devices/serial.hpp"
#include "devices/usb.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

namespace {
std::string hex4(int value) {
  char text[8];
  std::snprintf(text, sizeof text, "%04x", value & 0xFFFF);
  return text;
}
}  // namespace

int run_devices(const std::vector<std::string>& args, Context& context) {
  po::options_description options("options");
  po::positional_options_description positional;
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("devices"), options, positional, values, context)) {
    return *code;
  }
  int status = kExitOk;
  context.out << "serial ports:\n";
  auto ports = devices::list_serial_ports(devices::real_serial_api());
  if (!ports) {
    context.err << "wearknit devices: " << ports.error().text() << '\n';
    status = kExitUsage;
  } else if (ports.value().empty()) {
    context.out << "  (none)\n";
  } else {
    for (const devices::SerialPortInfo& p : ports.value()) {
      context.out << "  serial:" << p.name << "  " << p.description;
      if (p.usb) context.out << "  USB " << hex4(p.vid) << ':' << hex4(p.pid);
      context.out << '\n';
    }
  }
  context.out << "USB devices:\n";
  auto usb = devices::list_usb_devices(devices::real_usb_api());
  if (!usb) {
    context.err << "wearknit devices: " << usb.error().text() << '\n';
    status = kExitUsage;
  } else if (usb.value().empty()) {
    context.out << "  (none)\n";
  } else {
    for (const devices::UsbDeviceInfo& d : usb.value()) {
      context.out << "  usb://" << hex4(d.vid) << ':' << hex4(d.pid)
                  << (d.serial_number.empty() ? "" : "/" + d.serial_number) << "  bus " << d.bus
                  << " device " << d.address;
      if (!d.product.empty() || !d.manufacturer.empty()) {
        context.out << "  " << d.product
                    << (d.manufacturer.empty() ? "" : " (" + d.manufacturer + ")");
      }
      context.out << '\n';
    }
  }
  return status;
}

}  // namespace wearknit::cli
