// The mock knitting machine's logic (docs/protocol.md §5, docs/devices.md):
// a state machine that answers frames and advances with time, independent of
// any transport. `mock-device`, the loopback: transport, the umockdev USB
// test and the fault-injection simulation all drive this one class.
//
// The device keeps, in its store folder:
//   NAME, NAME.manifest.json          every verified job, as the sender named it
//   .wearknit-device/state.json       counters (written atomically: temp + rename)
//   .wearknit-device/job-ID.part      the rows received so far, in order
//   .wearknit-device/job-ID.knitlog   one line per knitted row: its index
//   .wearknit-device/quarantine/      what a start could not take up (an
//                                     unreadable state, a job an earlier
//                                     version accepted under a bad name)
// Rows pass through a RAM buffer of `buffer_rows` rows on their way to the
// spool (moved on every tick, and at once when full); rows that arrive past a
// gap wait there for the missing one. A reboot loses the buffer and nothing
// else; a device that comes up with a job still arriving stores every row
// before acknowledging it for the rest of that job, so frequent power cuts
// cannot keep a job from arriving. Acknowledgements announce the buffer's
// free room: the host's window. A job is knitted only
// after all of it arrived and its size, SHA-256, row count and the format's
// checker agreed; knitting then advances at `rows_per_s` and the knit log is
// the knitted counter, so a row is never knitted twice across restarts.
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <future>
#include <map>
#include <string>
#include <vector>

#include "devices/framing.hpp"
#include "devices/job.hpp"
#include "devices/protocol.hpp"
#include "devices/result.hpp"

namespace devices {

struct DeviceConfig {
  std::filesystem::path store;
  std::uint32_t buffer_rows = 32;
  double rows_per_s = 0;  // 0: a row is knitted as soon as the job is verified
  bool sync = true;       // fsync spool, log and state; off only for simulations
  JobCheckers checkers;
  // Alarms raised once per job when the knitted count reaches the row (0 = never).
  std::uint32_t yarn_break_at_row = 0;
  std::uint32_t stop_at_row = 0;
  // Receives one line per event worth telling the operator.
  std::function<void(const std::string&)> on_event;
  // Jobs larger than this are refused at their manifest (J008), as are jobs
  // larger than the store's free space.
  std::uint64_t max_job_bytes = std::uint64_t{1} << 32;
  // Complete jobs larger than this are checked on a worker thread, so the
  // device answers keep-alives while it checks; smaller ones at once.
  std::uint64_t background_check_bytes = std::uint64_t{1} << 20;
};

class DeviceEngine {
 public:
  // Loads the store's state (creating the folder when needed).
  static Result<std::unique_ptr<DeviceEngine>> open(DeviceConfig config);

  // Answers one frame from a host: appends the reply frames.
  void handle(const Frame& frame, double now_s, std::vector<Frame>& replies);
  // Moves buffered rows to the spool, verifies a complete job, knits.
  void tick(double now_s);
  // Power cycle: the RAM buffer is lost, everything else is read back.
  void reboot(double now_s);

  StatusMessage status() const;
  std::uint32_t job_id() const { return job_id_; }
  std::uint32_t rows_knitted() const { return knitted_; }
  JobState state() const;
  const std::filesystem::path& store() const { return config_.store; }

  // Reads a job's knit log and checks it holds each row 0..rows-1 exactly
  // once, in order. Returns the row count, or an error naming the first
  // row that is missing or repeated.
  Result<std::uint32_t> verify_knit_log(std::uint32_t job_id, std::uint32_t rows) const;
  std::filesystem::path knit_log_path(std::uint32_t job_id) const;

 private:
  explicit DeviceEngine(DeviceConfig config) : config_(std::move(config)) {}
  DeviceEngine(const DeviceEngine&) = delete;
  DeviceEngine& operator=(const DeviceEngine&) = delete;

 public:
  ~DeviceEngine();

 private:
  Outcome load();
  void reset_state();
  void quarantine_job(const std::string& why);
  void remove_stale_temporaries();
  void handle_frame(const Frame& frame, double now_s, std::vector<Frame>& replies);
  void advance(double now_s);
  void refuse_for_store_failure(const std::exception& failure);
  void save();
  void event(const std::string& text) const;
  std::uint32_t accepted() const { return received_ + static_cast<std::uint32_t>(buffer_.size()); }
  void flush_buffer();
  void clear_buffers();
  std::uint32_t free_rows() const;
  void take_row(std::uint32_t row, const Bytes& payload);
  void start_check();
  void finish_check();
  void store_job();
  void knit(double now_s);
  void refuse(std::string reason);
  std::filesystem::path state_dir() const { return config_.store / ".wearknit-device"; }
  std::filesystem::path part_path() const;

  DeviceConfig config_;
  // Persistent (state.json + knit log).
  std::uint32_t job_id_ = 0;
  JobState state_ = JobState::Idle;  // never Paused: paused_ is separate
  bool paused_ = false;
  Alarm alarm_ = Alarm::None;
  bool yarn_break_fired_ = false;
  bool stop_fired_ = false;
  ManifestMessage manifest_;
  std::uint32_t received_ = 0;
  std::uint64_t bytes_received_ = 0;
  std::uint32_t knitted_ = 0;
  std::string reason_;
  std::uint64_t jobs_done_ = 0;
  std::uint64_t rows_knitted_total_ = 0;
  // RAM only.
  std::deque<Bytes> buffer_;  // rows accepted() - buffer_.size() .. accepted() - 1
  std::uint64_t buffered_bytes_ = 0;
  std::map<std::uint32_t, Bytes> ahead_;  // rows that arrived past a gap
  std::uint64_t ahead_bytes_ = 0;
  double knit_origin_s_ = -1;
  std::uint32_t knit_origin_rows_ = 0;
  // Set when the device came up with a job still arriving: its RAM buffer
  // was lost once, so every row is stored before it is acknowledged.
  bool write_through_ = false;
  std::future<std::string> check_;  // the running check of a complete job
};

}  // namespace devices
