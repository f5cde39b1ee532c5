#include "devices/device_engine.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "devices/hash.hpp"
#include "devices/job.hpp"
#include "tests/devices/device_test_support.hpp"
#include "tests/test_support.hpp"

namespace devices {
namespace {

class DeviceEngineTest : public ::testing::Test {
 protected:
  void SetUp() override { store_ = wearknit::test::make_temp_dir("wk-engine"); }
  void TearDown() override { std::filesystem::remove_all(store_); }

  std::unique_ptr<DeviceEngine> open(std::uint32_t buffer_rows = 4, double rows_per_s = 0) {
    DeviceConfig config;
    config.store = store_;
    config.buffer_rows = buffer_rows;
    config.rows_per_s = rows_per_s;
    config.sync = false;
    config.checkers = test::test_checkers();
    config.yarn_break_at_row = yarn_break_at_;
    config.on_event = [this](const std::string& e) { events_.push_back(e); };
    auto engine = DeviceEngine::open(config);
    EXPECT_TRUE(engine.ok());
    return std::move(engine.value());
  }

  // Sends one frame, returns the replies.
  std::vector<Frame> call(DeviceEngine& e, FrameType type, std::uint32_t job, std::uint32_t seq,
                          Bytes payload = {}) {
    std::vector<Frame> replies;
    e.handle(Frame{type, 0, job, seq, std::move(payload)}, now_, replies);
    return replies;
  }
  StatusMessage status_of(const Frame& f) {
    StatusMessage s;
    EXPECT_EQ(f.type, FrameType::Status);
    EXPECT_TRUE(decode(f.payload, s));
    return s;
  }
  AckMessage ack_of(const Frame& f) {
    AckMessage a;
    EXPECT_EQ(f.type, FrameType::Ack);
    EXPECT_TRUE(decode(f.payload, a));
    return a;
  }
  // Sends the manifest and every row in order, ticking after each.
  void send_all(DeviceEngine& e, const Job& job, std::uint32_t id) {
    call(e, FrameType::Manifest, id, 1, encode(job.manifest()));
    for (std::uint32_t r = 0; r < job.row_count(); ++r) {
      const auto row = job.row(r);
      const auto a = ack_of(call(e, FrameType::Row, id, r, Bytes(row.begin(), row.end()))[0]);
      EXPECT_EQ(a.rows_received, r + 1);
      e.tick(now_);
    }
  }

  std::filesystem::path store_;
  double now_ = 100;
  std::uint32_t yarn_break_at_ = 0;
  std::vector<std::string> events_;
};

TEST_F(DeviceEngineTest, StoresAVerifiedJobAndKnitsEveryRowOnce) {
  auto e = open();
  const Job job = test::make_sheet_job("sheet.k", 6, 10);
  send_all(*e, job, 42);
  e->tick(now_);
  EXPECT_EQ(e->state(), JobState::Done);
  EXPECT_EQ(e->rows_knitted(), job.row_count());
  EXPECT_EQ(test::read_text(store_ / "sheet.k"), std::string(job.bytes.begin(), job.bytes.end()));
  EXPECT_NE(test::read_text(store_ / "sheet.k.manifest.json").find(to_hex(job.sha256)),
            std::string::npos);
  auto log = e->verify_knit_log(42, job.row_count());
  ASSERT_TRUE(log.ok()) << log.error().text();
  EXPECT_EQ(log.value(), job.row_count());
  EXPECT_EQ(events_.back(), "job sheet.k: done: knitted 12/12 rows, each exactly once");
}

TEST_F(DeviceEngineTest, DuplicatesAndGapsAreAnsweredButNeverApplied) {
  auto e = open();
  const Job job = test::make_sheet_job("s.k", 4, 6);
  call(*e, FrameType::Manifest, 7, 1, encode(job.manifest()));
  const auto row = [&](std::uint32_t r) { return Bytes(job.row(r).begin(), job.row(r).end()); };
  EXPECT_EQ(ack_of(call(*e, FrameType::Row, 7, 0, row(0))[0]).rows_received, 1u);
  EXPECT_EQ(ack_of(call(*e, FrameType::Row, 7, 0, row(0))[0]).rows_received, 1u);  // dup
  const AckMessage gap = ack_of(call(*e, FrameType::Row, 7, 2, row(2))[0]);
  EXPECT_EQ(gap.rows_received, 1u);  // row 2 is held, not counted
  EXPECT_EQ(gap.buffer_free, 2u);
  EXPECT_EQ(ack_of(call(*e, FrameType::Row, 7, 2, row(2))[0]).buffer_free, 2u);    // held once
  EXPECT_EQ(ack_of(call(*e, FrameType::Row, 8, 1, row(1))[0]).rows_received, 1u);  // other job
  // The missing row arrives: the held one follows it.
  EXPECT_EQ(ack_of(call(*e, FrameType::Row, 7, 1, row(1))[0]).rows_received, 3u);
  e->tick(now_);
  EXPECT_EQ(test::read_text(store_ / ".wearknit-device" / "job-7.part"),
            std::string(job.bytes.begin(), job.bytes.begin() + job.row_offsets[3]));
}

TEST_F(DeviceEngineTest, RowsPastAGapAreHeldOnlyWithinTheBuffer) {
  auto e = open(/*buffer_rows=*/3);
  const Job job = test::make_sheet_job("s.k", 4, 8);
  call(*e, FrameType::Manifest, 7, 1, encode(job.manifest()));
  const auto row = [&](std::uint32_t r) { return Bytes(job.row(r).begin(), job.row(r).end()); };
  call(*e, FrameType::Row, 7, 1, row(1));
  const AckMessage held = ack_of(call(*e, FrameType::Row, 7, 2, row(2))[0]);
  EXPECT_EQ(held.rows_received, 0u);
  EXPECT_EQ(held.buffer_free, 1u);
  // Row 3 lies past the buffer's reach from row 0: not taken.
  EXPECT_EQ(ack_of(call(*e, FrameType::Row, 7, 3, row(3))[0]).buffer_free, 1u);
  const AckMessage filled = ack_of(call(*e, FrameType::Row, 7, 0, row(0))[0]);
  EXPECT_EQ(filled.rows_received, 3u);
  EXPECT_EQ(filled.buffer_free, 3u);  // rows 0-2 moved to the store
  EXPECT_EQ(ack_of(call(*e, FrameType::Row, 7, 3, row(3))[0]).rows_received, 4u);
}

TEST_F(DeviceEngineTest, WindowIsTheFreeBuffer) {
  auto e = open(/*buffer_rows=*/3);
  const Job job = test::make_sheet_job("s.k", 4, 6);
  call(*e, FrameType::Manifest, 7, 1, encode(job.manifest()));
  const auto row = [&](std::uint32_t r) { return Bytes(job.row(r).begin(), job.row(r).end()); };
  EXPECT_EQ(ack_of(call(*e, FrameType::Row, 7, 0, row(0))[0]).buffer_free, 2u);
  EXPECT_EQ(ack_of(call(*e, FrameType::Row, 7, 1, row(1))[0]).buffer_free, 1u);
  // The third row fills the buffer, which goes to the store at once.
  const AckMessage full = ack_of(call(*e, FrameType::Row, 7, 2, row(2))[0]);
  EXPECT_EQ(full.rows_received, 3u);
  EXPECT_EQ(full.buffer_free, 3u);
  EXPECT_EQ(std::filesystem::file_size(store_ / ".wearknit-device" / "job-7.part"),
            job.row_offsets[3]);
}

TEST_F(DeviceEngineTest, RefusesAJobWhoseBytesDoNotMatchTheManifest) {
  auto e = open();
  const Job job = test::make_sheet_job("s.k", 4, 3);
  ManifestMessage m = job.manifest();
  m.sha256[0] ^= 1;
  call(*e, FrameType::Manifest, 5, 1, encode(m));
  for (std::uint32_t r = 0; r < job.row_count(); ++r) {
    call(*e, FrameType::Row, 5, r, Bytes(job.row(r).begin(), job.row(r).end()));
    e->tick(now_);
  }
  EXPECT_EQ(e->state(), JobState::Refused);
  EXPECT_EQ(e->status().reason.rfind("[J005] SHA-256 of the received bytes ", 0), 0u);
  EXPECT_FALSE(std::filesystem::exists(store_ / "s.k"));
  EXPECT_EQ(e->rows_knitted(), 0u);
}

TEST_F(DeviceEngineTest, RefusesAnInvalidKnitoutJobWithTheParsersReason) {
  auto e = open();
  const std::string text = ";!knitout-2\n;;Carriers: 1 2 3\ninhook 3\nknot + f1 3\n";
  auto job = make_job("bad.k", Bytes(text.begin(), text.end()));
  ASSERT_TRUE(job.ok());
  send_all(*e, job.value(), 9);
  EXPECT_EQ(e->state(), JobState::Refused);
  EXPECT_EQ(e->status().reason.rfind("bad.k:4:1: error: [K", 0), 0u) << e->status().reason;
  EXPECT_FALSE(std::filesystem::exists(store_ / "bad.k"));
}

TEST_F(DeviceEngineTest, AValidTwinOfTheInvalidJobIsAccepted) {
  auto e = open();
  const std::string text = ";!knitout-2\n;;Carriers: 1 2 3\ninhook 3\nknit + f1 3\n";
  auto job = make_job("good.k", Bytes(text.begin(), text.end()));
  ASSERT_TRUE(job.ok());
  send_all(*e, job.value(), 9);
  e->tick(now_);
  EXPECT_EQ(e->state(), JobState::Done);
}

TEST_F(DeviceEngineTest, RefusesUnsafeNames) {
  auto e = open();
  ManifestMessage m = test::make_sheet_job("s.k", 2, 2).manifest();
  m.name = "../escape.k";
  const StatusMessage s = status_of(call(*e, FrameType::Manifest, 3, 1, encode(m))[0]);
  EXPECT_EQ(s.state, JobState::Refused);
  EXPECT_EQ(s.reason,
            "[J001] the job name '../escape.k' names a folder; a plain file name is needed");
}

// The name rule (docs/protocol.md §7), at the device: every name a hostile
// client may send is refused with J001 before anything touches the disk,
// and the device takes the next job.
TEST_F(DeviceEngineTest, HostileNamesAreRefusedBeforeTheDiskAndTheDeviceKeepsServing) {
  auto e = open();
  const std::vector<std::string> names = {
      std::string(240, 'a') + ".k",  // its manifest's temporary name is too long
      std::string(201, 'b'),         // just over the limit
      std::string("\xff\xfe.k"),     // not UTF-8
      std::string("ok\xc3.k"),       // a cut sequence
      "X.k.manifest.json",           // would overwrite job X.k's manifest
      "X.K.MANIFEST.JSON",
      "job.part",
      "job.k.knitlog",
      ".hidden.k",
      "a.k.tmp-123456",
      "tab\tname.k",
      "con:.k",
      "trailing.k ",
      ""};
  std::uint32_t id = 40;
  for (const std::string& name : names) {
    ManifestMessage m = test::make_sheet_job("s.k", 2, 2).manifest();
    m.name = name;
    const StatusMessage s = status_of(call(*e, FrameType::Manifest, ++id, 1, encode(m))[0]);
    EXPECT_EQ(s.state, JobState::Refused) << printable_name(name);
    EXPECT_EQ(s.reason.rfind("[J001] ", 0), 0u) << s.reason;
  }
  // Nothing but the device's own folder was created.
  for (const auto& entry : std::filesystem::directory_iterator(store_)) {
    EXPECT_EQ(entry.path().filename(), ".wearknit-device") << entry.path();
  }
  // A refused name survives a restart as printable text, and the device
  // takes the next job.
  e.reset();
  e = open();
  const Job job = test::make_sheet_job("s.k", 3, 3);
  send_all(*e, job, 77);
  e->tick(now_);
  EXPECT_EQ(e->state(), JobState::Done);
}

TEST_F(DeviceEngineTest, AnUnreadableStateIsSetAsideAndTheDeviceStartsIdle) {
  std::filesystem::create_directories(store_ / ".wearknit-device");
  wearknit::test::write_file(store_ / ".wearknit-device" / "state.json", "{\"job_id\": 3, garbage");
  wearknit::test::write_file(store_ / "old.k.manifest.json.tmp-ab12cd", "half");
  wearknit::test::write_file(store_ / ".wearknit-device" / "state.json.tmp-99", "half");
  auto e = open();
  EXPECT_EQ(e->state(), JobState::Idle);
  EXPECT_FALSE(std::filesystem::exists(store_ / ".wearknit-device" / "state.json"));
  EXPECT_FALSE(std::filesystem::exists(store_ / "old.k.manifest.json.tmp-ab12cd"));
  EXPECT_FALSE(std::filesystem::exists(store_ / ".wearknit-device" / "state.json.tmp-99"));
  int kept = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(store_ / ".wearknit-device" / "quarantine")) {
    EXPECT_EQ(wearknit::test::read_file(entry.path()), "{\"job_id\": 3, garbage");
    ++kept;
  }
  EXPECT_EQ(kept, 1);
  const auto said = [&](const std::string& text) {
    return std::any_of(events_.begin(), events_.end(), [&](const std::string& line) {
      return line.find(text) != std::string::npos;
    });
  };
  EXPECT_TRUE(said("unreadable device state"));
  EXPECT_TRUE(said("removed the temporary file"));
  const Job job = test::make_sheet_job("s.k", 3, 3);
  send_all(*e, job, 5);
  e->tick(now_);
  EXPECT_EQ(e->state(), JobState::Done);
}

// A store written by an earlier version that took a 240-byte name: the
// unfinished job is refused and its files quarantined on every start, never
// a crash loop.
TEST_F(DeviceEngineTest, AnUnfinishedJobWithANameTheRuleRefusesIsQuarantined) {
  const std::string name(240, 'n');
  {
    auto e = open();
    const Job job = test::make_sheet_job("s.k", 3, 6);
    call(*e, FrameType::Manifest, 9, 1, encode(job.manifest()));
    for (std::uint32_t r = 0; r < 3; ++r) {
      call(*e, FrameType::Row, 9, r, Bytes(job.row(r).begin(), job.row(r).end()));
    }
    ASSERT_EQ(e->state(), JobState::Receiving);
  }
  const auto state = store_ / ".wearknit-device" / "state.json";
  std::string text = wearknit::test::read_file(state);
  const auto at = text.find("\"s.k\"");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 5, "\"" + name + "\"");
  wearknit::test::write_file(state, text);
  for (int start = 0; start < 2; ++start) {
    auto e = open();
    EXPECT_EQ(e->state(), JobState::Refused);
    EXPECT_EQ(e->status().reason.rfind("[J009] refused on start: [J001] ", 0), 0u)
        << e->status().reason;
  }
  EXPECT_TRUE(std::filesystem::exists(store_ / ".wearknit-device" / "quarantine" / "job-9"));
  EXPECT_FALSE(std::filesystem::exists(store_ / ".wearknit-device" / "job-9.part"));
  auto e = open();
  const Job next = test::make_sheet_job("t.k", 3, 3);
  send_all(*e, next, 10);
  e->tick(now_);
  EXPECT_EQ(e->state(), JobState::Done);
}

// A DAT whose runs fill a 65536 x 65536 raster (34 MB for 4 GiB of pixels)
// is refused by the device's check from its declared size, in the job's
// own bytes and no more.
TEST_F(DeviceEngineTest, ADatBombIsRefusedByItsDeclaredSize) {
  const Bytes bomb = test::make_dat_bomb();
  DeviceConfig config;
  config.store = store_;
  config.sync = false;
  config.buffer_rows = 64;
  config.checkers = test::test_checkers();
  auto opened = DeviceEngine::open(config);
  ASSERT_TRUE(opened.ok());
  DeviceEngine& e = *opened.value();
  // A hostile host cuts the bytes as it likes; the device cuts them again.
  constexpr std::size_t kChunk = 32768;
  ManifestMessage m;
  m.format = JobFormat::Dat;
  m.size = bomb.size();
  m.rows = static_cast<std::uint32_t>((bomb.size() + kChunk - 1) / kChunk);
  m.sha256 = sha256(bomb);
  m.name = "bomb.dat";
  call(e, FrameType::Manifest, 3, 1, encode(m));
  for (std::uint32_t r = 0; r < m.rows; ++r) {
    const std::size_t from = r * kChunk;
    call(e, FrameType::Row, 3, r,
         Bytes(bomb.begin() + static_cast<std::ptrdiff_t>(from),
               bomb.begin() + static_cast<std::ptrdiff_t>(std::min(bomb.size(), from + kChunk))));
  }
  for (int i = 0; i < 200 && e.state() == JobState::Receiving; ++i) {
    e.tick(now_);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  EXPECT_EQ(e.state(), JobState::Refused);
  EXPECT_NE(e.status().reason.find("[D047] DAT raster too large"), std::string::npos)
      << e.status().reason;
  EXPECT_FALSE(std::filesystem::exists(store_ / "bomb.dat"));
}

// A slow check runs beside the device's replies: STATUS? is answered at
// once while the job is checked, and the answer comes with a later tick.
TEST_F(DeviceEngineTest, ASlowCheckKeepsTheDeviceAnswering) {
  DeviceConfig config;
  config.store = store_;
  config.sync = false;
  config.background_check_bytes = 0;  // every job is checked on the worker
  config.checkers.knitout = [](const std::string&, std::span<const std::uint8_t>) {
    std::this_thread::sleep_for(std::chrono::milliseconds(400));
    return std::string();
  };
  auto opened = DeviceEngine::open(config);
  ASSERT_TRUE(opened.ok());
  DeviceEngine& e = *opened.value();
  const Job job = test::make_sheet_job("slow.k", 3, 3);
  call(e, FrameType::Manifest, 4, 1, encode(job.manifest()));
  for (std::uint32_t r = 0; r < job.row_count(); ++r) {
    call(e, FrameType::Row, 4, r, Bytes(job.row(r).begin(), job.row(r).end()));
  }
  e.tick(now_);
  const auto asked = std::chrono::steady_clock::now();
  const StatusMessage during = status_of(call(e, FrameType::StatusRequest, 4, 9)[0]);
  EXPECT_LT(std::chrono::steady_clock::now() - asked, std::chrono::milliseconds(200));
  EXPECT_EQ(during.state, JobState::Receiving);
  EXPECT_EQ(during.rows_received, job.row_count());
  for (int i = 0; i < 300 && e.state() == JobState::Receiving; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    e.tick(now_);
  }
  EXPECT_NE(e.state(), JobState::Receiving);
  EXPECT_NE(e.state(), JobState::Refused) << e.status().reason;
}

TEST_F(DeviceEngineTest, ACheckerThatThrowsRefusesTheJobAndTheDeviceKeepsServing) {
  DeviceConfig config;
  config.store = store_;
  config.sync = false;
  config.checkers.knitout = [](const std::string&, std::span<const std::uint8_t>) -> std::string {
    throw std::runtime_error("checker failed");
  };
  auto opened = DeviceEngine::open(config);
  ASSERT_TRUE(opened.ok());
  DeviceEngine& e = *opened.value();
  send_all(e, test::make_sheet_job("t.k", 3, 3), 6);
  e.tick(now_);
  EXPECT_EQ(e.state(), JobState::Refused);
  EXPECT_EQ(e.status().reason, "[J007] the device could not check the job: checker failed");
}

TEST_F(DeviceEngineTest, CountersSurviveARestartAndTheBufferDoesNot) {
  const Job job = test::make_sheet_job("s.k", 4, 8);
  {
    auto e = open(/*buffer_rows=*/8);
    call(*e, FrameType::Manifest, 11, 1, encode(job.manifest()));
    for (std::uint32_t r = 0; r < 3; ++r) {
      call(*e, FrameType::Row, 11, r, Bytes(job.row(r).begin(), job.row(r).end()));
    }
    e->tick(now_);  // rows 0-2 reach the store
    for (std::uint32_t r = 3; r < 5; ++r) {
      call(*e, FrameType::Row, 11, r, Bytes(job.row(r).begin(), job.row(r).end()));
    }
    EXPECT_EQ(e->status().rows_received, 5u);
  }  // power cut: rows 3-4 were only in RAM
  auto e = open(8);
  const StatusMessage s = status_of(call(*e, FrameType::Hello, 0, 1, encode(HelloMessage{}))[0]);
  EXPECT_EQ(s.state, JobState::Receiving);
  EXPECT_EQ(s.rows_received, 3u);
  EXPECT_EQ(s.name, "s.k");
  for (std::uint32_t r = 3; r < job.row_count(); ++r) {
    call(*e, FrameType::Row, 11, r, Bytes(job.row(r).begin(), job.row(r).end()));
    e->tick(now_);
  }
  EXPECT_EQ(e->state(), JobState::Done);
  EXPECT_EQ(test::read_text(store_ / "s.k"), std::string(job.bytes.begin(), job.bytes.end()));
}

TEST_F(DeviceEngineTest, KnittingResumesFromTheLogAfterARestart) {
  const Job job = test::make_sheet_job("s.k", 4, 20);
  {
    auto e = open(32, /*rows_per_s=*/10);
    send_all(*e, job, 12);
    e->tick(now_);        // knitting starts
    e->tick(now_ + 0.5);  // 5 rows
    EXPECT_EQ(e->rows_knitted(), 5u);
  }
  auto e = open(32, 10);
  EXPECT_EQ(e->rows_knitted(), 5u);
  e->tick(now_ + 10);  // knitting clock restarts at the first tick
  e->tick(now_ + 20);
  EXPECT_EQ(e->state(), JobState::Done);
  auto log = e->verify_knit_log(12, job.row_count());
  ASSERT_TRUE(log.ok()) << log.error().text();
  EXPECT_EQ(log.value(), job.row_count());
}

TEST_F(DeviceEngineTest, PauseResumeAndCancelAreAcknowledged) {
  const Job job = test::make_sheet_job("s.k", 4, 40);
  auto e = open(32, 10);
  send_all(*e, job, 13);
  e->tick(now_);
  now_ += 0.35;
  e->tick(now_);
  const auto command = [&](std::uint32_t job_id, Command c) {
    return status_of(call(*e, FrameType::Command, job_id, 2, encode(CommandMessage{c}))[0]);
  };
  EXPECT_EQ(command(13, Command::Pause).state, JobState::Paused);
  const std::uint32_t at = e->rows_knitted();
  EXPECT_EQ(at, 3u);
  now_ += 5;
  e->tick(now_);
  EXPECT_EQ(e->rows_knitted(), at);  // paused: nothing knitted
  EXPECT_EQ(command(13, Command::Resume).state, JobState::Knitting);
  now_ += 0.55;
  e->tick(now_);
  EXPECT_EQ(e->rows_knitted(), at + 5);
  EXPECT_EQ(command(99, Command::Cancel).state, JobState::Knitting);  // another job: ignored
  const StatusMessage cancelled = command(13, Command::Cancel);
  EXPECT_EQ(cancelled.state, JobState::Cancelled);
  EXPECT_EQ(cancelled.rows_knitted, at + 5);
  now_ += 10;
  e->tick(now_);
  EXPECT_EQ(e->rows_knitted(), at + 5);  // cancelled: nothing more
}

TEST_F(DeviceEngineTest, YarnBreakStopsKnittingUntilResumed) {
  yarn_break_at_ = 6;
  const Job job = test::make_sheet_job("s.k", 4, 20);
  auto e = open(32, 0);
  send_all(*e, job, 14);
  e->tick(now_);
  EXPECT_EQ(e->state(), JobState::Alarm);
  EXPECT_EQ(e->status().alarm, Alarm::YarnBreak);
  EXPECT_EQ(e->rows_knitted(), 6u);
  e->tick(now_ + 1);
  EXPECT_EQ(e->rows_knitted(), 6u);
  call(*e, FrameType::Command, 14, 2, encode(CommandMessage{Command::Resume}));
  e->tick(now_ + 2);
  EXPECT_EQ(e->state(), JobState::Done);
  EXPECT_TRUE(e->verify_knit_log(14, job.row_count()).ok());
}

TEST_F(DeviceEngineTest, ABusyDeviceKeepsItsJobWhenAnotherManifestArrives) {
  const Job a = test::make_sheet_job("a.k", 4, 4);
  const Job b = test::make_sheet_job("b.k", 4, 5);
  auto e = open();
  call(*e, FrameType::Manifest, 1, 1, encode(a.manifest()));
  const StatusMessage s = status_of(call(*e, FrameType::Manifest, 2, 2, encode(b.manifest()))[0]);
  EXPECT_EQ(s.name, "a.k");
  EXPECT_EQ(e->job_id(), 1u);
}

TEST_F(DeviceEngineTest, KnitLogCheckFindsARowKnittedTwice) {
  auto e = open();
  std::filesystem::create_directories(store_ / ".wearknit-device");
  wearknit::test::write_file(e->knit_log_path(77), "0\n1\n1\n");
  auto log = e->verify_knit_log(77, 3);
  ASSERT_FALSE(log.ok());
  EXPECT_EQ(log.error().message, "row 1 was knitted twice");
}

}  // namespace
}  // namespace devices
