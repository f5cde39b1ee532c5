// Hostile and unlucky clients against a real `wearknit mock-device` process
// on loopback TCP: raw manifests with names no store can hold, peers that do
// not speak the protocol, devices that lose their buffer on every frame.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "devices/framing.hpp"
#include "devices/protocol.hpp"
#include "devices/transport.hpp"
#include "tests/devices/background_wearknit.hpp"
#include "tests/devices/device_test_support.hpp"
#include "tests/test_support.hpp"

namespace devices {
namespace {

using wearknit::test::run_wearknit;

class HostileCliTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = wearknit::test::make_temp_dir("wk-hostile"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }
  std::filesystem::path dir_;
};

// Sends one frame on `link` and waits for the STATUS that answers `seq`.
std::optional<StatusMessage> ask(Transport& link, const Frame& frame) {
  if (!link.write_all(encode_wire(frame), 2000)) return std::nullopt;
  SlipDecoder decoder;
  std::vector<std::uint8_t> buffer(4096);
  std::optional<StatusMessage> answer;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!answer && std::chrono::steady_clock::now() < give_up) {
    auto n = link.read_some(buffer, 200);
    if (!n) return std::nullopt;
    decoder.feed(std::span<const std::uint8_t>(buffer.data(), n.value()),
                 [&](std::span<const std::uint8_t> raw) {
                   Frame reply;
                   StatusMessage s;
                   if (decode_frame(raw, reply) && reply.type == FrameType::Status &&
                       reply.seq == frame.seq && decode(reply.payload, s)) {
                     answer = s;
                   }
                 });
  }
  return answer;
}

TEST_F(HostileCliTest, RawManifestsWithNamesNoStoreCanHoldAreRefusedAndTheDeviceKeepsServing) {
  test::BackgroundWearknit mock("mock-device --listen tcp://127.0.0.1:0 --store " + path("D") +
                                " --no-sync --rows-per-s 0");
  ASSERT_FALSE(mock.uri().empty()) << mock.first_line();
  auto opened = open_transport(parse_uri(mock.uri()).value());
  ASSERT_TRUE(opened.ok()) << opened.error().text();
  Transport& link = *opened.value();
  const std::vector<std::string> names = {std::string(231, 'a'), std::string(255, 'b'),
                                          "\xff\xfe\xfd.k",      "X.k.manifest.json",
                                          "job-1.part",          ".hidden.k"};
  std::uint32_t seq = 1;
  for (const std::string& name : names) {
    ManifestMessage m = test::make_sheet_job("s.k", 2, 2).manifest();
    m.name = name;
    ++seq;
    const auto answer = ask(link, Frame{FrameType::Manifest, 0, 100 + seq, seq, encode(m)});
    ASSERT_TRUE(answer.has_value()) << "no answer to the manifest named " << printable_name(name);
    EXPECT_EQ(answer->state, JobState::Refused);
    EXPECT_EQ(answer->reason.rfind("[J001] ", 0), 0u) << answer->reason;
  }
  opened.value().reset();
  // Still serving: a real job goes through, and nothing but it was stored.
  wearknit::test::write_file(dir_ / "X.k", test::sheet_knitout(4, 6));
  const auto sent = run_wearknit("send -q " + path("X.k") + " --to " + mock.uri());
  EXPECT_EQ(sent.exit_code, 0) << sent.err;
  for (const auto& entry : std::filesystem::directory_iterator(dir_ / "D")) {
    const std::string file = entry.path().filename().string();
    EXPECT_TRUE(file == "X.k" || file == "X.k.manifest.json" || file == ".wearknit-device") << file;
  }
  mock.stop();
  EXPECT_EQ(mock.finish().find("[killed"), std::string::npos);
}

TEST_F(HostileCliTest, TheSenderRefusesNamesTheRuleRefusesBeforeConnecting) {
  for (const std::string& name : {std::string(240, 'n') + ".k", std::string("\xff\xfe.k")}) {
    wearknit::test::write_file(dir_ / name, test::sheet_knitout(2, 2));
    const auto sent = run_wearknit("send " + path(name) + " --to tcp://127.0.0.1:9");
    EXPECT_NE(sent.exit_code, 0);
    EXPECT_NE(sent.err.find("[J001] the job name '"), std::string::npos) << sent.err;
    EXPECT_EQ(sent.err.find("cannot connect"), std::string::npos) << sent.err;
  }
}

TEST_F(HostileCliTest, APeerThatIsNotAWearknitDeviceFailsFastWithoutAResumeHint) {
  // A one-shot HTTP server on loopback.
  const int server = ::socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(server, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(::bind(server, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  socklen_t length = sizeof address;
  ASSERT_EQ(::getsockname(server, reinterpret_cast<sockaddr*>(&address), &length), 0);
  ASSERT_EQ(::listen(server, 8), 0);
  std::thread http([server] {
    for (int i = 0; i < 2; ++i) {
      const int client = ::accept(server, nullptr, nullptr);
      if (client < 0) return;
      char request[256];
      (void)::recv(client, request, sizeof request, 0);
      const std::string reply = "HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n";
      (void)::send(client, reply.data(), reply.size(), MSG_NOSIGNAL);
      ::close(client);
    }
  });
  const std::string uri = "tcp://127.0.0.1:" + std::to_string(ntohs(address.sin_port));
  wearknit::test::write_file(dir_ / "a.k", test::sheet_knitout(4, 4));
  const auto start = std::chrono::steady_clock::now();
  const auto sent = run_wearknit("send " + path("a.k") + " --to " + uri);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto status = run_wearknit("status --to " + uri);
  ::shutdown(server, SHUT_RDWR);
  ::close(server);
  http.join();
  EXPECT_NE(sent.exit_code, 0);
  EXPECT_NE(sent.err.find("[J010] " + uri +
                          " is not a wearknit device: it answered like an HTTP server "
                          "(\"HTTP/1.1 400 Bad Request\")"),
            std::string::npos)
      << sent.err;
  EXPECT_EQ(sent.err.find("--resume"), std::string::npos) << sent.err;
  EXPECT_EQ(sent.err.find("retrying"), std::string::npos) << sent.err;  // no reconnects
  // One connection, no retries: far under the 3 s silence timeout.
  EXPECT_LT(seconds, 3.0);
  EXPECT_NE(status.err.find("[J010]"), std::string::npos) << status.err;
}

TEST_F(HostileCliTest, ADeviceThatRebootsEveryTwentyFramesStillFinishesTheJob) {
  wearknit::test::write_file(dir_ / "r.k", test::sheet_knitout(6, 80));
  test::BackgroundWearknit mock("mock-device --listen tcp://127.0.0.1:0 --store " + path("D") +
                                " --fault reboot-every=20 --exit-when-done --no-sync"
                                " --rows-per-s 0");
  ASSERT_FALSE(mock.uri().empty()) << mock.first_line();
  const auto sent = run_wearknit("send -q " + path("r.k") + " --to " + mock.uri());
  EXPECT_EQ(sent.exit_code, 0) << sent.err;
  const std::string log = mock.finish();
  EXPECT_NE(log.find("power cycle"), std::string::npos);
  EXPECT_NE(log.find("each exactly once"), std::string::npos) << log;
  EXPECT_EQ(test::read_text(dir_ / "D" / "r.k"), test::read_text(dir_ / "r.k"));
}

TEST_F(HostileCliTest, ADeviceThatRebootsOnEveryFrameIsGivenUpWithinTheAttempts) {
  wearknit::test::write_file(dir_ / "r.k", test::sheet_knitout(6, 20));
  test::BackgroundWearknit mock("mock-device --listen tcp://127.0.0.1:0 --store " + path("D") +
                                " --fault reboot-every=1 --no-sync --rows-per-s 0");
  ASSERT_FALSE(mock.uri().empty()) << mock.first_line();
  const auto sent = run_wearknit("send -q " + path("r.k") + " --attempts 3 --to " + mock.uri());
  EXPECT_NE(sent.exit_code, 0);
  EXPECT_NE(sent.err.find("gave up on " + mock.uri() +
                          " after 3 attempts in a row that moved the job no further"),
            std::string::npos)
      << sent.err;
  EXPECT_EQ(sent.err.find("attempt 4 of"), std::string::npos) << sent.err;
  // The mock never finishes a job that way: stop it.
  mock.stop();
  EXPECT_EQ(mock.finish().find("[killed"), std::string::npos);
}

TEST_F(HostileCliTest, ADatBombIsRefusedByItsDeclaredSizeEverywhere) {
  const Bytes bomb = test::make_dat_bomb();
  wearknit::test::write_file(dir_ / "bomb.dat", std::string(bomb.begin(), bomb.end()));
  const auto info = run_wearknit("dat-info " + path("bomb.dat"));
  EXPECT_EQ(info.exit_code, 1);
  EXPECT_NE(info.err.find("[D047] DAT raster too large: the header declares 65536 x 65536"),
            std::string::npos)
      << info.err;
  const auto png = run_wearknit("dat-info " + path("bomb.dat") + " --png " + path("b.png"));
  EXPECT_EQ(png.exit_code, 2);
  EXPECT_NE(png.err.find("picture is too large"), std::string::npos) << png.err;
  EXPECT_FALSE(std::filesystem::exists(dir_ / "b.png"));
  const auto sent = run_wearknit("send " + path("bomb.dat") + " --to loopback:" + path("L"));
  EXPECT_NE(sent.exit_code, 0);
  EXPECT_NE(sent.err.find("[D047]"), std::string::npos) << sent.err;
}

}  // namespace
}  // namespace devices
