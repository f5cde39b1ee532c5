// devices_throughput: what the job protocol costs against sending the raw
// file over the same link, fault-free and at 1% frame corruption.
//   devices_throughput JOB [REPEATS]
// For TCP on 127.0.0.1 and for a pseudo-terminal (libserialport on the host
// side: run with sp_pty_shim preloaded, as bench/devices_throughput.sh
// does) it times:
//   raw       the file's bytes written to a reader that acknowledges the
//             last byte (no framing, no checks, nothing stored);
//   protocol  `send_job` to the mock machine (knitting instantly, store
//             unsynced): the time until every row is acknowledged (transfer)
//             and until the device reports every row knitted (done: adds the
//             device's verification of the whole job);
//   corrupt   the same with corrupt=0.01 in both directions.
// It prints the median of REPEATS runs (default 3), bytes on the wire and
// the ratios to raw.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <pty.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <future>
#include <iostream>
#include <thread>

#include "devices/mock_server.hpp"
#include "devices/sender.hpp"
#include "devices/serial.hpp"

namespace {

using devices::Bytes;

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Counts the bytes a transport moves.
class CountingTransport final : public devices::Transport {
 public:
  CountingTransport(std::unique_ptr<devices::Transport> inner, std::uint64_t& out,
                    std::uint64_t& in)
      : inner_(std::move(inner)), out_(out), in_(in) {}
  devices::Outcome write_all(std::span<const std::uint8_t> bytes, int timeout_ms) override {
    out_ += bytes.size();
    return inner_->write_all(bytes, timeout_ms);
  }
  devices::Result<std::size_t> read_some(std::span<std::uint8_t> buffer, int timeout_ms) override {
    auto n = inner_->read_some(buffer, timeout_ms);
    if (n) in_ += n.value();
    return n;
  }
  std::string describe() const override { return inner_->describe(); }

 private:
  std::unique_ptr<devices::Transport> inner_;
  std::uint64_t& out_;
  std::uint64_t& in_;
};

struct Run {
  double seconds = 0;           // until done (protocol: every row knitted)
  double transfer_seconds = 0;  // until every row was acknowledged
  std::uint64_t wire_out = 0;
  std::uint64_t wire_in = 0;
};

// Reads `expected` bytes from fd and answers one byte.
void sink(int fd, std::size_t expected) {
  std::vector<std::uint8_t> buffer(1 << 16);
  std::size_t got = 0;
  while (got < expected) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 5000) <= 0) break;
    const ssize_t n = ::read(fd, buffer.data(), buffer.size());
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  const std::uint8_t ack = 1;
  if (::write(fd, &ack, 1) != 1) std::perror("sink write");
}

Run raw_run(const devices::Job& job, bool pty) {
  Run run;
  std::unique_ptr<devices::Transport> transport;
  std::thread reader;
  int master = -1;
  int slave = -1;
  int listen_fd = -1;
  if (pty) {
    char name[256];
    ::openpty(&master, &slave, name, nullptr, nullptr);
    termios t{};
    ::tcgetattr(master, &t);
    ::cfmakeraw(&t);
    ::tcsetattr(master, TCSANOW, &t);
    ::tcsetattr(slave, TCSANOW, &t);
    auto opened = devices::open_serial(devices::real_serial_api(), name, 115200);
    if (!opened) throw std::runtime_error(opened.error().text());
    transport = std::move(opened.value());
    reader = std::thread(sink, master, job.bytes.size());
  } else {
    listen_fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(listen_fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
    ::listen(listen_fd, 1);
    socklen_t length = sizeof address;
    ::getsockname(listen_fd, reinterpret_cast<sockaddr*>(&address), &length);
    reader = std::thread([&] {
      const int fd = ::accept(listen_fd, nullptr, nullptr);
      sink(fd, job.bytes.size());
      ::close(fd);
    });
    auto opened = devices::open_transport(
        devices::parse_uri("tcp://127.0.0.1:" + std::to_string(ntohs(address.sin_port))).value());
    if (!opened) throw std::runtime_error(opened.error().text());
    transport = std::move(opened.value());
  }
  const double start = now_s();
  for (std::size_t at = 0; at < job.bytes.size(); at += 1 << 16) {
    const std::size_t n = std::min<std::size_t>(1 << 16, job.bytes.size() - at);
    if (!transport->write_all(std::span(job.bytes.data() + at, n), 10000)) {
      throw std::runtime_error("raw write failed");
    }
  }
  std::uint8_t ack = 0;
  while (true) {
    auto n = transport->read_some(std::span(&ack, 1), 5000);
    if (!n || n.value() == 1) break;
  }
  run.seconds = now_s() - start;
  run.transfer_seconds = run.seconds;
  run.wire_out = job.bytes.size();
  run.wire_in = 1;
  reader.join();
  transport.reset();
  if (master >= 0) ::close(master);
  if (slave >= 0) ::close(slave);
  if (listen_fd >= 0) ::close(listen_fd);
  return run;
}

Run protocol_run(const devices::Job& job, bool pty, double corrupt,
                 const std::filesystem::path& store) {
  std::filesystem::remove_all(store);
  devices::MockServerOptions server;
  server.listen = devices::parse_uri(pty ? "pty:" : "tcp://127.0.0.1:0").value();
  server.device.store = store;
  server.device.rows_per_s = 0;
  server.device.sync = false;
  server.device.buffer_rows = 32;
  server.faults.corrupt = corrupt;
  server.seed = 3;
  std::atomic<bool> stop{false};
  std::promise<std::string> listening;
  auto uri = listening.get_future();
  server.stop = &stop;
  server.on_listening = [&](const std::string& where) { listening.set_value(where); };
  std::thread thread([&] { (void)devices::run_mock_server(server); });
  const devices::DeviceUri target = devices::parse_uri(uri.get()).value();
  Run run;
  devices::LinkOptions link;
  link.open = [&]() -> devices::Result<std::unique_ptr<devices::Transport>> {
    auto t = devices::open_transport(target);
    if (!t) return t.error();
    return std::unique_ptr<devices::Transport>(
        std::make_unique<CountingTransport>(std::move(t.value()), run.wire_out, run.wire_in));
  };
  devices::SendOptions options;
  const double start = now_s();
  auto report = devices::send_job(
      target, job, options, link, [&](const devices::Progress& p, const std::string&) {
        if (run.transfer_seconds == 0 && p.rows_received == p.rows_total) {
          run.transfer_seconds = now_s() - start;
        }
      });
  run.seconds = now_s() - start;
  stop = true;
  thread.join();
  if (!report || !report.value().done) throw std::runtime_error("send failed");
  return run;
}

Run median(std::vector<Run> runs) {
  std::sort(runs.begin(), runs.end(),
            [](const Run& a, const Run& b) { return a.transfer_seconds < b.transfer_seconds; });
  return runs[runs.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: devices_throughput JOB [REPEATS]\n";
    return 2;
  }
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
  auto job = devices::load_job(argv[1]);
  if (!job) {
    std::cerr << job.error().text() << '\n';
    return 2;
  }
  const auto store = std::filesystem::temp_directory_path() / "wearknit-bench-store";
  const double mb = job.value().bytes.size() / 1e6;
  std::printf("job %s: %.2f MB, %u rows\n", job.value().name.c_str(), mb, job.value().row_count());
  // What the device does once every row is in, timed alone: SHA-256 and
  // cutting the job into rows again (the mock runs no other check here).
  const double verify_start = now_s();
  (void)devices::sha256(job.value().bytes);
  (void)devices::split_rows(job.value().format, job.value().bytes);
  std::printf("device verification alone (SHA-256 + row split): %.3f s\n", now_s() - verify_start);
  std::printf("%-4s %-9s %10s %9s %8s %8s %13s %11s %9s\n", "link", "mode", "transfer s", "MB/s",
              "x raw", "done s", "wire out B", "wire in B", "overhead");
  for (const bool pty : {false, true}) {
    std::vector<Run> raw_runs, proto_runs, corrupt_runs;
    for (int i = 0; i < repeats; ++i) {
      raw_runs.push_back(raw_run(job.value(), pty));
      proto_runs.push_back(protocol_run(job.value(), pty, 0, store));
      corrupt_runs.push_back(protocol_run(job.value(), pty, 0.01, store));
    }
    const Run raw = median(raw_runs);
    for (const auto& [mode, run] :
         {std::pair{"raw", raw}, std::pair{"protocol", median(proto_runs)},
          std::pair{"corrupt1%", median(corrupt_runs)}}) {
      std::printf("%-4s %-9s %10.3f %9.1f %8.2f %8.3f %13llu %11llu %8.2f%%\n", pty ? "pty" : "tcp",
                  mode, run.transfer_seconds, mb / run.transfer_seconds,
                  run.transfer_seconds / raw.transfer_seconds, run.seconds,
                  static_cast<unsigned long long>(run.wire_out),
                  static_cast<unsigned long long>(run.wire_in),
                  100.0 * (double(run.wire_out + run.wire_in) / job.value().bytes.size() - 1));
    }
  }
  std::filesystem::remove_all(store);
  return 0;
}
