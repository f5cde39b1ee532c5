// The job protocol under every fault the mock can inject, in a deterministic
// simulation: the host session and the device engine exchange frames
// through lossy pipes on a virtual clock (1 ms steps), 200 seeds per fault
// kind and 200 with all of them at once. Every run must end with the stored
// job byte-identical to the sent one and every row knitted exactly once.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <deque>
#include <iostream>
#include <random>

#include "devices/device_engine.hpp"
#include "devices/faults.hpp"
#include "devices/host_session.hpp"
#include "tests/devices/device_test_support.hpp"
#include "tests/test_support.hpp"

namespace devices {
namespace {

struct SimResult {
  bool host_done = false;
  std::string host_message;
  int steps = 0;
  int disconnects = 0;
  int reboots = 0;
  int host_kills = 0;
  int device_kills = 0;
};

// Kills of either side: each step, with these chances, the sender process
// dies (a new one starts with --resume) or the device process dies (its
// engine is destroyed and opened again on the same store), at most
// `max_kills` times each.
struct Kills {
  double host_per_step = 0;
  double device_per_step = 0;
  int max_kills = 0;
};

SimResult simulate(const Job& job, const FaultSpec& spec, std::uint64_t seed,
                   const std::filesystem::path& store, std::unique_ptr<DeviceEngine>& engine,
                   const Kills& kills = {}) {
  DeviceConfig config;
  config.store = store;
  config.buffer_rows = 4;
  config.rows_per_s = 2000;
  config.sync = false;  // a simulated power cycle cannot lose unsynced pages
  config.checkers = test::test_checkers();
  config.yarn_break_at_row = spec.yarn_break_at;
  auto opened = DeviceEngine::open(config);
  if (!opened) throw std::runtime_error(opened.error().text());
  engine = std::move(opened.value());

  FaultInjector faults(spec, seed);
  SendOptions options;
  options.max_window = 8;
  options.rto_s = 0.02;
  options.max_rto_s = 0.2;
  options.poll_s = 0.005;
  options.silence_s = 0.5;
  auto host = std::make_unique<HostSession>(job, options,
                                            static_cast<std::uint32_t>(seed * 2654435761u + 1));
  std::mt19937_64 killer(seed ^ 0x9e3779b97f4a7c15ull);
  std::uniform_real_distribution<double> chance(0.0, 1.0);
  std::deque<Bytes> to_device;  // wire frames in flight, whole
  std::deque<Bytes> to_host;
  SlipDecoder device_decoder;
  SlipDecoder host_decoder;
  SimResult result;
  double now = 0;
  double stalled_until = -1;
  const auto cut_link = [&] {
    to_device.clear();
    to_host.clear();
    device_decoder.reset();
    host_decoder.reset();
    ++result.disconnects;
    host->on_connect(now);
  };
  host->on_connect(now);
  for (result.steps = 0; result.steps < 400000 && !host->finished(); ++result.steps) {
    now += 0.001;
    if (result.host_kills < kills.max_kills && chance(killer) < kills.host_per_step) {
      // The sender dies; the operator runs `send --resume` with a new job id.
      ++result.host_kills;
      SendOptions again = options;
      again.resume = true;
      host = std::make_unique<HostSession>(job, again, static_cast<std::uint32_t>(killer()));
      cut_link();
    }
    if (result.device_kills < kills.max_kills && chance(killer) < kills.device_per_step) {
      // The device process dies and starts again on its store.
      ++result.device_kills;
      engine.reset();
      auto reopened = DeviceEngine::open(config);
      if (!reopened) throw std::runtime_error(reopened.error().text());
      engine = std::move(reopened.value());
      cut_link();
    }
    for (const Frame& f : host->take_outbox()) to_device.push_back(encode_wire(f));
    bool cut = false;
    while (!cut && now >= stalled_until && !to_device.empty()) {
      const Bytes wire = std::move(to_device.front());
      to_device.pop_front();
      std::vector<Bytes> frames;
      device_decoder.feed(wire, [&](std::span<const std::uint8_t> raw) {
        frames.emplace_back(raw.begin(), raw.end());
      });
      for (Bytes& raw : frames) {
        std::vector<Frame> replies;
        for (const Bytes& copy : faults.pass(std::move(raw))) {
          Frame frame;
          if (decode_frame(copy, frame)) engine->handle(frame, now, replies);
        }
        for (const Frame& reply : replies) {
          for (Bytes& w : faults.pass(encode_wire(reply))) to_host.push_back(std::move(w));
        }
        const auto event = faults.after_received_frame();
        if (event == FaultInjector::Event::Reboot) {
          engine->reboot(now);
          ++result.reboots;
          cut_link();
          cut = true;
          break;
        }
        if (event == FaultInjector::Event::Disconnect) {
          cut_link();
          cut = true;
          break;
        }
        if (const std::uint32_t ms = faults.stall_now(); ms != 0) stalled_until = now + ms / 1000.0;
      }
    }
    engine->tick(now);
    if (engine->state() == JobState::Alarm) {
      // The operator mends the yarn and presses start.
      std::vector<Frame> ignored;
      engine->handle(Frame{FrameType::Command, 0, engine->job_id(), 0,
                           encode(CommandMessage{Command::Resume})},
                     now, ignored);
    }
    while (!to_host.empty()) {
      const Bytes wire = std::move(to_host.front());
      to_host.pop_front();
      host_decoder.feed(wire, [&](std::span<const std::uint8_t> raw) {
        Frame frame;
        if (decode_frame(raw, frame)) host->on_frame(frame, now);
      });
    }
    host->poll(now);
    if (host->wants_reconnect()) cut_link();
  }
  result.host_done = host->phase() == Phase::Done;
  result.host_message = host->message();
  return result;
}

// The device's store for the simulations. ext4 flushes a file replaced by
// rename at once, which makes the thousands of small state writes of these
// runs slow on disk; a RAM-backed folder keeps the same semantics.
std::filesystem::path scratch_dir() {
  std::error_code ec;
  if (std::filesystem::is_directory("/dev/shm", ec)) {
    std::string pattern = "/dev/shm/wk-faults-XXXXXX";
    if (::mkdtemp(pattern.data()) != nullptr) return pattern;
  }
  return wearknit::test::make_temp_dir("wk-faults");
}

struct Case {
  const char* name;
  FaultSpec spec;
};

std::vector<Case> cases() {
  std::vector<Case> all;
  FaultSpec f;
  f.corrupt = 0.05;
  all.push_back({"corrupt", f});
  f = {};
  f.drop = 0.05;
  all.push_back({"drop", f});
  f = {};
  f.dup = 0.05;
  all.push_back({"dup", f});
  f = {};
  f.disconnect_every = 9;
  all.push_back({"disconnect", f});
  f = {};
  f.reboot_every = 13;
  all.push_back({"reboot", f});
  f = {};
  f.stall_ms = 40;
  all.push_back({"stall", f});
  f = {};
  f.yarn_break_at = 7;
  all.push_back({"alarm", f});
  f = {};
  f.corrupt = 0.03;
  f.drop = 0.03;
  f.dup = 0.03;
  f.disconnect_every = 23;
  f.reboot_every = 37;
  f.stall_ms = 25;
  f.yarn_break_at = 5;
  all.push_back({"all", f});
  return all;
}

TEST(FaultInjectionTest, EveryRowArrivesIntactAndIsKnittedExactlyOnce) {
  const Job job = test::make_sheet_job("fault.k", 5, 14);  // 16 rows
  const std::string sent(job.bytes.begin(), job.bytes.end());
  const auto root = scratch_dir();
  constexpr int kSeeds = 200;
  for (const Case& c : cases()) {
    int disconnects = 0;
    int reboots = 0;
    int max_steps = 0;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const auto store = root / (std::string(c.name) + "-" + std::to_string(seed));
      std::unique_ptr<DeviceEngine> engine;
      const SimResult r = simulate(job, c.spec, static_cast<std::uint64_t>(seed), store, engine);
      SCOPED_TRACE(std::string(c.name) + " seed " + std::to_string(seed));
      ASSERT_TRUE(r.host_done) << r.host_message << " after " << r.steps << " steps";
      ASSERT_EQ(engine->state(), JobState::Done);
      ASSERT_EQ(test::read_text(store / "fault.k"), sent);
      const auto log = engine->verify_knit_log(engine->job_id(), job.row_count());
      ASSERT_TRUE(log.ok()) << log.error().text();
      ASSERT_EQ(log.value(), job.row_count());
      disconnects += r.disconnects;
      reboots += r.reboots;
      max_steps = std::max(max_steps, r.steps);
      std::filesystem::remove_all(store);
    }
    // The faults really happened.
    if (c.spec.disconnect_every != 0) {
      EXPECT_GT(disconnects, kSeeds / 4) << c.name;
    }
    if (c.spec.reboot_every != 0) {
      EXPECT_GT(reboots, 0) << c.name;
    }
    RecordProperty(std::string(c.name) + "_max_steps", max_steps);
  }
  std::filesystem::remove_all(root);
}

TEST(FaultInjectionTest, TheDoneWhenFaultsFinishATwoHundredRowJob) {
  // corrupt=0.01,drop=0.01,dup=0.01,disconnect-every=500 on a bigger job.
  const Job job = test::make_sheet_job("big.k", 12, 200);
  FaultSpec spec;
  spec.corrupt = spec.drop = spec.dup = 0.01;
  spec.disconnect_every = 50;
  const auto root = scratch_dir();
  std::unique_ptr<DeviceEngine> engine;
  const SimResult r = simulate(job, spec, 99, root, engine);
  ASSERT_TRUE(r.host_done) << r.host_message;
  EXPECT_GT(r.disconnects, 2);
  EXPECT_EQ(test::read_text(root / "big.k"), std::string(job.bytes.begin(), job.bytes.end()));
  EXPECT_TRUE(engine->verify_knit_log(engine->job_id(), job.row_count()).ok());
  std::filesystem::remove_all(root);
}

// The soak: 200 seeded runs, each with its own random mix of every fault
// and random kills of the sender and of the device process. Every run ends
// with the stored job byte-identical and every row knitted exactly once,
// within a bounded number of steps.
TEST(FaultInjectionTest, SoakOfRandomFaultMixesAndKillsOfEitherSide) {
  const Job job = test::make_sheet_job("soak.k", 6, 30);
  const std::string sent(job.bytes.begin(), job.bytes.end());
  const auto root = scratch_dir();
  constexpr int kRuns = 200;
  int disconnects = 0;
  int reboots = 0;
  int host_kills = 0;
  int device_kills = 0;
  int max_steps = 0;
  std::uint64_t bytes = 0;
  for (int seed = 1; seed <= kRuns; ++seed) {
    std::mt19937_64 mix(static_cast<std::uint64_t>(seed) * 7919u);
    auto pick = [&](std::initializer_list<double> values) {
      return *(values.begin() + static_cast<std::ptrdiff_t>(mix() % values.size()));
    };
    FaultSpec spec;
    spec.corrupt = pick({0, 0.01, 0.05, 0.1});
    spec.drop = pick({0, 0.01, 0.05, 0.1});
    spec.dup = pick({0, 0.01, 0.05});
    spec.disconnect_every = static_cast<std::uint32_t>(pick({0, 7, 19, 53}));
    spec.reboot_every = static_cast<std::uint32_t>(pick({0, 2, 5, 17, 41}));
    spec.stall_ms = static_cast<std::uint32_t>(pick({0, 10, 60}));
    spec.yarn_break_at = static_cast<std::uint32_t>(pick({0, 0, 3, 20}));
    Kills kills;
    kills.host_per_step = pick({0, 0.004, 0.012});
    kills.device_per_step = pick({0, 0.004, 0.012});
    kills.max_kills = 4;
    const auto store = root / ("soak-" + std::to_string(seed));
    std::unique_ptr<DeviceEngine> engine;
    const SimResult r = simulate(job, spec, static_cast<std::uint64_t>(seed), store, engine, kills);
    SCOPED_TRACE("soak seed " + std::to_string(seed));
    ASSERT_TRUE(r.host_done) << r.host_message << " after " << r.steps << " steps";
    ASSERT_EQ(engine->state(), JobState::Done);
    ASSERT_EQ(test::read_text(store / "soak.k"), sent);
    const auto log = engine->verify_knit_log(engine->job_id(), job.row_count());
    ASSERT_TRUE(log.ok()) << log.error().text();
    ASSERT_EQ(log.value(), job.row_count());
    disconnects += r.disconnects;
    reboots += r.reboots;
    host_kills += r.host_kills;
    device_kills += r.device_kills;
    max_steps = std::max(max_steps, r.steps);
    bytes += job.bytes.size();
    engine.reset();
    std::filesystem::remove_all(store);
  }
  // The faults and kills really happened.
  EXPECT_GT(reboots, kRuns);
  EXPECT_GT(host_kills, kRuns / 4);
  EXPECT_GT(device_kills, kRuns / 4);
  std::cout << "soak: " << kRuns << " runs, " << bytes << " bytes, " << disconnects
            << " disconnects, " << reboots << " reboots, " << host_kills << " sender kills, "
            << device_kills << " device kills, at most " << max_steps
            << " steps (ms); every job byte-identical, every row knitted once\n";
  std::filesystem::remove_all(root);
}

}  // namespace
}  // namespace devices
