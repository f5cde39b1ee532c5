// The properties the device frame fuzzer checks on every input, shared with
// the replay test (frame_fuzz_replay_test.cpp). The input's first byte picks
// what the rest is: even, bytes off the wire; odd, a frame's header and
// payload, which get their CRC and SLIP framing here, so that the fuzzer
// reaches past the CRC check into the header and the messages. The bytes
// are fed to a SlipDecoder in two pieces (split where the first byte says);
// for every frame it yields, decode_frame never crashes or reads out of
// bounds; a frame it accepts encodes back to the same bytes (but for the
// reserved byte, which it ignores: docs/protocol.md §1); a payload the
// message decoder of the frame's type accepts is the encoding of the message
// it decoded; describe() names the frame. Returns "" or what went wrong.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "devices/framing.hpp"
#include "devices/hash.hpp"
#include "devices/job.hpp"
#include "devices/protocol.hpp"

namespace devices {

// "" when `payload` is not a Message or is the encoding of the one it
// decodes to.
template <typename Message>
std::string check_message(std::span<const std::uint8_t> payload, const char* name) {
  Message message;
  if (!decode(payload, message)) return "";
  const Bytes again = encode(message);
  if (!std::equal(again.begin(), again.end(), payload.begin(), payload.end())) {
    return std::string("a ") + name + " payload that is not the encoding of what it decodes to";
  }
  return "";
}

inline std::string check_frame(std::span<const std::uint8_t> bytes) {
  Frame frame;
  if (!decode_frame(bytes, frame)) return "";
  // The reserved byte (offset 3) is ignored on reading and written 0, which
  // changes the CRC: the bytes before the CRC are compared, and the frame
  // encoded again must be accepted.
  Bytes expected(bytes.begin(), bytes.end() - kCrcSize);
  expected[3] = 0;
  const Bytes again = encode_frame(frame);
  if (!std::equal(expected.begin(), expected.end(), again.begin(), again.end() - kCrcSize)) {
    return "a frame that does not encode back to its bytes";
  }
  Frame decoded_again;
  if (!decode_frame(again, decoded_again)) return "a frame whose encoding is not accepted";
  if (describe(frame).empty()) return "a frame without a description";
  switch (frame.type) {
    case FrameType::Hello:
      return check_message<HelloMessage>(frame.payload, "HELLO");
    case FrameType::Manifest: {
      // Whatever name a manifest carries, the name rule answers without
      // throwing, and the name as printed is plain printable ASCII.
      ManifestMessage manifest;
      if (decode(frame.payload, manifest)) {
        const std::string problem = job_name_problem(manifest.name);
        if (problem.empty() != valid_job_name(manifest.name)) {
          return "job_name_problem and valid_job_name disagree";
        }
        for (const char c : printable_name(manifest.name)) {
          if (c < 0x20 || c > 0x7e) return "a printable name with a byte that is not printable";
        }
      }
      return check_message<ManifestMessage>(frame.payload, "MANIFEST");
    }
    case FrameType::Command:
      return check_message<CommandMessage>(frame.payload, "COMMAND");
    case FrameType::Status: {
      // A device writes at most 1000 bytes of reason; a longer one is read
      // whole, and cut there when written again.
      StatusMessage status;
      if (decode(frame.payload, status) && status.reason.size() > 1000) {
        StatusMessage written;
        if (!decode(encode(status), written) || written.reason != status.reason.substr(0, 1000)) {
          return "a long STATUS reason that is not cut to 1000 bytes when written";
        }
        return "";
      }
      return check_message<StatusMessage>(frame.payload, "STATUS");
    }
    case FrameType::Ack:
      return check_message<AckMessage>(frame.payload, "ACK");
    case FrameType::Row:
    case FrameType::StatusRequest:
      return "";
  }
  return "decode_frame accepted a frame of no known type";
}

inline std::string check_frames(std::span<const std::uint8_t> data) {
  if (data.empty()) return "";
  const std::uint8_t mode = data[0];
  std::span<const std::uint8_t> rest = data.subspan(1);
  Bytes wire;
  if (mode % 2 == 1) {
    Bytes body(rest.begin(), rest.end());
    const std::uint32_t crc = crc32(body);
    for (int i = 0; i < 4; ++i) body.push_back(static_cast<std::uint8_t>(crc >> (8 * i)));
    wire = slip_encode(body);
    rest = wire;
  }
  const std::size_t split = std::min<std::size_t>(mode / 2, rest.size());
  SlipDecoder decoder;
  std::string problem;
  auto on_frame = [&](std::span<const std::uint8_t> frame) {
    if (problem.empty()) problem = check_frame(frame);
  };
  decoder.feed(rest.first(split), on_frame);
  decoder.feed(rest.subspan(split), on_frame);
  return problem;
}

}  // namespace devices
