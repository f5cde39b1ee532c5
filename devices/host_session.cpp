#include "devices/host_session.hpp"

#include <algorithm>

#include "devices/debug.hpp"

namespace devices {

std::string_view to_string(Phase phase) {
  switch (phase) {
    case Phase::Handshake:
      return "handshake";
    case Phase::Manifest:
      return "manifest";
    case Phase::Transfer:
      return "transfer";
    case Phase::Knitting:
      return "knitting";
    case Phase::Done:
      return "done";
    case Phase::Failed:
      return "failed";
  }
  return "unknown";
}

HostSession::HostSession(const Job& job, SendOptions options, std::uint32_t new_job_id)
    : job_(job), options_(options), new_job_id_(new_job_id == 0 ? 1 : new_job_id) {
  progress_.rows_total = job.row_count();
}

Progress HostSession::progress() const {
  Progress p = progress_;
  p.phase = phase_;
  return p;
}

void HostSession::send(FrameType type, std::uint32_t seq, Bytes payload) {
  Frame f{type, 0, job_id_, seq, std::move(payload)};
  ++progress_.frames_sent;
  progress_.bytes_sent += f.payload.size() + kHeaderSize + kCrcSize;
  outbox_.push_back(std::move(f));
}

void HostSession::send_request(FrameType type, Bytes payload, double now_s) {
  pending_seq_ = ++seq_;
  last_request_s_ = now_s;
  send(type, pending_seq_, std::move(payload));
}

std::vector<Frame> HostSession::take_outbox() {
  std::vector<Frame> out;
  out.swap(outbox_);
  return out;
}

void HostSession::fail(std::string message) {
  phase_ = Phase::Failed;
  message_ = std::move(message);
}

void HostSession::on_connect(double now_s) {
  wants_reconnect_ = false;
  last_heard_s_ = now_s;
  rto_s_ = options_.rto_s;
  if (finished()) return;
  phase_ = Phase::Handshake;
  send_request(FrameType::Hello, encode(HelloMessage{}), now_s);
}

double HostSession::next_timer_s(double now_s) const {
  if (finished()) return 1.0;
  double due = last_request_s_ + (phase_ == Phase::Knitting ? options_.poll_s : rto_s_);
  if (phase_ == Phase::Transfer) {
    due = std::min(due, last_advance_s_ + rto_s_);
    if (next_ < limit_ && next_ < job_.row_count()) due = now_s;
  }
  return std::max(0.0, due - now_s);
}

void HostSession::poll(double now_s) {
  if (finished()) return;
  if (now_s - last_heard_s_ > options_.silence_s) {
    wants_reconnect_ = true;
    return;
  }
  switch (phase_) {
    case Phase::Handshake:
      if (now_s - last_request_s_ > rto_s_) {
        rto_s_ = std::min(rto_s_ * 2, options_.max_rto_s);
        send_request(FrameType::Hello, encode(HelloMessage{}), now_s);
      }
      return;
    case Phase::Manifest:
      if (now_s - last_request_s_ > rto_s_) {
        rto_s_ = std::min(rto_s_ * 2, options_.max_rto_s);
        send_request(FrameType::Manifest, encode(job_.manifest()), now_s);
      }
      return;
    case Phase::Transfer:
      if (now_s - last_advance_s_ > rto_s_) {
        // Go back to what the device has and send again (go-back-N).
        debug_line("host: retransmission timeout, back to row " + std::to_string(base_));
        next_ = base_;
        last_advance_s_ = now_s;
        recovering_ = false;
        rto_s_ = std::min(rto_s_ * 2, options_.max_rto_s);
        if (limit_ <= base_) limit_ = base_ + 1;  // probe with one row
      }
      if (next_ >= limit_ && now_s - last_probe_s_ > rto_s_ / 4) {
        // The device's buffer was full: ask how much room it has now.
        last_probe_s_ = now_s;
        send_request(FrameType::StatusRequest, {}, now_s);
      }
      fill_window(now_s);
      return;
    case Phase::Knitting:
      if (now_s - last_request_s_ > options_.poll_s) {
        send_request(FrameType::StatusRequest, {}, now_s);
      }
      return;
    case Phase::Done:
    case Phase::Failed:
      return;
  }
}

void HostSession::resend_row(std::uint32_t row) {
  const auto bytes = job_.row(row);
  send(FrameType::Row, row, Bytes(bytes.begin(), bytes.end()));
  ++progress_.rows_sent;
}

void HostSession::fill_window(double now_s) {
  const std::uint32_t total = job_.row_count();
  while (next_ < total && next_ < base_ + options_.max_window && next_ < limit_) {
    const auto row = job_.row(next_);
    send(FrameType::Row, next_, Bytes(row.begin(), row.end()));
    ++progress_.rows_sent;
    ++next_;
  }
  (void)now_s;
}

void HostSession::on_frame(const Frame& frame, double now_s) {
  if (finished()) return;
  if (job_id_ != 0 && frame.job_id == job_id_ &&
      (frame.type == FrameType::Ack || frame.type == FrameType::Status)) {
    device_has_job_ = true;
  }
  if (frame.type == FrameType::Ack) {
    AckMessage ack;
    if (!decode(frame.payload, ack)) return;
    last_heard_s_ = now_s;
    if (job_id_ == 0 || frame.job_id != job_id_) return;
    if (phase_ != Phase::Transfer) return;
    apply_counters(ack.state, ack.rows_received, ack.rows_knitted, ack.buffer_free, now_s);
    return;
  }
  if (frame.type == FrameType::Status) {
    StatusMessage status;
    if (!decode(frame.payload, status)) return;
    last_heard_s_ = now_s;
    on_status(frame, status, now_s);
  }
}

void HostSession::apply_counters(JobState state, std::uint32_t received, std::uint32_t knitted,
                                 std::uint32_t free, double now_s) {
  progress_.device_state = state;
  progress_.rows_knitted = std::max(progress_.rows_knitted, knitted);
  if (state != JobState::Receiving) {
    // Verified, refused or cancelled: STATUS polling tells which and why.
    progress_.rows_received = received;
    phase_ = Phase::Knitting;
    last_request_s_ = now_s - options_.poll_s - 1;
    return;
  }
  if (received > base_) {
    base_ = received;
    last_advance_s_ = now_s;
    rto_s_ = options_.rto_s;
    duplicate_acks_ = 0;
    if (next_ < base_) next_ = base_;
    if (recovering_ && base_ < recover_until_) {
      // The device filled one gap and still waits: the next row in line was
      // lost too. Resend it alone (NewReno's partial acknowledgement).
      resend_row(base_);
    } else {
      recovering_ = false;
    }
  } else if (received < base_) {
    // The device lost rows it had accepted (a power cycle): resend from its count.
    ++progress_.buffer_losses;
    base_ = next_ = received;
    last_advance_s_ = now_s;
    recovering_ = false;
  } else if (next_ > base_ && ++duplicate_acks_ >= 3 && !recovering_) {
    // Rows after a lost one keep getting the same count back: the device
    // holds them and waits for the missing row. Resend that row now rather
    // than wait for the timeout.
    resend_row(base_);
    recovering_ = true;
    recover_until_ = next_;
  }
  limit_ = received + free;
  progress_.rows_received = base_;
  if (base_ == job_.row_count()) {
    phase_ = Phase::Knitting;
    last_request_s_ = now_s - options_.poll_s - 1;
  }
  fill_window(now_s);
}

void HostSession::apply_state(const StatusMessage& status, double now_s) {
  progress_.device_state = status.state;
  progress_.alarm = status.alarm;
  progress_.rows_knitted = status.rows_knitted;
  progress_.rows_durable = status.rows_durable;
  if (job_unfinished(status.state) || status.state == JobState::Done) {
    progress_.job_accepted = true;
  }
  const std::string where = " after " + std::to_string(status.rows_knitted) + " of " +
                            std::to_string(status.rows_total) + " rows";
  switch (status.state) {
    case JobState::Receiving:
      if (status.rows_received < base_) ++progress_.buffer_losses;
      if (status.rows_received >= job_.row_count()) {
        // Every row is there and the device checks the job: wait for it.
        phase_ = Phase::Knitting;
        progress_.rows_received = status.rows_received;
        return;
      }
      phase_ = Phase::Transfer;
      base_ = next_ = status.rows_received;
      limit_ = status.rows_received + status.buffer_free;
      last_advance_s_ = now_s;
      rto_s_ = options_.rto_s;
      progress_.rows_received = base_;
      fill_window(now_s);
      return;
    case JobState::Knitting:
    case JobState::Paused:
    case JobState::Alarm:
      phase_ = Phase::Knitting;
      progress_.rows_received = status.rows_received;
      return;
    case JobState::Done:
      progress_.rows_received = status.rows_received;
      if (status.rows_knitted != status.rows_total) {
        fail("the device reports the job done" + where);
        return;
      }
      phase_ = Phase::Done;
      return;
    case JobState::Cancelled:
      fail("the job was cancelled at the device" + where);
      return;
    case JobState::Refused:
      fail("the device refused the job: " + status.reason);
      return;
    case JobState::Idle:
      fail("the device has no record of the job (was its store wiped?)");
      return;
  }
}

void HostSession::on_status(const Frame& frame, const StatusMessage& status, double now_s) {
  if (frame.seq != pending_seq_) {
    // An answer to an older request. Counters in it are still true.
    if (phase_ == Phase::Transfer && job_id_ != 0 && frame.job_id == job_id_ &&
        status.state == JobState::Receiving) {
      apply_counters(status.state, status.rows_received, status.rows_knitted, status.buffer_free,
                     now_s);
    }
    return;
  }
  pending_seq_ = 0;  // answered
  rto_s_ = options_.rto_s;
  if (status.version != kProtocolVersion) {
    fail("the device speaks protocol version " + std::to_string(status.version) +
         ", this host speaks " + std::to_string(kProtocolVersion));
    return;
  }
  if (phase_ == Phase::Handshake && job_id_ == 0) {
    const bool same_job = status.sha256 == job_.sha256 && status.name == job_.name;
    if (job_unfinished(status.state)) {
      if (options_.resume && same_job) {
        job_id_ = frame.job_id;
        apply_state(status, now_s);
        return;
      }
      fail("the device is busy with job '" + status.name + "' (" +
           std::string(to_string(status.state)) + ", " + std::to_string(status.rows_knitted) +
           " of " + std::to_string(status.rows_total) + " rows knitted)" +
           (same_job ? "; it is this job: add --resume to finish it"
                     : "; wait for it, or cancel it with `wearknit status --to URI --cancel`"));
      return;
    }
    if (options_.resume && same_job && status.state == JobState::Done) {
      job_id_ = frame.job_id;
      apply_state(status, now_s);
      message_ = "the device had already knitted this job; nothing was sent";
      return;
    }
    job_id_ = new_job_id_;
    phase_ = Phase::Manifest;
    send_request(FrameType::Manifest, encode(job_.manifest()), now_s);
    return;
  }
  if (frame.job_id == job_id_ && job_id_ != 0 && status.state == JobState::Receiving) {
    progress_.rows_durable = status.rows_durable;
  }
  if (phase_ == Phase::Transfer && frame.job_id == job_id_ && status.state == JobState::Receiving) {
    // A window probe's answer: rows may still be in flight, keep them.
    apply_counters(status.state, status.rows_received, status.rows_knitted, status.buffer_free,
                   now_s);
    return;
  }
  if (frame.job_id != job_id_) {
    if (!device_has_job_ && !job_unfinished(status.state)) {
      // The manifest was lost with the link before the device answered it:
      // the device never had this job, so it is announced again.
      phase_ = Phase::Manifest;
      send_request(FrameType::Manifest, encode(job_.manifest()), now_s);
    } else if (phase_ == Phase::Manifest && job_unfinished(status.state)) {
      fail("the device took another job ('" + status.name + "') before this one");
    } else if (phase_ == Phase::Manifest) {
      send_request(FrameType::Manifest, encode(job_.manifest()), now_s);
    } else {
      fail("the device now holds another job ('" + status.name +
           "'); this job's progress: " + std::to_string(progress_.rows_knitted) + " of " +
           std::to_string(job_.row_count()) + " rows knitted");
    }
    return;
  }
  apply_state(status, now_s);
}

}  // namespace devices
