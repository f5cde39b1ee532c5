#include "devices/protocol.hpp"

namespace devices {

std::string_view to_string(JobFormat format) {
  switch (format) {
    case JobFormat::Dat:
      return "dat";
    case JobFormat::Knitout:
      return "knitout";
    case JobFormat::Unknown:
      break;
  }
  return "unknown";
}

std::string_view to_string(JobState state) {
  switch (state) {
    case JobState::Idle:
      return "idle";
    case JobState::Receiving:
      return "receiving";
    case JobState::Knitting:
      return "knitting";
    case JobState::Paused:
      return "paused";
    case JobState::Done:
      return "done";
    case JobState::Cancelled:
      return "cancelled";
    case JobState::Refused:
      return "refused";
    case JobState::Alarm:
      return "alarm";
  }
  return "unknown";
}

bool job_unfinished(JobState state) {
  return state == JobState::Receiving || state == JobState::Knitting || state == JobState::Paused ||
         state == JobState::Alarm;
}

std::string_view to_string(Alarm alarm) {
  switch (alarm) {
    case Alarm::None:
      return "none";
    case Alarm::YarnBreak:
      return "yarn break";
    case Alarm::Stop:
      return "stop";
  }
  return "unknown";
}

std::string_view to_string(Command command) {
  switch (command) {
    case Command::Pause:
      return "pause";
    case Command::Resume:
      return "resume";
    case Command::Cancel:
      return "cancel";
  }
  return "unknown";
}

Bytes encode(const HelloMessage& m) {
  Writer w;
  w.u8(m.version_min);
  w.u8(m.version_max);
  w.u32(m.capabilities);
  return w.take();
}

bool decode(std::span<const std::uint8_t> payload, HelloMessage& m) {
  Reader r(payload);
  m.version_min = r.u8();
  m.version_max = r.u8();
  m.capabilities = r.u32();
  return !r.failed() && r.at_end();
}

Bytes encode(const ManifestMessage& m) {
  Writer w;
  w.u8(static_cast<std::uint8_t>(m.format));
  w.u64(m.size);
  w.u32(m.rows);
  w.raw(m.sha256);
  w.str(m.name);
  return w.take();
}

bool decode(std::span<const std::uint8_t> payload, ManifestMessage& m) {
  Reader r(payload);
  m.format = static_cast<JobFormat>(r.u8());
  m.size = r.u64();
  m.rows = r.u32();
  r.raw(m.sha256);
  m.name = r.str();
  return !r.failed() && r.at_end();
}

Bytes encode(const AckMessage& m) {
  Writer w;
  w.u8(static_cast<std::uint8_t>(m.state));
  w.u32(m.rows_received);
  w.u32(m.rows_knitted);
  w.u32(m.buffer_free);
  return w.take();
}

bool decode(std::span<const std::uint8_t> payload, AckMessage& m) {
  Reader r(payload);
  m.state = static_cast<JobState>(r.u8());
  m.rows_received = r.u32();
  m.rows_knitted = r.u32();
  m.buffer_free = r.u32();
  return !r.failed() && r.at_end() && static_cast<int>(m.state) <= 7;
}

Bytes encode(const StatusMessage& m) {
  Writer w;
  w.u8(m.version);
  w.u32(m.capabilities);
  w.u32(m.buffer_capacity);
  w.u32(m.buffer_free);
  w.u32(m.max_row_bytes);
  w.u8(static_cast<std::uint8_t>(m.state));
  w.u8(static_cast<std::uint8_t>(m.alarm));
  w.u8(static_cast<std::uint8_t>(m.format));
  w.u32(m.rows_total);
  w.u32(m.rows_received);
  w.u32(m.rows_knitted);
  w.raw(m.sha256);
  w.str(m.name);
  w.str(m.reason.size() > 1000 ? m.reason.substr(0, 1000) : m.reason);
  w.u32(m.rows_durable);
  return w.take();
}

bool decode(std::span<const std::uint8_t> payload, StatusMessage& m) {
  Reader r(payload);
  m.version = r.u8();
  m.capabilities = r.u32();
  m.buffer_capacity = r.u32();
  m.buffer_free = r.u32();
  m.max_row_bytes = r.u32();
  m.state = static_cast<JobState>(r.u8());
  m.alarm = static_cast<Alarm>(r.u8());
  m.format = static_cast<JobFormat>(r.u8());
  m.rows_total = r.u32();
  m.rows_received = r.u32();
  m.rows_knitted = r.u32();
  r.raw(m.sha256);
  m.name = r.str();
  m.reason = r.str();
  m.rows_durable = r.u32();
  return !r.failed() && r.at_end() && static_cast<int>(m.state) <= 7 &&
         static_cast<int>(m.alarm) <= 2;
}

Bytes encode(const CommandMessage& m) {
  return Bytes{static_cast<std::uint8_t>(m.command)};
}

bool decode(std::span<const std::uint8_t> payload, CommandMessage& m) {
  if (payload.size() != 1 || payload[0] < 1 || payload[0] > 3) return false;
  m.command = static_cast<Command>(payload[0]);
  return true;
}

std::string describe(const Frame& frame) {
  std::string name;
  switch (frame.type) {
    case FrameType::Hello:
      name = "HELLO";
      break;
    case FrameType::Manifest:
      name = "MANIFEST";
      break;
    case FrameType::Row:
      name = "ROW";
      break;
    case FrameType::StatusRequest:
      name = "STATUS?";
      break;
    case FrameType::Command:
      name = "COMMAND";
      break;
    case FrameType::Status:
      name = "STATUS";
      break;
    case FrameType::Ack:
      name = "ACK";
      break;
  }
  std::string text = name + " job=" + std::to_string(frame.job_id) +
                     " seq=" + std::to_string(frame.seq) +
                     " len=" + std::to_string(frame.payload.size());
  if (frame.type == FrameType::Ack) {
    AckMessage ack;
    if (decode(frame.payload, ack)) {
      text += " received=" + std::to_string(ack.rows_received) +
              " knitted=" + std::to_string(ack.rows_knitted) +
              " free=" + std::to_string(ack.buffer_free);
    }
  } else if (frame.type == FrameType::Status) {
    StatusMessage status;
    if (decode(frame.payload, status)) {
      text += " state=" + std::string(to_string(status.state)) +
              " received=" + std::to_string(status.rows_received) +
              " knitted=" + std::to_string(status.rows_knitted) + "/" +
              std::to_string(status.rows_total);
    }
  }
  return text;
}

}  // namespace devices
