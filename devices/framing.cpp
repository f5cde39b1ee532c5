#include "devices/framing.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "devices/hash.hpp"

namespace devices {

void Writer::u16(std::uint16_t v) {
  u8(static_cast<std::uint8_t>(v));
  u8(static_cast<std::uint8_t>(v >> 8));
}
void Writer::u32(std::uint32_t v) {
  u16(static_cast<std::uint16_t>(v));
  u16(static_cast<std::uint16_t>(v >> 16));
}
void Writer::u64(std::uint64_t v) {
  u32(static_cast<std::uint32_t>(v));
  u32(static_cast<std::uint32_t>(v >> 32));
}
void Writer::str(std::string_view v) {
  if (v.size() > 0xFFFF) throw std::logic_error("devices::Writer::str: string longer than 65535");
  u16(static_cast<std::uint16_t>(v.size()));
  bytes_.insert(bytes_.end(), v.begin(), v.end());
}

bool Reader::take(std::size_t n) {
  if (failed_ || bytes_.size() - offset_ < n) {
    failed_ = true;
    return false;
  }
  return true;
}
std::uint8_t Reader::u8() {
  if (!take(1)) return 0;
  return bytes_[offset_++];
}
std::uint16_t Reader::u16() {
  const std::uint16_t lo = u8();
  return static_cast<std::uint16_t>(lo | (u8() << 8));
}
std::uint32_t Reader::u32() {
  const std::uint32_t lo = u16();
  return lo | (static_cast<std::uint32_t>(u16()) << 16);
}
std::uint64_t Reader::u64() {
  const std::uint64_t lo = u32();
  return lo | (static_cast<std::uint64_t>(u32()) << 32);
}
void Reader::raw(std::span<std::uint8_t> out) {
  if (!take(out.size())) return;
  std::copy_n(bytes_.begin() + static_cast<std::ptrdiff_t>(offset_), out.size(), out.begin());
  offset_ += out.size();
}
std::string Reader::str() {
  const std::uint16_t n = u16();
  if (!take(n)) return {};
  std::string s(bytes_.begin() + static_cast<std::ptrdiff_t>(offset_),
                bytes_.begin() + static_cast<std::ptrdiff_t>(offset_ + n));
  offset_ += n;
  return s;
}

Bytes encode_frame(const Frame& frame) {
  if (frame.payload.size() > kMaxPayload) {
    throw std::logic_error("devices::encode_frame: payload of " +
                           std::to_string(frame.payload.size()) + " bytes exceeds 65535");
  }
  Writer w;
  w.u8(kProtocolVersion);
  w.u8(static_cast<std::uint8_t>(frame.type));
  w.u8(frame.flags);
  w.u8(0);
  w.u32(frame.job_id);
  w.u32(frame.seq);
  w.u16(static_cast<std::uint16_t>(frame.payload.size()));
  w.raw(frame.payload);
  Bytes bytes = w.take();
  const std::uint32_t crc = crc32(bytes);
  for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(crc >> (8 * i)));
  return bytes;
}

Bytes slip_encode(std::span<const std::uint8_t> bytes) {
  Bytes out;
  out.reserve(bytes.size() + bytes.size() / 32 + 2);
  out.push_back(0xC0);
  for (std::uint8_t b : bytes) {
    if (b == 0xC0) {
      out.push_back(0xDB);
      out.push_back(0xDC);
    } else if (b == 0xDB) {
      out.push_back(0xDB);
      out.push_back(0xDD);
    } else {
      out.push_back(b);
    }
  }
  out.push_back(0xC0);
  return out;
}

Bytes encode_wire(const Frame& frame) {
  return slip_encode(encode_frame(frame));
}

bool decode_frame(std::span<const std::uint8_t> bytes, Frame& out) {
  if (bytes.size() < kHeaderSize + kCrcSize) return false;
  const std::size_t body = bytes.size() - kCrcSize;
  std::uint32_t wire_crc = 0;
  for (int i = 0; i < 4; ++i) wire_crc |= static_cast<std::uint32_t>(bytes[body + i]) << (8 * i);
  if (crc32(bytes.first(body)) != wire_crc) return false;
  Reader r(bytes.first(body));
  if (r.u8() != kProtocolVersion) return false;
  const std::uint8_t type = r.u8();
  const std::uint8_t flags = r.u8();
  r.u8();
  const std::uint32_t job_id = r.u32();
  const std::uint32_t seq = r.u32();
  const std::uint16_t length = r.u16();
  if (r.failed() || kHeaderSize + length != body) return false;
  switch (static_cast<FrameType>(type)) {
    case FrameType::Hello:
    case FrameType::Manifest:
    case FrameType::Row:
    case FrameType::StatusRequest:
    case FrameType::Command:
    case FrameType::Status:
    case FrameType::Ack:
      break;
    default:
      return false;
  }
  out.type = static_cast<FrameType>(type);
  out.flags = flags;
  out.job_id = job_id;
  out.seq = seq;
  out.payload.assign(bytes.begin() + kHeaderSize,
                     bytes.begin() + static_cast<std::ptrdiff_t>(body));
  return true;
}

}  // namespace devices
