// The mock machine over real TCP on 127.0.0.1, with the sender's
// reconnection, give-up and --resume.
#include <gtest/gtest.h>

#include "devices/sender.hpp"
#include "tests/devices/device_test_support.hpp"
#include "tests/devices/mock_server_thread.hpp"
#include "tests/test_support.hpp"

namespace devices {
namespace {

class TcpTest : public ::testing::Test {
 protected:
  void SetUp() override { store_ = wearknit::test::make_temp_dir("wk-tcp"); }
  void TearDown() override { std::filesystem::remove_all(store_); }

  MockServerOptions server_options(double rows_per_s = 0, FaultSpec faults = {}) {
    MockServerOptions o;
    o.listen = parse_uri("tcp://127.0.0.1:0").value();
    o.device.store = store_;
    o.device.rows_per_s = rows_per_s;
    o.device.sync = false;
    o.device.checkers = test::test_checkers();
    o.device.yarn_break_at_row = faults.yarn_break_at;
    o.device.on_event = [this](const std::string& e) {
      std::lock_guard lock(mutex_);
      events_.push_back(e);
    };
    o.faults = faults;
    o.seed = 5;
    return o;
  }
  static LinkOptions fast_link(int attempts = 8) {
    LinkOptions link;
    link.max_attempts = attempts;
    link.first_backoff_s = 0.02;
    link.max_backoff_s = 0.05;
    return link;
  }
  static SendOptions fast_send(bool resume = false) {
    SendOptions s;
    s.resume = resume;
    s.rto_s = 0.05;
    s.max_rto_s = 0.3;
    s.silence_s = 1.0;
    return s;
  }
  void expect_stored_and_knitted_once(const Job& job, std::uint32_t job_id) {
    EXPECT_EQ(test::read_text(store_ / job.name), std::string(job.bytes.begin(), job.bytes.end()));
    auto engine = open_store();
    ASSERT_TRUE(engine.ok());
    auto log = engine.value()->verify_knit_log(job_id, job.row_count());
    ASSERT_TRUE(log.ok()) << log.error().text();
    EXPECT_EQ(log.value(), job.row_count());
  }

  // The device's state as a restarted machine would read it.
  Result<std::unique_ptr<DeviceEngine>> open_store() {
    DeviceConfig config;
    config.store = store_;
    return DeviceEngine::open(config);
  }

  std::filesystem::path store_;
  std::mutex mutex_;
  std::vector<std::string> events_;
};

TEST_F(TcpTest, SendsAJobThatArrivesIdenticalAndIsKnittedOnce) {
  test::MockServerThread server(server_options());
  const Job job = test::make_sheet_job("tcp.k", 10, 60);
  auto report = send_job(parse_uri(server.uri()).value(), job, fast_send(), fast_link(), nullptr);
  ASSERT_TRUE(report.ok()) << report.error().text();
  EXPECT_TRUE(report.value().done) << report.value().message;
  EXPECT_EQ(report.value().progress.rows_knitted, job.row_count());
  server.stop();
  EXPECT_EQ(server.failure(), "");
  auto status = open_store();
  ASSERT_TRUE(status.ok());
  expect_stored_and_knitted_once(job, status.value()->job_id());
}

TEST_F(TcpTest, SurvivesTheFaultsOfTheDoneWhenCommand) {
  FaultSpec faults;
  faults.corrupt = faults.drop = faults.dup = 0.01;
  faults.disconnect_every = 50;
  test::MockServerThread server(server_options(0, faults));
  const Job job = test::make_sheet_job("faulty.k", 10, 150);
  int notes = 0;
  auto report = send_job(parse_uri(server.uri()).value(), job, fast_send(), fast_link(),
                         [&](const Progress&, const std::string& note) { notes += !note.empty(); });
  ASSERT_TRUE(report.ok()) << report.error().text();
  EXPECT_TRUE(report.value().done) << report.value().message;
  EXPECT_GE(report.value().reconnects, 2);
  EXPECT_GE(notes, 2);
  server.stop();
  auto engine = open_store();
  ASSERT_TRUE(engine.ok());
  expect_stored_and_knitted_once(job, engine.value()->job_id());
}

TEST_F(TcpTest, GivesUpWithAClearMessageAndResumeFinishesWithoutKnittingTwice) {
  const Job job = test::make_sheet_job("resume.k", 6, 60);
  std::uint32_t knitted_before = 0;
  {
    MockServerOptions o = server_options(/*rows_per_s=*/40);
    test::MockServerThread server(o);
    const DeviceUri uri = parse_uri(server.uri()).value();
    std::thread stopper([&] {
      // Pull the plug once knitting is under way.
      for (int i = 0; i < 400; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        std::lock_guard lock(mutex_);
        if (!events_.empty() && events_.back().find("stored") != std::string::npos) break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
      server.stop();
    });
    LinkOptions link = fast_link(3);
    link.job_path = "/jobs/spring line/resume.k";  // the path the user gave
    auto report = send_job(uri, job, fast_send(), link, nullptr);
    stopper.join();
    ASSERT_FALSE(report.ok());
    EXPECT_EQ(report.error().error_class, ErrorClass::Disconnected);
    const std::string& m = report.error().message;
    EXPECT_EQ(m.rfind("gave up on " + server.uri() +
                          " after 3 attempts in a row that moved the job no further (",
                      0),
              0u)
        << m;
    // Every row is stored (the check ran) and some are knitted: the message
    // says so before its hint.
    EXPECT_NE(m.find("62 of 62 rows are stored on the device and "), std::string::npos) << m;
    EXPECT_NE(
        m.find(
            "The device keeps its counters: run `wearknit send '/jobs/spring line/resume.k' --to " +
            server.uri() + " --resume` to finish the job"),
        std::string::npos)
        << m;
    auto engine = open_store();
    knitted_before = engine.value()->rows_knitted();
    EXPECT_GT(knitted_before, 0u);
    EXPECT_LT(knitted_before, job.row_count());
  }
  // The machine comes back (a new port); without --resume the sender refuses
  // to start the job a second time.
  test::MockServerThread server(server_options(/*rows_per_s=*/60));
  const DeviceUri uri = parse_uri(server.uri()).value();
  auto again = send_job(uri, job, fast_send(false), fast_link(), nullptr);
  ASSERT_TRUE(again.ok());
  EXPECT_FALSE(again.value().done);
  EXPECT_NE(again.value().message.find("it is this job: add --resume to finish it"),
            std::string::npos)
      << again.value().message;
  auto resumed = send_job(uri, job, fast_send(true), fast_link(), nullptr);
  ASSERT_TRUE(resumed.ok()) << resumed.error().text();
  EXPECT_TRUE(resumed.value().done) << resumed.value().message;
  EXPECT_EQ(resumed.value().progress.frames_sent > 0, true);
  EXPECT_EQ(resumed.value().progress.rows_sent, 0u);  // nothing re-sent: it was all stored
  server.stop();
  auto engine = open_store();
  expect_stored_and_knitted_once(job, engine.value()->job_id());
}

TEST_F(TcpTest, StatusShowsTheJobAndCommandsAreAcknowledged) {
  test::MockServerThread server(server_options(/*rows_per_s=*/20));
  const DeviceUri uri = parse_uri(server.uri()).value();
  auto idle = query_status(uri, fast_link());
  ASSERT_TRUE(idle.ok()) << idle.error().text();
  EXPECT_EQ(idle.value().status.state, JobState::Idle);
  auto none = send_command(uri, Command::Pause, fast_link());
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().message, uri.text + ": no unfinished job to pause (the device is idle)");

  const Job job = test::make_sheet_job("cmd.k", 6, 200);
  std::atomic<bool> cancelled{false};
  std::thread sender([&] {
    auto report = send_job(uri, job, fast_send(), fast_link(), nullptr);
    ASSERT_TRUE(report.ok());
    EXPECT_FALSE(report.value().done);
    EXPECT_EQ(report.value().message.rfind("the job was cancelled at the device after ", 0), 0u)
        << report.value().message;
    cancelled = true;
  });
  DeviceStatus status;
  for (int i = 0; i < 300; ++i) {
    auto s = query_status(uri, fast_link());
    ASSERT_TRUE(s.ok());
    status = s.value();
    if (status.status.state == JobState::Knitting) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_EQ(status.status.state, JobState::Knitting);
  EXPECT_EQ(status.status.name, "cmd.k");
  auto paused = send_command(uri, Command::Pause, fast_link());
  ASSERT_TRUE(paused.ok()) << paused.error().text();
  EXPECT_EQ(paused.value().status.state, JobState::Paused);
  const std::uint32_t at = paused.value().status.rows_knitted;
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  auto still = query_status(uri, fast_link());
  EXPECT_EQ(still.value().status.rows_knitted, at);
  auto resumed = send_command(uri, Command::Resume, fast_link());
  ASSERT_TRUE(resumed.ok());
  EXPECT_EQ(resumed.value().status.state, JobState::Knitting);
  auto cancel = send_command(uri, Command::Cancel, fast_link());
  ASSERT_TRUE(cancel.ok());
  EXPECT_EQ(cancel.value().status.state, JobState::Cancelled);
  sender.join();
  EXPECT_TRUE(cancelled);
}

TEST_F(TcpTest, RefusedJobFailsTheSendWithTheDevicesReason) {
  test::MockServerThread server(server_options());
  const std::string text = ";!knitout-2\n;;Carriers: 1 2 3\ninhook 3\nknot + f1 3\n";
  auto job = make_job("bad.k", Bytes(text.begin(), text.end()));
  ASSERT_TRUE(job.ok());
  auto report =
      send_job(parse_uri(server.uri()).value(), job.value(), fast_send(), fast_link(), nullptr);
  ASSERT_TRUE(report.ok());
  EXPECT_FALSE(report.value().done);
  EXPECT_EQ(report.value().message.rfind("the device refused the job: bad.k:4:1: error: [K", 0), 0u)
      << report.value().message;
}

TEST_F(TcpTest, NothingListeningGivesUpAfterTheBoundedAttempts) {
  // Find a free port by listening and closing.
  std::string uri_text;
  {
    test::MockServerThread server(server_options());
    uri_text = server.uri();
  }
  const Job job = test::make_sheet_job("x.k", 2, 2);
  auto report = send_job(parse_uri(uri_text).value(), job, fast_send(), fast_link(2), nullptr);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.error().message,
            "gave up on " + uri_text +
                " after 2 attempts in a row that moved the job no further (cannot connect to " +
                uri_text + ": nothing listens); nothing of the job reached the device")
      << report.error().message;
}

}  // namespace
}  // namespace devices
