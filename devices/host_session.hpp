// The sending side of the job protocol (docs/protocol.md §5) as a state
// machine over frames and time, independent of any transport: `send_job`
// drives it over a real link, the tests drive it over simulated lossy pipes
// with a virtual clock.
//
// Rules it keeps: it resumes from the device's counters, never from its own
// memory; it sends a row only inside the window the device's free buffer
// allows; it resends the missing row alone after three duplicate
// acknowledgements (the device holds rows past a gap) and goes back to the
// device's cumulative count after a timeout (doubling, capped); and the
// job is done only when a STATUS says every row is knitted.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "devices/framing.hpp"
#include "devices/job.hpp"
#include "devices/protocol.hpp"

namespace devices {

struct SendOptions {
  bool resume = false;            // adopt the device's unfinished copy of this same job
  std::uint32_t max_window = 64;  // rows in flight at most
  double rto_s = 0.2;             // first retransmission timeout
  double max_rto_s = 2.0;
  double poll_s = 0.05;    // STATUS polling while the device knits
  double silence_s = 3.0;  // nothing valid heard for this long: reconnect
};

enum class Phase { Handshake, Manifest, Transfer, Knitting, Done, Failed };
std::string_view to_string(Phase phase);

struct Progress {
  Phase phase = Phase::Handshake;
  JobState device_state = JobState::Idle;
  Alarm alarm = Alarm::None;
  std::uint32_t rows_total = 0;
  std::uint32_t rows_received = 0;  // acknowledged by the device
  std::uint32_t rows_knitted = 0;
  // Rows the device holds in its store (its last STATUS): a power cycle
  // keeps these, while the rest of rows_received may be lost.
  std::uint32_t rows_durable = 0;
  // Times the device's count of received rows fell: it lost its buffer.
  std::uint32_t buffer_losses = 0;
  bool job_accepted = false;  // the device took this job's manifest
  std::uint64_t frames_sent = 0;
  std::uint64_t rows_sent = 0;  // including retransmissions
  std::uint64_t bytes_sent = 0;
};

class HostSession {
 public:
  HostSession(const Job& job, SendOptions options, std::uint32_t new_job_id);

  // A new link is up: start (or restart) with HELLO.
  void on_connect(double now_s);
  void on_frame(const Frame& frame, double now_s);
  // Runs the timers; may queue frames.
  void poll(double now_s);
  // Frames to write, in order; clears the queue.
  std::vector<Frame> take_outbox();

  bool finished() const { return phase_ == Phase::Done || phase_ == Phase::Failed; }
  bool wants_reconnect() const { return wants_reconnect_; }
  Phase phase() const { return phase_; }
  // Why the job failed, or a note on how it finished ("already knitted").
  const std::string& message() const { return message_; }
  Progress progress() const;
  std::uint32_t job_id() const { return job_id_; }
  // Seconds until poll() has something to do (for read timeouts).
  double next_timer_s(double now_s) const;

 private:
  void send(FrameType type, std::uint32_t seq, Bytes payload);
  void send_request(FrameType type, Bytes payload, double now_s);
  void on_status(const Frame& frame, const StatusMessage& status, double now_s);
  void apply_counters(JobState state, std::uint32_t received, std::uint32_t knitted,
                      std::uint32_t free, double now_s);
  void apply_state(const StatusMessage& status, double now_s);
  void fail(std::string message);
  void fill_window(double now_s);
  void resend_row(std::uint32_t row);

  const Job& job_;
  SendOptions options_;
  std::uint32_t new_job_id_;
  std::uint32_t job_id_ = 0;
  bool device_has_job_ = false;  // the device has answered about job_id_
  Phase phase_ = Phase::Handshake;
  std::string message_;
  bool wants_reconnect_ = false;
  std::vector<Frame> outbox_;
  std::uint32_t seq_ = 0;
  std::uint32_t pending_seq_ = 0;  // the request whose STATUS we wait for
  double last_request_s_ = 0;
  double last_heard_s_ = 0;
  double rto_s_ = 0;
  // Transfer window, in rows.
  std::uint32_t base_ = 0;   // rows the device has accepted
  std::uint32_t next_ = 0;   // next row to send
  std::uint32_t limit_ = 0;  // the device takes rows below this
  double last_advance_s_ = 0;
  double last_probe_s_ = 0;
  int duplicate_acks_ = 0;
  bool recovering_ = false;          // a lost row was resent on duplicate acks
  std::uint32_t recover_until_ = 0;  // ... and rows up to here were in flight then
  Progress progress_;
};

}  // namespace devices
