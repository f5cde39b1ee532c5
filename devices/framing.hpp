// Framing of the job protocol (docs/protocol.md §1-2).
//
// A frame is `header | payload | CRC-32`, little-endian, wrapped in SLIP
// (RFC 1055: END 0xC0 around every frame, ESC 0xDB escapes). The header:
//
//   version u8 | type u8 | flags u8 | reserved u8 | job_id u32 | seq u32 | length u16
//
// `decode_frame` checks length and CRC before anything else reads the
// payload; a frame that fails is dropped whole and never acted upon.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace devices {

using Bytes = std::vector<std::uint8_t>;

inline constexpr std::uint8_t kProtocolVersion = 1;
inline constexpr std::size_t kHeaderSize = 14;
inline constexpr std::size_t kCrcSize = 4;
inline constexpr std::size_t kMaxPayload = 65535;

enum class FrameType : std::uint8_t {
  Hello = 0x01,     // host -> device: versions and capabilities
  Manifest = 0x02,  // host -> device: a new job
  Row = 0x03,       // host -> device: one row of the job (seq = row index)
  StatusRequest = 0x04,
  Command = 0x05,  // host -> device: pause / resume / cancel
  Status = 0x81,   // device -> host: the full state (answers every request)
  Ack = 0x82,      // device -> host: counters after a Row
};

struct Frame {
  FrameType type = FrameType::Status;
  std::uint8_t flags = 0;
  std::uint32_t job_id = 0;
  std::uint32_t seq = 0;
  Bytes payload;
};

// Header + payload + CRC (not yet SLIP-wrapped). The payload must fit u16.
Bytes encode_frame(const Frame& frame);
// SLIP-wrapped encode_frame, ready for the wire.
Bytes encode_wire(const Frame& frame);
// Parses one de-SLIPped frame; false when short, of another version, of a
// wrong length or a wrong CRC.
bool decode_frame(std::span<const std::uint8_t> bytes, Frame& out);

Bytes slip_encode(std::span<const std::uint8_t> bytes);

// Splits a byte stream into SLIP frames. Frames longer than the largest
// legal frame are discarded (the stream resynchronises at the next END).
class SlipDecoder {
 public:
  // Calls `on_frame(std::span<const uint8_t>)` for every complete frame.
  template <typename F>
  void feed(std::span<const std::uint8_t> bytes, F&& on_frame) {
    for (std::uint8_t b : bytes) {
      if (b == 0xC0) {
        if (!overflow_ && !current_.empty()) on_frame(std::span<const std::uint8_t>(current_));
        current_.clear();
        escaped_ = false;
        overflow_ = false;
      } else if (overflow_) {
        continue;
      } else if (escaped_) {
        current_.push_back(b == 0xDC ? 0xC0 : b == 0xDD ? 0xDB : b);
        escaped_ = false;
      } else if (b == 0xDB) {
        escaped_ = true;
      } else {
        current_.push_back(b);
      }
      if (current_.size() > kHeaderSize + kMaxPayload + kCrcSize) overflow_ = true;
    }
  }
  void reset() {
    current_.clear();
    escaped_ = false;
    overflow_ = false;
  }

 private:
  Bytes current_;
  bool escaped_ = false;
  bool overflow_ = false;
};

// Little-endian field writing and reading for payloads.
class Writer {
 public:
  void u8(std::uint8_t v) { bytes_.push_back(v); }
  void u16(std::uint16_t v);
  void u32(std::uint32_t v);
  void u64(std::uint64_t v);
  void raw(std::span<const std::uint8_t> v) { bytes_.insert(bytes_.end(), v.begin(), v.end()); }
  void str(std::string_view v);  // u16 length + bytes
  Bytes take() { return std::move(bytes_); }

 private:
  Bytes bytes_;
};

// Reads fields; any read past the end sets failed() and yields zeros.
class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  std::uint8_t u8();
  std::uint16_t u16();
  std::uint32_t u32();
  std::uint64_t u64();
  void raw(std::span<std::uint8_t> out);
  std::string str();
  bool failed() const { return failed_; }
  bool at_end() const { return offset_ == bytes_.size(); }

 private:
  bool take(std::size_t n);
  std::span<const std::uint8_t> bytes_;
  std::size_t offset_ = 0;
  bool failed_ = false;
};

}  // namespace devices
