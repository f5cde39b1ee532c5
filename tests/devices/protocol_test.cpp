#include "devices/protocol.hpp"

#include <gtest/gtest.h>

#include "devices/faults.hpp"
#include "devices/framing.hpp"
#include "devices/transport.hpp"

namespace devices {
namespace {

std::vector<Frame> decode_stream(const Bytes& wire) {
  std::vector<Frame> frames;
  SlipDecoder decoder;
  decoder.feed(wire, [&](std::span<const std::uint8_t> raw) {
    Frame f;
    if (decode_frame(raw, f)) frames.push_back(f);
  });
  return frames;
}

TEST(FramingTest, Crc32MatchesTheCatalogueCheckValue) {
  const std::string check = "123456789";
  EXPECT_EQ(crc32(std::span(reinterpret_cast<const std::uint8_t*>(check.data()), check.size())),
            0xCBF43926u);
}

TEST(FramingTest, Sha256MatchesTheKnownDigestOfAbc) {
  const std::string abc = "abc";
  EXPECT_EQ(to_hex(sha256(std::span(reinterpret_cast<const std::uint8_t*>(abc.data()), 3))),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(FramingTest, SlipEscapesEndAndEscBytes) {
  const Bytes raw{0x01, 0xC0, 0x02, 0xDB, 0x03};
  EXPECT_EQ(slip_encode(raw), (Bytes{0xC0, 0x01, 0xDB, 0xDC, 0x02, 0xDB, 0xDD, 0x03, 0xC0}));
}

TEST(FramingTest, RoundTripsFramesWithEveryByteValue) {
  Frame f{FrameType::Row, 0, 0xDEADBEEF, 77, {}};
  for (int i = 0; i < 256; ++i) f.payload.push_back(static_cast<std::uint8_t>(i));
  const Bytes wire = encode_wire(f);
  const auto frames = decode_stream(wire);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].type, FrameType::Row);
  EXPECT_EQ(frames[0].job_id, 0xDEADBEEFu);
  EXPECT_EQ(frames[0].seq, 77u);
  EXPECT_EQ(frames[0].payload, f.payload);
}

TEST(FramingTest, HeaderLayoutIsLittleEndianAsDocumented) {
  const Bytes bytes = encode_frame(Frame{FrameType::Ack, 0, 0x04030201, 0x08070605, {0xAA}});
  ASSERT_EQ(bytes.size(), kHeaderSize + 1 + kCrcSize);
  EXPECT_EQ(bytes[0], kProtocolVersion);
  EXPECT_EQ(bytes[1], 0x82);
  EXPECT_EQ(bytes[4], 0x01);
  EXPECT_EQ(bytes[7], 0x04);
  EXPECT_EQ(bytes[8], 0x05);
  EXPECT_EQ(bytes[12], 1);  // length low byte
  EXPECT_EQ(bytes[13], 0);
  EXPECT_EQ(bytes[14], 0xAA);
}

TEST(FramingTest, RejectsEverySingleBitFlip) {
  const Bytes good = encode_frame(Frame{FrameType::Manifest, 0, 9, 1, {1, 2, 3, 4, 5}});
  Frame out;
  ASSERT_TRUE(decode_frame(good, out));
  for (std::size_t byte = 0; byte < good.size(); ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      Bytes bad = good;
      bad[byte] = static_cast<std::uint8_t>(bad[byte] ^ (1 << bit));
      EXPECT_FALSE(decode_frame(bad, out)) << "byte " << byte << " bit " << bit;
    }
  }
}

TEST(FramingTest, RejectsShortAndWrongLengthFrames) {
  Frame out;
  EXPECT_FALSE(decode_frame(Bytes{1, 2, 3}, out));
  Bytes bytes = encode_frame(Frame{FrameType::Hello, 0, 0, 1, {1, 2}});
  bytes.erase(bytes.begin() + kHeaderSize);  // payload one byte short of its length
  EXPECT_FALSE(decode_frame(bytes, out));
}

TEST(FramingTest, DecoderResynchronisesAfterGarbage) {
  Bytes wire{0x55, 0x66, 0xDB, 0x01};
  const Bytes frame = encode_wire(Frame{FrameType::StatusRequest, 0, 0, 5, {}});
  wire.insert(wire.end(), frame.begin(), frame.end());
  const auto frames = decode_stream(wire);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].seq, 5u);
}

TEST(ProtocolTest, StatusRoundTrips) {
  StatusMessage s;
  s.capabilities = kCapPause | kCapAlarms;
  s.buffer_capacity = 32;
  s.buffer_free = 7;
  s.state = JobState::Alarm;
  s.alarm = Alarm::YarnBreak;
  s.format = JobFormat::Dat;
  s.rows_total = 100;
  s.rows_received = 90;
  s.rows_knitted = 40;
  s.sha256[0] = 0xAB;
  s.name = "J.dat";
  s.reason = "why";
  StatusMessage back;
  ASSERT_TRUE(decode(encode(s), back));
  EXPECT_EQ(back.state, JobState::Alarm);
  EXPECT_EQ(back.alarm, Alarm::YarnBreak);
  EXPECT_EQ(back.rows_knitted, 40u);
  EXPECT_EQ(back.sha256[0], 0xAB);
  EXPECT_EQ(back.name, "J.dat");
  EXPECT_EQ(back.reason, "why");
}

TEST(ProtocolTest, RejectsTruncatedAndOverlongPayloads) {
  ManifestMessage m;
  m.name = "a.k";
  const Bytes bytes = encode(m);
  ManifestMessage back;
  EXPECT_TRUE(decode(bytes, back));
  Bytes longer = bytes;
  longer.push_back(0);
  EXPECT_FALSE(decode(longer, back));
  EXPECT_FALSE(decode(std::span(bytes).first(bytes.size() - 2), back));
  CommandMessage c;
  EXPECT_FALSE(decode(Bytes{9}, c));
}

TEST(FaultSpecTest, ParsesEveryKey) {
  auto spec = parse_fault_spec(
      "corrupt=0.01,drop=0.02,dup=0.03,disconnect-every=500,reboot-every=700,stall-ms=20,"
      "yarn-break-at=5,stop-at=9");
  ASSERT_TRUE(spec.ok());
  EXPECT_DOUBLE_EQ(spec.value().corrupt, 0.01);
  EXPECT_DOUBLE_EQ(spec.value().drop, 0.02);
  EXPECT_DOUBLE_EQ(spec.value().dup, 0.03);
  EXPECT_EQ(spec.value().disconnect_every, 500u);
  EXPECT_EQ(spec.value().reboot_every, 700u);
  EXPECT_EQ(spec.value().stall_ms, 20u);
  EXPECT_EQ(spec.value().yarn_break_at, 5u);
  EXPECT_EQ(spec.value().stop_at, 9u);
}

TEST(FaultSpecTest, RejectsUnknownKeysAndBadValues) {
  auto unknown = parse_fault_spec("corupt=0.1");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().message,
            "unknown fault 'corupt' (known: corrupt, drop, dup, disconnect-every, reboot-every, "
            "stall-ms, yarn-break-at, stop-at)");
  auto bad = parse_fault_spec("drop=1.5");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().message, "fault drop=1.5: the value must be a probability from 0 to 1");
  EXPECT_FALSE(parse_fault_spec("stall-ms=x").ok());
  EXPECT_FALSE(parse_fault_spec("drop").ok());
}

TEST(FaultInjectorTest, IsRepeatableForASeedAndHitsTheAskedRate) {
  FaultSpec spec;
  spec.drop = 0.25;
  FaultInjector a(spec, 7);
  FaultInjector b(spec, 7);
  int dropped = 0;
  for (int i = 0; i < 4000; ++i) {
    const auto x = a.pass(Bytes{1, 2, 3});
    EXPECT_EQ(x.size(), b.pass(Bytes{1, 2, 3}).size());
    dropped += x.empty();
  }
  EXPECT_NEAR(dropped / 4000.0, 0.25, 0.03);
}

TEST(UriTest, ParsesEveryKind) {
  auto tcp = parse_uri("tcp://127.0.0.1:9000");
  ASSERT_TRUE(tcp.ok());
  EXPECT_EQ(tcp.value().host, "127.0.0.1");
  EXPECT_EQ(tcp.value().port, 9000);
  auto serial = parse_uri("serial:/dev/ttyACM0?baud=57600");
  ASSERT_TRUE(serial.ok());
  EXPECT_EQ(serial.value().path, "/dev/ttyACM0");
  EXPECT_EQ(serial.value().baud, 57600);
  auto usb = parse_uri("usb://1209:4b4e/KNIT0001");
  ASSERT_TRUE(usb.ok());
  EXPECT_EQ(usb.value().vid, 0x1209);
  EXPECT_EQ(usb.value().pid, 0x4b4e);
  EXPECT_EQ(usb.value().serial_number, "KNIT0001");
  auto dir = parse_uri("dir:/media/stick");
  ASSERT_TRUE(dir.ok());
  EXPECT_EQ(dir.value().kind, DeviceUri::Kind::Dir);
  auto loop = parse_uri("loopback:");
  ASSERT_TRUE(loop.ok());
  EXPECT_EQ(loop.value().kind, DeviceUri::Kind::Loopback);
}

TEST(UriTest, RejectsMalformedUrisWithTheReason) {
  auto bad_port = parse_uri("tcp://localhost:99999");
  ASSERT_FALSE(bad_port.ok());
  EXPECT_EQ(bad_port.error().message,
            "device URI 'tcp://localhost:99999': the port must be a number from 0 to 65535");
  EXPECT_FALSE(parse_uri("usb://xyz:1").ok());
  EXPECT_FALSE(parse_uri("serial:/dev/x?speed=3").ok());
  auto unknown = parse_uri("ftp://x");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().error_class, ErrorClass::InvalidArgument);
}

}  // namespace
}  // namespace devices
