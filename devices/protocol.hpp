// Messages of the job protocol (docs/protocol.md §3): the payloads carried by
// the frames of framing.hpp, with their encoders and decoders. Decoders return
// false on a payload of the wrong shape; such a frame is ignored like one
// that failed its CRC.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "devices/framing.hpp"
#include "devices/hash.hpp"

namespace devices {

// Capability bits a device announces in STATUS.
inline constexpr std::uint32_t kCapPause = 1u << 0;
inline constexpr std::uint32_t kCapCancel = 1u << 1;
inline constexpr std::uint32_t kCapAlarms = 1u << 2;
inline constexpr std::uint32_t kCapResume = 1u << 3;

enum class JobFormat : std::uint8_t { Unknown = 0, Dat = 1, Knitout = 2 };
std::string_view to_string(JobFormat format);

// The device's job state. Paused is a state of its own only while the job
// would otherwise be knitting; receiving continues while paused.
enum class JobState : std::uint8_t {
  Idle = 0,       // no job yet
  Receiving = 1,  // rows arriving; nothing knitted before the whole job is verified
  Knitting = 2,
  Paused = 3,
  Done = 4,  // every row knitted
  Cancelled = 5,
  Refused = 6,  // the job failed verification or the check; `reason` says why
  Alarm = 7,    // the machine stopped by itself (`alarm` says why); resume clears it
};
std::string_view to_string(JobState state);
bool job_unfinished(JobState state);

enum class Alarm : std::uint8_t { None = 0, YarnBreak = 1, Stop = 2 };
std::string_view to_string(Alarm alarm);

enum class Command : std::uint8_t { Pause = 1, Resume = 2, Cancel = 3 };
std::string_view to_string(Command command);

struct HelloMessage {
  std::uint8_t version_min = kProtocolVersion;
  std::uint8_t version_max = kProtocolVersion;
  std::uint32_t capabilities = 0;
};

struct ManifestMessage {
  JobFormat format = JobFormat::Unknown;
  std::uint64_t size = 0;
  std::uint32_t rows = 0;
  Sha256 sha256{};
  std::string name;
};

struct AckMessage {
  JobState state = JobState::Idle;
  std::uint32_t rows_received = 0;  // rows accepted, in order, from row 0
  std::uint32_t rows_knitted = 0;
  std::uint32_t buffer_free = 0;  // more rows the device takes now
};

struct StatusMessage {
  std::uint8_t version = kProtocolVersion;
  std::uint32_t capabilities = 0;
  std::uint32_t buffer_capacity = 0;
  std::uint32_t buffer_free = 0;
  std::uint32_t max_row_bytes = 0;
  JobState state = JobState::Idle;
  Alarm alarm = Alarm::None;
  JobFormat format = JobFormat::Unknown;
  std::uint32_t rows_total = 0;
  std::uint32_t rows_received = 0;
  std::uint32_t rows_knitted = 0;
  Sha256 sha256{};
  std::string name;
  std::string reason;  // why Refused (or other detail); empty otherwise
  // Rows stored in the device's spool, which a power cycle keeps; the rest
  // of rows_received is in its RAM buffer.
  std::uint32_t rows_durable = 0;
};

struct CommandMessage {
  Command command = Command::Pause;
};

Bytes encode(const HelloMessage& m);
Bytes encode(const ManifestMessage& m);
Bytes encode(const AckMessage& m);
Bytes encode(const StatusMessage& m);
Bytes encode(const CommandMessage& m);
bool decode(std::span<const std::uint8_t> payload, HelloMessage& m);
bool decode(std::span<const std::uint8_t> payload, ManifestMessage& m);
bool decode(std::span<const std::uint8_t> payload, AckMessage& m);
bool decode(std::span<const std::uint8_t> payload, StatusMessage& m);
bool decode(std::span<const std::uint8_t> payload, CommandMessage& m);

// One line naming the frame, for WEARKNIT_DEVICE_DEBUG traces.
std::string describe(const Frame& frame);

}  // namespace devices
