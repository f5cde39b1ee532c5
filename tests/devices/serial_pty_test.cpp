// The serial transport for real: libserialport on one end of a
// pseudo-terminal, the mock machine on the other. Runs with sp_pty_shim
// preloaded (ctest sets LD_PRELOAD), without which libserialport cannot open
// a pty at all.
#include <gtest/gtest.h>

#include "devices/sender.hpp"
#include "devices/serial.hpp"
#include "tests/devices/background_wearknit.hpp"
#include "tests/devices/device_test_support.hpp"
#include "tests/devices/mock_server_thread.hpp"
#include "tests/test_support.hpp"

namespace devices {
namespace {

class SerialPtyTest : public ::testing::Test {
 protected:
  void SetUp() override { store_ = wearknit::test::make_temp_dir("wk-pty"); }
  void TearDown() override { std::filesystem::remove_all(store_); }
  MockServerOptions options(FaultSpec faults = {}) {
    MockServerOptions o;
    o.listen = parse_uri("pty:").value();
    o.device.store = store_;
    o.device.rows_per_s = 0;
    o.device.sync = false;
    o.device.checkers = test::test_checkers();
    o.faults = faults;
    o.seed = 11;
    return o;
  }
  std::filesystem::path store_;
};

TEST_F(SerialPtyTest, MockListensOnAPseudoTerminalAndPrintsItsPath) {
  test::MockServerThread server(options());
  EXPECT_EQ(server.uri().rfind("serial:/dev/pts/", 0), 0u) << server.uri();
}

TEST_F(SerialPtyTest, SendsAJobOverLibserialportWithFaults) {
  FaultSpec faults;
  faults.corrupt = faults.drop = faults.dup = 0.01;
  faults.disconnect_every = 60;
  test::MockServerThread server(options(faults));
  const Job job = test::make_sheet_job("pty.k", 10, 120);
  SendOptions send;
  send.rto_s = 0.05;
  send.silence_s = 1.0;
  LinkOptions link;
  link.first_backoff_s = 0.02;
  auto report =
      send_job(parse_uri(server.uri() + "?baud=115200").value(), job, send, link, nullptr);
  ASSERT_TRUE(report.ok()) << report.error().text();
  ASSERT_TRUE(report.value().done) << report.value().message;
  server.stop();
  EXPECT_EQ(test::read_text(store_ / "pty.k"), std::string(job.bytes.begin(), job.bytes.end()));
  DeviceConfig config;
  config.store = store_;
  auto engine = DeviceEngine::open(config);
  ASSERT_TRUE(engine.ok());
  auto log = engine.value()->verify_knit_log(engine.value()->job_id(), job.row_count());
  ASSERT_TRUE(log.ok()) << log.error().text();
  EXPECT_EQ(log.value(), job.row_count());
}

TEST_F(SerialPtyTest, StatusWorksOverThePseudoTerminal) {
  test::MockServerThread server(options());
  auto status = query_status(parse_uri(server.uri()).value());
  ASSERT_TRUE(status.ok()) << status.error().text();
  EXPECT_EQ(status.value().status.state, JobState::Idle);
  EXPECT_EQ(status.value().status.buffer_capacity, 32u);
}

TEST_F(SerialPtyTest, TheVerbsWorkOverAPseudoTerminal) {
  // mock-device prints the pty it listens on; send reaches it through
  // libserialport (the shim is inherited through LD_PRELOAD).
  const std::string text = test::sheet_knitout(12, 40);
  wearknit::test::write_file(store_ / "P.k", text);
  test::BackgroundWearknit mock("mock-device --listen pty: --store '" + (store_ / "D").string() +
                                "' --fault corrupt=0.01,drop=0.01,dup=0.01,disconnect-every=500"
                                " --exit-when-done --no-sync --rows-per-s 0");
  ASSERT_EQ(mock.uri().rfind("serial:/dev/pts/", 0), 0u) << mock.first_line();
  const auto sent =
      wearknit::test::run_wearknit("send '" + (store_ / "P.k").string() + "' --to " + mock.uri());
  EXPECT_EQ(sent.exit_code, 0) << sent.err;
  EXPECT_NE(sent.out.find("done: P.k -> " + mock.uri() + ": 42/42 rows knitted"), std::string::npos)
      << sent.out;
  EXPECT_NE(mock.finish().find("job P.k: done: knitted 42/42 rows, each exactly once"),
            std::string::npos);
  EXPECT_EQ(test::read_text(store_ / "D" / "P.k"), text);
}

TEST_F(SerialPtyTest, AMissingPortIsAnInvalidArgumentNamingIt) {
  auto t = open_serial(real_serial_api(), "/dev/wearknit-no-such-port", 9600);
  ASSERT_FALSE(t.ok());
  EXPECT_EQ(t.error().error_class, ErrorClass::InvalidArgument);
  EXPECT_EQ(t.error().message.rfind("serial:/dev/wearknit-no-such-port: no such serial port (", 0),
            0u)
      << t.error().message;
}

}  // namespace
}  // namespace devices
