// The USB transport for real: unmodified libusb-1.0 talks to an in-process
// mock USB device through umockdev, which answers the usbdevfs ioctls
// (SUBMITURB, REAPURB, DISCARDURB, ...) here. Behind the device's bulk
// endpoints sits the mock machine's engine. Must run under
// `umockdev-wrapper` (ctest does); otherwise the tests skip, saying so.
#include <gtest/gtest.h>
#include <linux/usbdevice_fs.h>
#include <sys/ioctl.h>
#include <umockdev.h>

#include <chrono>
#include <cstddef>
#include <deque>
#include <mutex>

#include "devices/faults.hpp"
#include "devices/sender.hpp"
#include "devices/usb.hpp"
#include "tests/devices/device_test_support.hpp"
#include "tests/test_support.hpp"

namespace devices {
namespace {

bool in_mock_environment = false;
UMockdevTestbed* testbed = nullptr;

// Device 1209:4b4e: descriptors (device, configuration, one vendor interface
// with bulk IN 0x81 and bulk OUT 0x02, 512-byte packets).
#define WK_DESCRIPTORS \
  "1201000200000040"   \
  "09124E4B"           \
  "0001"               \
  "010203"             \
  "01"                 \
  "0902200001010080"   \
  "32"                 \
  "090400000"          \
  "2FF000000"          \
  "07058102000200"     \
  "07050202000200"
constexpr const char* kDevice =
    "P: /devices/pci0000:00/0000:00:14.0/usb1/1-2\n"
    "N: bus/usb/001/003=" WK_DESCRIPTORS
    "\n"
    "E: BUSNUM=001\nE: DEVNUM=003\nE: DEVNAME=/dev/bus/usb/001/003\nE: DEVTYPE=usb_device\n"
    "E: DRIVER=usb\nE: SUBSYSTEM=usb\n"
    "A: busnum=1\\n\nA: devnum=3\\n\nA: idVendor=1209\nA: idProduct=4b4e\nA: speed=480\n"
    "A: bConfigurationValue=1\nA: bNumConfigurations=1\n"
    "A: manufacturer=wearknit\nA: product=Mock Knitter\nA: serial=KNIT0001\n"
    "H: descriptors=" WK_DESCRIPTORS "\n";

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The mock USB device: usbdevfs requests in, the engine behind bulk OUT/IN.
struct MockUsbDevice {
  struct Urb {
    UMockdevIoctlData* urb;
    UMockdevIoctlData* buffer;
  };
  std::mutex mutex;
  DeviceEngine* engine = nullptr;
  FaultInjector faults{FaultSpec{}, 1};
  SlipDecoder decoder;
  Bytes to_host;
  std::deque<Urb> pending_in;
  std::deque<Urb> done;
  // Unplugged: every submission fails with ENODEV (libusb: NO_DEVICE);
  // the device comes back shortly after the host first notices.
  bool unplugged = false;
  double replug_at = 0;
  int unplugs = 0;
  int urbs = 0;

  void complete_ins() {
    while (!pending_in.empty() && !to_host.empty()) {
      Urb u = pending_in.front();
      pending_in.pop_front();
      auto* urb = reinterpret_cast<usbdevfs_urb*>(u.urb->data);
      const std::size_t n =
          std::min<std::size_t>(static_cast<std::size_t>(urb->buffer_length), to_host.size());
      std::copy_n(to_host.begin(), n, u.buffer->data);
      to_host.erase(to_host.begin(), to_host.begin() + static_cast<std::ptrdiff_t>(n));
      urb->actual_length = static_cast<int>(n);
      urb->status = 0;
      done.push_back(u);
    }
  }

  void bulk_out(const std::uint8_t* data, std::size_t length) {
    std::vector<Bytes> frames;
    decoder.feed(std::span(data, length), [&](std::span<const std::uint8_t> raw) {
      frames.emplace_back(raw.begin(), raw.end());
    });
    for (Bytes& raw : frames) {
      std::vector<Frame> replies;
      for (const Bytes& copy : faults.pass(std::move(raw))) {
        Frame f;
        if (decode_frame(copy, f)) engine->handle(f, seconds_now(), replies);
      }
      for (const Frame& r : replies) {
        for (const Bytes& w : faults.pass(encode_wire(r))) {
          to_host.insert(to_host.end(), w.begin(), w.end());
        }
      }
      if (faults.after_received_frame() != FaultInjector::Event::None) {
        // Unplugged: gone for a moment, then enumerated again.
        ++unplugs;
        unplugged = true;
        replug_at = 1e300;
        to_host.clear();
        decoder.reset();
        // Transfers in flight end the way the kernel ends them on unplug.
        for (Urb& u : pending_in) {
          reinterpret_cast<usbdevfs_urb*>(u.urb->data)->status = -ESHUTDOWN;
          reinterpret_cast<usbdevfs_urb*>(u.urb->data)->actual_length = 0;
          done.push_back(u);
        }
        pending_in.clear();
        return;
      }
    }
  }

  // Control requests: string descriptors only; anything else stalls.
  static int control(std::uint8_t* setup) {
    const std::uint8_t type = setup[0];
    const std::uint8_t request = setup[1];
    const unsigned value = setup[2] | (setup[3] << 8);
    const unsigned length = setup[6] | (setup[7] << 8);
    std::uint8_t* out = setup + 8;
    if (type != 0x80 || request != 6 || (value >> 8) != 3) return -EPIPE;
    const unsigned index = value & 0xFF;
    std::vector<std::uint8_t> d;
    if (index == 0) {
      d = {4, 3, 0x09, 0x04};
    } else {
      static const char* strings[] = {nullptr, "wearknit", "Mock Knitter", "KNIT0001"};
      if (index > 3) return -EPIPE;
      const std::string s = strings[index];
      d = {static_cast<std::uint8_t>(2 + 2 * s.size()), 3};
      for (char c : s) {
        d.push_back(static_cast<std::uint8_t>(c));
        d.push_back(0);
      }
    }
    const unsigned n = std::min<unsigned>(length, static_cast<unsigned>(d.size()));
    std::copy_n(d.begin(), n, out);
    return static_cast<int>(n);
  }
};

MockUsbDevice mock;

gboolean on_ioctl(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer) {
  std::lock_guard lock(mock.mutex);
  GError* error = nullptr;
  const gulong request = umockdev_ioctl_client_get_request(client);
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  const bool reaping = request == USBDEVFS_REAPURB || request == USBDEVFS_REAPURBNDELAY ||
                       request == USBDEVFS_DISCARDURB;
  if (mock.unplugged && seconds_now() >= mock.replug_at) mock.unplugged = false;
  if (mock.unplugged && !reaping) {
    if (mock.replug_at > 1e299) mock.replug_at = seconds_now() + 0.02;
    umockdev_ioctl_client_complete(client, -1, ENODEV);
    return TRUE;
  }
  if (mock.engine != nullptr) mock.engine->tick(seconds_now());
  switch (request) {
    case USBDEVFS_GET_CAPABILITIES: {
      UMockdevIoctlData* caps = umockdev_ioctl_data_resolve(arg, 0, sizeof(guint32), &error);
      *reinterpret_cast<guint32*>(caps->data) = USBDEVFS_CAP_BULK_CONTINUATION |
                                                USBDEVFS_CAP_NO_PACKET_SIZE_LIM |
                                                USBDEVFS_CAP_ZERO_PACKET;
      umockdev_ioctl_client_complete(client, 0, 0);
      g_object_unref(caps);
      break;
    }
    case USBDEVFS_CLAIMINTERFACE:
    case USBDEVFS_RELEASEINTERFACE:
    case USBDEVFS_CLEAR_HALT:
    case USBDEVFS_RESET:
    case USBDEVFS_RESETEP:
      umockdev_ioctl_client_complete(client, 0, 0);
      break;
    case USBDEVFS_SUBMITURB: {
      ++mock.urbs;
      MockUsbDevice::Urb u{};
      u.urb = umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_urb), &error);
      auto* urb = reinterpret_cast<usbdevfs_urb*>(u.urb->data);
      u.buffer = umockdev_ioctl_data_resolve(u.urb, offsetof(usbdevfs_urb, buffer),
                                             static_cast<gsize>(urb->buffer_length), &error);
      if (urb->type == USBDEVFS_URB_TYPE_CONTROL) {
        const int r = MockUsbDevice::control(u.buffer->data);
        urb->status = r < 0 ? r : 0;
        urb->actual_length = r < 0 ? 0 : r;
        mock.done.push_back(u);
      } else if (urb->endpoint & 0x80) {
        mock.pending_in.push_back(u);
      } else {
        mock.bulk_out(u.buffer->data, static_cast<std::size_t>(urb->buffer_length));
        urb->status = 0;
        urb->actual_length = urb->buffer_length;
        mock.done.push_back(u);
      }
      mock.complete_ins();
      umockdev_ioctl_client_complete(client, 0, 0);
      break;
    }
    case USBDEVFS_DISCARDURB: {
      const gulong address = *reinterpret_cast<gulong*>(arg->data);
      bool found = false;
      for (auto it = mock.pending_in.begin(); it != mock.pending_in.end(); ++it) {
        if (it->urb->client_addr == address) {
          reinterpret_cast<usbdevfs_urb*>(it->urb->data)->status = -ENOENT;
          mock.done.push_front(*it);
          mock.pending_in.erase(it);
          found = true;
          break;
        }
      }
      umockdev_ioctl_client_complete(client, found ? 0 : -1, found ? 0 : EINVAL);
      break;
    }
    case USBDEVFS_REAPURB:
    case USBDEVFS_REAPURBNDELAY: {
      mock.complete_ins();
      if (mock.done.empty()) {
        umockdev_ioctl_client_complete(client, -1, EAGAIN);
        break;
      }
      MockUsbDevice::Urb u = mock.done.front();
      mock.done.pop_front();
      UMockdevIoctlData* out = umockdev_ioctl_data_resolve(arg, 0, sizeof(void*), &error);
      umockdev_ioctl_data_set_ptr(out, 0, u.urb);
      umockdev_ioctl_client_complete(client, 0, 0);
      g_object_unref(out);
      g_object_unref(u.buffer);
      g_object_unref(u.urb);
      break;
    }
    default:
      umockdev_ioctl_client_complete(client, -1, ENOTTY);
  }
  if (error != nullptr) {
    ADD_FAILURE() << "umockdev: " << error->message;
    g_error_free(error);
  }
  return TRUE;
}

class UsbUmockdevTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!in_mock_environment) {
      GTEST_SKIP() << "needs umockdev: run under `umockdev-wrapper` (ctest does)";
    }
    store_ = wearknit::test::make_temp_dir("wk-usb");
    DeviceConfig config;
    config.store = store_;
    config.sync = false;
    config.checkers = test::test_checkers();
    engine_ = std::move(DeviceEngine::open(config).value());
    std::lock_guard lock(mock.mutex);
    mock.engine = engine_.get();
    mock.faults = FaultInjector(FaultSpec{}, 1);
    mock.decoder.reset();
    mock.to_host.clear();
    mock.unplugged = false;
  }
  void TearDown() override {
    if (!in_mock_environment) return;
    std::lock_guard lock(mock.mutex);
    mock.engine = nullptr;
    std::filesystem::remove_all(store_);
  }
  std::filesystem::path store_;
  std::unique_ptr<DeviceEngine> engine_;
};

TEST_F(UsbUmockdevTest, DevicesListsTheMockMachine) {
  auto list = list_usb_devices(real_usb_api());
  ASSERT_TRUE(list.ok()) << list.error().text();
  ASSERT_EQ(list.value().size(), 1u);
  const UsbDeviceInfo& d = list.value()[0];
  EXPECT_EQ(d.vid, 0x1209);
  EXPECT_EQ(d.pid, 0x4b4e);
  EXPECT_EQ(d.bus, 1);
  EXPECT_EQ(d.address, 3);
  EXPECT_EQ(d.product, "Mock Knitter");
  EXPECT_EQ(d.serial_number, "KNIT0001");
}

TEST_F(UsbUmockdevTest, SendsAJobOverBulkEndpointsWithFaultsAndUnplugs) {
  FaultSpec faults;
  faults.corrupt = faults.drop = faults.dup = 0.01;
  faults.disconnect_every = 70;
  {
    std::lock_guard lock(mock.mutex);
    mock.faults = FaultInjector(faults, 21);
    mock.unplugs = 0;
  }
  const Job job = test::make_sheet_job("usb.k", 10, 100);
  SendOptions send;
  send.rto_s = 0.05;
  send.silence_s = 1.0;
  LinkOptions link;
  link.first_backoff_s = 0.05;
  auto report = send_job(parse_uri("usb://1209:4b4e/KNIT0001").value(), job, send, link, nullptr);
  ASSERT_TRUE(report.ok()) << report.error().text();
  ASSERT_TRUE(report.value().done) << report.value().message;
  EXPECT_GE(report.value().reconnects, 1);
  std::lock_guard lock(mock.mutex);
  EXPECT_GE(mock.unplugs, 1);
  EXPECT_EQ(test::read_text(store_ / "usb.k"), std::string(job.bytes.begin(), job.bytes.end()));
  auto log = engine_->verify_knit_log(engine_->job_id(), job.row_count());
  ASSERT_TRUE(log.ok()) << log.error().text();
  EXPECT_EQ(log.value(), job.row_count());
}

TEST_F(UsbUmockdevTest, AWrongSerialNumberFindsNoDevice) {
  auto t = open_usb(real_usb_api(), 0x1209, 0x4b4e, "OTHER");
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.error().error_class, ErrorClass::Disconnected);
  EXPECT_EQ(t.error().message, "usb://1209:4b4e/OTHER: no device with serial number OTHER");
  auto absent = open_usb(real_usb_api(), 0x1234, 0x5678, "");
  ASSERT_FALSE(absent.ok());
  EXPECT_EQ(absent.error().message, "usb://1234:5678: no such device");
}

}  // namespace
}  // namespace devices

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  // The testbed must exist before libusb looks for devices; only then does
  // umockdev_in_mock_environment() tell the truth.
  devices::testbed = umockdev_testbed_new();
  devices::in_mock_environment = umockdev_in_mock_environment();
  UMockdevIoctlBase* handler = nullptr;
  if (devices::in_mock_environment) {
    GError* error = nullptr;
    if (!umockdev_testbed_add_from_string(devices::testbed, devices::kDevice, &error)) {
      std::fprintf(stderr, "umockdev: %s\n", error->message);
      return 1;
    }
    handler = umockdev_ioctl_base_new();
    g_signal_connect(handler, "handle-ioctl", G_CALLBACK(devices::on_ioctl), nullptr);
    if (!umockdev_testbed_attach_ioctl(devices::testbed, "/dev/bus/usb/001/003", handler, &error)) {
      std::fprintf(stderr, "umockdev: %s\n", error->message);
      return 1;
    }
  }
  int result = RUN_ALL_TESTS();
  if (handler != nullptr) g_object_unref(handler);
  g_object_unref(devices::testbed);
  // Every test skipped (no umockdev): ctest reports the test skipped
  // (SKIP_RETURN_CODE, tests/test_main.cpp).
  const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
  if (result == 0 && unit.successful_test_count() == 0 && unit.skipped_test_count() > 0) {
    result = 77;
  }
  return result;
}
