// Sending a job over a real link: HostSession driven by a Transport, with
// reconnection. Also the one-shot requests behind `wearknit status`.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "devices/host_session.hpp"
#include "devices/job.hpp"
#include "devices/transport.hpp"

namespace devices {

struct LinkOptions {
  // Attempts in a row (connections, or tries to connect) that moved the job
  // no further before giving up. Only progress that lasts resets the count:
  // more rows stored on the device, more rows knitted, the job accepted or
  // verified; rows the device only buffered do not.
  int max_attempts = 8;
  double first_backoff_s = 0.1;  // doubles per failed attempt, up to max_backoff_s
  double max_backoff_s = 2.0;
  int write_timeout_ms = 2000;
  JobCheckers loopback_checkers;  // for loopback: URIs
  std::uint32_t job_id = 0;       // 0: random
  std::string job_path;           // the job file as the user gave it, for hints; the name if empty
  // Opens the link instead of the URI's own transport when set (tests put a
  // transport over a faked libserialport or libusb here).
  std::function<Result<std::unique_ptr<Transport>>()> open;
};

struct SendReport {
  bool done = false;  // every row knitted
  std::string message;
  Progress progress;
  int reconnects = 0;
  double seconds = 0;
};

// Called after every batch of frames and on notable events (`note` non-empty:
// "connection lost: ...", "reconnected", ...).
using ProgressCallback = std::function<void(const Progress& progress, const std::string& note)>;

// Sends `job` to `uri` (a stream URI) until the device reports every row
// knitted or the job fails at the device (SendReport.done false, message
// says why). A Disconnected error means the link could not be brought back
// within the bounds of LinkOptions; its message says how to resume when
// anything reached the device. A Protocol error "[J010] ... not a wearknit
// device" means the peer answered in another protocol (recognised on its
// first bytes; nothing is retried).
Result<SendReport> send_job(const DeviceUri& uri, const Job& job, const SendOptions& options,
                            const LinkOptions& link, const ProgressCallback& on_progress);

struct DeviceStatus {
  std::uint32_t job_id = 0;
  StatusMessage status;
};

// HELLO -> STATUS, retried a few times.
Result<DeviceStatus> query_status(const DeviceUri& uri, const LinkOptions& link = {});

// Sends a command for the device's current job and waits until a STATUS
// shows it took effect (pause: paused; resume: knitting or receiving;
// cancel: cancelled). Fails with Protocol when the device has no unfinished
// job.
Result<DeviceStatus> send_command(const DeviceUri& uri, Command command,
                                  const LinkOptions& link = {});

}  // namespace devices
