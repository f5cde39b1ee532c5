// The serial transport against a fake libserialport (the SerialApi seam):
// short reads, silent timeouts, unplugs and short writes, with the mock
// machine's engine behind the fake port.
#include <gtest/gtest.h>

#include <chrono>
#include <random>

#include "devices/sender.hpp"
#include "devices/serial.hpp"
#include "tests/devices/device_test_support.hpp"
#include "tests/test_support.hpp"

namespace devices {
namespace {

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

class FakeSerial final : public SerialApi {
 public:
  explicit FakeSerial(DeviceEngine* engine) : engine_(engine) {}

  sp_port* port(int i) { return reinterpret_cast<sp_port*>(&tokens_[i]); }

  sp_return get_port_by_name(const char* name, sp_port** out) override {
    if (std::string(name) != "/dev/ttyFAKE0") return SP_ERR_ARG;
    *out = port(0);
    return SP_OK;
  }
  void free_port(sp_port*) override {}
  sp_return list_ports(sp_port*** list) override {
    list_[0] = port(0);
    list_[1] = port(1);
    list_[2] = nullptr;
    *list = list_;
    return SP_OK;
  }
  void free_port_list(sp_port**) override { ++freed_lists; }
  sp_return open(sp_port*, sp_mode) override {
    ++opens;
    unplugged = false;
    return fail_open ? SP_ERR_FAIL : SP_OK;
  }
  sp_return close(sp_port*) override {
    ++closes;
    return SP_OK;
  }
  sp_return set_baudrate(sp_port*, int baud) override {
    last_baud = baud;
    return SP_OK;
  }
  sp_return set_bits(sp_port*, int) override { return SP_OK; }
  sp_return set_parity(sp_port*, sp_parity) override { return SP_OK; }
  sp_return set_stopbits(sp_port*, int) override { return SP_OK; }
  sp_return set_flowcontrol(sp_port*, sp_flowcontrol) override { return SP_OK; }
  sp_return flush(sp_port*, sp_buffer) override {
    pending_.clear();
    decoder_.reset();
    return SP_OK;
  }
  sp_return blocking_write(sp_port*, const void* buf, size_t count, unsigned) override {
    if (unplugged) return SP_ERR_FAIL;
    if (short_writes) return static_cast<sp_return>(count / 2);
    const auto* bytes = static_cast<const std::uint8_t*>(buf);
    std::vector<Frame> replies;
    decoder_.feed(std::span(bytes, count), [&](std::span<const std::uint8_t> raw) {
      Frame f;
      if (decode_frame(raw, f)) engine_->handle(f, seconds_now(), replies);
    });
    for (const Frame& r : replies) {
      const Bytes w = encode_wire(r);
      pending_.insert(pending_.end(), w.begin(), w.end());
    }
    return static_cast<sp_return>(count);
  }
  sp_return blocking_read_next(sp_port*, void* buf, size_t count, unsigned) override {
    if (unplugged) return SP_OK;  // what a hung-up port does: "no data"
    if (unplug_every != 0 && ++reads % unplug_every == 0) {
      unplugged = true;
      ++unplugs;
      return SP_OK;
    }
    engine_->tick(seconds_now());
    if (pending_.empty() || rng_() % 5 == 0) return SP_OK;  // a timeout
    const std::size_t n = std::min<std::size_t>({count, pending_.size(), 1 + rng_() % 3});
    std::copy_n(pending_.begin(), n, static_cast<std::uint8_t*>(buf));
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
    return static_cast<sp_return>(n);
  }
  sp_return input_waiting(sp_port*) override {
    return unplugged ? SP_ERR_FAIL : static_cast<sp_return>(pending_.size());
  }
  const char* port_name(sp_port* p) override {
    return p == port(0) ? "/dev/ttyFAKE0" : "/dev/ttyS0";
  }
  const char* port_description(sp_port* p) override {
    return p == port(0) ? "Fake Knitter" : "Built-in serial";
  }
  sp_transport port_transport(sp_port* p) override {
    return p == port(0) ? SP_TRANSPORT_USB : SP_TRANSPORT_NATIVE;
  }
  sp_return port_usb_vid_pid(sp_port*, int* vid, int* pid) override {
    *vid = 0x2341;
    *pid = 0x0043;
    return SP_OK;
  }
  std::string last_error_message() override { return "fake failure"; }

  int opens = 0;
  int closes = 0;
  int unplugs = 0;
  int reads = 0;
  int unplug_every = 0;
  int last_baud = 0;
  int freed_lists = 0;
  bool unplugged = false;
  bool fail_open = false;
  bool short_writes = false;

 private:
  DeviceEngine* engine_;
  SlipDecoder decoder_;
  Bytes pending_;
  std::mt19937 rng_{3};
  int tokens_[2] = {0, 0};
  sp_port* list_[3] = {};
};

class SerialFakeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = wearknit::test::make_temp_dir("wk-fake-serial");
    DeviceConfig config;
    config.store = store_;
    config.sync = false;
    config.checkers = test::test_checkers();
    engine_ = std::move(DeviceEngine::open(config).value());
  }
  void TearDown() override { std::filesystem::remove_all(store_); }
  std::filesystem::path store_;
  std::unique_ptr<DeviceEngine> engine_;
};

TEST_F(SerialFakeTest, ShortReadsAndTimeoutsStillCarryFrames) {
  FakeSerial fake(engine_.get());
  auto t = open_serial(fake, "/dev/ttyFAKE0", 57600);
  ASSERT_TRUE(t.ok()) << t.error().text();
  EXPECT_EQ(fake.last_baud, 57600);
  const Bytes hello = encode_wire(Frame{FrameType::Hello, 0, 0, 1, encode(HelloMessage{})});
  ASSERT_TRUE(t.value()->write_all(hello, 100).ok());
  SlipDecoder decoder;
  int frames = 0;
  std::uint8_t buffer[64];
  for (int i = 0; i < 400 && frames == 0; ++i) {
    auto n = t.value()->read_some(buffer, 10);
    ASSERT_TRUE(n.ok());
    EXPECT_LE(n.value(), 3u);
    decoder.feed(std::span(buffer, n.value()), [&](std::span<const std::uint8_t>) { ++frames; });
  }
  EXPECT_EQ(frames, 1);
}

TEST_F(SerialFakeTest, AnUnpluggedPortReadsAsDisconnectedNotAsSilence) {
  FakeSerial fake(engine_.get());
  auto t = open_serial(fake, "/dev/ttyFAKE0", 115200);
  ASSERT_TRUE(t.ok());
  fake.unplugged = true;
  std::uint8_t buffer[8];
  auto n = t.value()->read_some(buffer, 10);
  ASSERT_FALSE(n.ok());
  EXPECT_EQ(n.error().error_class, ErrorClass::Disconnected);
  EXPECT_EQ(n.error().message, "serial:/dev/ttyFAKE0: the port hung up");
  auto w = t.value()->write_all(Bytes{1, 2, 3}, 10);
  ASSERT_FALSE(w.ok());
  EXPECT_EQ(w.error().error_class, ErrorClass::Disconnected);
}

TEST_F(SerialFakeTest, AShortWriteIsATimeout) {
  FakeSerial fake(engine_.get());
  auto t = open_serial(fake, "/dev/ttyFAKE0", 115200);
  ASSERT_TRUE(t.ok());
  fake.short_writes = true;
  auto w = t.value()->write_all(Bytes(10, 0x55), 25);
  ASSERT_FALSE(w.ok());
  EXPECT_EQ(w.error().error_class, ErrorClass::Timeout);
  EXPECT_EQ(w.error().message, "serial:/dev/ttyFAKE0: wrote 5 of 10 bytes in 25 ms");
}

TEST_F(SerialFakeTest, OpenFailuresAreClassified) {
  FakeSerial fake(engine_.get());
  auto missing = open_serial(fake, "/dev/ttyNONE", 115200);
  ASSERT_FALSE(missing.ok());
  EXPECT_EQ(missing.error().error_class, ErrorClass::InvalidArgument);
  EXPECT_EQ(missing.error().message, "serial:/dev/ttyNONE: no such serial port (fake failure)");
  fake.fail_open = true;
  auto busy = open_serial(fake, "/dev/ttyFAKE0", 115200);
  ASSERT_FALSE(busy.ok());
  EXPECT_EQ(busy.error().error_class, ErrorClass::OsFailure);
  EXPECT_EQ(busy.error().message, "serial:/dev/ttyFAKE0: cannot open: fake failure");
}

TEST_F(SerialFakeTest, SendReconnectsAfterUnplugsAndFinishesTheJobOnce) {
  FakeSerial fake(engine_.get());
  fake.unplug_every = 150;
  const Job job = test::make_sheet_job("fake.k", 8, 40);
  SendOptions send;
  send.rto_s = 0.05;
  LinkOptions link;
  link.first_backoff_s = 0.001;
  link.open = [&] { return open_serial(fake, "/dev/ttyFAKE0", 115200); };
  auto report = send_job(parse_uri("serial:/dev/ttyFAKE0").value(), job, send, link, nullptr);
  ASSERT_TRUE(report.ok()) << report.error().text();
  EXPECT_TRUE(report.value().done) << report.value().message;
  EXPECT_GE(fake.unplugs, 2);
  EXPECT_EQ(report.value().reconnects, fake.opens - 1);
  EXPECT_EQ(fake.closes, fake.opens);
  EXPECT_EQ(test::read_text(store_ / "fake.k"), std::string(job.bytes.begin(), job.bytes.end()));
  auto log = engine_->verify_knit_log(engine_->job_id(), job.row_count());
  ASSERT_TRUE(log.ok()) << log.error().text();
  EXPECT_EQ(log.value(), job.row_count());
}

TEST_F(SerialFakeTest, ListsPortsWithUsbIds) {
  FakeSerial fake(engine_.get());
  auto ports = list_serial_ports(fake);
  ASSERT_TRUE(ports.ok());
  ASSERT_EQ(ports.value().size(), 2u);
  EXPECT_EQ(ports.value()[0].name, "/dev/ttyFAKE0");
  EXPECT_EQ(ports.value()[0].description, "Fake Knitter");
  EXPECT_TRUE(ports.value()[0].usb);
  EXPECT_EQ(ports.value()[0].vid, 0x2341);
  EXPECT_FALSE(ports.value()[1].usb);
  EXPECT_EQ(fake.freed_lists, 1);
}

}  // namespace
}  // namespace devices
