#include "devices/mock_server.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <pty.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "devices/debug.hpp"

namespace devices {
namespace {

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Connection {
  int fd = -1;
  bool is_socket = false;
  SlipDecoder decoder;
};

bool write_fully(int fd, const Bytes& bytes, bool is_socket) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    pollfd p{fd, POLLOUT, 0};
    if (::poll(&p, 1, 1000) <= 0) return false;
    const ssize_t n = is_socket ? ::send(fd, bytes.data() + done, bytes.size() - done, MSG_NOSIGNAL)
                                : ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

void make_raw(int fd) {
  termios t{};
  if (::tcgetattr(fd, &t) == 0) {
    ::cfmakeraw(&t);
    ::tcsetattr(fd, TCSANOW, &t);
  }
}

}  // namespace

Outcome run_mock_server(MockServerOptions options) {
  auto opened = DeviceEngine::open(options.device);
  if (!opened) return opened.error();
  DeviceEngine& engine = *opened.value();
  FaultInjector faults(options.faults, options.seed);

  int listen_fd = -1;
  int pty_slave = -1;
  std::vector<Connection> connections;
  const DeviceUri& uri = options.listen;
  std::string listening;
  if (uri.kind == DeviceUri::Kind::Tcp) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE;
    addrinfo* found = nullptr;
    const int rc =
        ::getaddrinfo(uri.host.c_str(), std::to_string(uri.port).c_str(), &hints, &found);
    if (rc != 0) {
      return make_error(ErrorClass::InvalidArgument,
                        "cannot resolve " + uri.host + ": " + ::gai_strerror(rc));
    }
    listen_fd = ::socket(found->ai_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
    const int one = 1;
    ::setsockopt(listen_fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (listen_fd < 0 || ::bind(listen_fd, found->ai_addr, found->ai_addrlen) != 0 ||
        ::listen(listen_fd, 8) != 0) {
      const int saved = errno;
      ::freeaddrinfo(found);
      if (listen_fd >= 0) ::close(listen_fd);
      return os_error("cannot listen on " + uri.text, saved);
    }
    ::freeaddrinfo(found);
    sockaddr_storage bound{};
    socklen_t length = sizeof bound;
    ::getsockname(listen_fd, reinterpret_cast<sockaddr*>(&bound), &length);
    const std::uint16_t port =
        ntohs(bound.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port
                                          : reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
    const bool v6 = uri.host.find(':') != std::string::npos;
    listening = "tcp://" + (v6 ? "[" + uri.host + "]" : uri.host) + ":" + std::to_string(port);
  } else if (uri.kind == DeviceUri::Kind::Pty) {
    int master = -1;
    char name[256] = {};
    if (::openpty(&master, &pty_slave, name, nullptr, nullptr) != 0) {
      return os_error("cannot open a pseudo-terminal");
    }
    ::fcntl(master, F_SETFD, FD_CLOEXEC);
    ::fcntl(pty_slave, F_SETFD, FD_CLOEXEC);
    // The slave stays open here, so a host closing and reopening its end is
    // not a hang-up of the master.
    make_raw(pty_slave);
    make_raw(master);
    connections.push_back(Connection{master, false, {}});
    listening = std::string("serial:") + name;
  } else if (uri.kind == DeviceUri::Kind::Serial) {
    const int fd = ::open(uri.path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (fd < 0) return os_error("cannot open " + uri.path);
    make_raw(fd);
    connections.push_back(Connection{fd, false, {}});
    listening = uri.text;
  } else {
    return make_error(ErrorClass::Unsupported,
                      uri.text +
                          ": the mock device listens on tcp://HOST:PORT, pty: or "
                          "serial:PATH (a USB device is the machine's own side)");
  }
  if (options.on_listening) options.on_listening(listening);

  const auto hang_up = [&](std::size_t index) {
    Connection& c = connections[index];
    if (c.is_socket) {
      debug_line("mock: closing a connection");
      ::close(c.fd);
      c.fd = -1;
    } else {
      // A terminal cannot be unplugged from here: lose what is in flight.
      ::tcflush(c.fd, TCIOFLUSH);
      c.decoder.reset();
    }
  };

  std::vector<Frame> replies;
  double ended_at = -1;
  for (;;) {
    if (options.stop != nullptr && options.stop->load()) break;
    if (ended_at >= 0) {
      // Linger so the host's last STATUS request gets its answer: until the
      // hosts hang up (TCP) or a short grace period passes.
      const double since = seconds_now() - ended_at;
      const bool hosts_gone = listen_fd >= 0 && connections.empty();
      if ((hosts_gone && since > 0.2) || since > 2.0) break;
    }
    std::vector<pollfd> fds;
    if (listen_fd >= 0) fds.push_back(pollfd{listen_fd, POLLIN, 0});
    for (const Connection& c : connections) fds.push_back(pollfd{c.fd, POLLIN, 0});
    const int ready = ::poll(fds.data(), fds.size(), 5);
    if (ready < 0 && errno != EINTR) return os_error("poll");
    std::size_t first = 0;
    if (listen_fd >= 0) {
      first = 1;
      if (fds[0].revents & POLLIN) {
        const int fd = ::accept4(listen_fd, nullptr, nullptr, SOCK_CLOEXEC);
        if (fd >= 0) {
          const int one = 1;
          ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
          connections.push_back(Connection{fd, true, {}});
          debug_line("mock: accepted a connection");
        }
      }
    }
    for (std::size_t i = first; i < fds.size(); ++i) {
      if ((fds[i].revents & (POLLIN | POLLHUP | POLLERR)) == 0) continue;
      const std::size_t index = i - first;
      Connection& c = connections[index];
      std::uint8_t buffer[65536];
      const ssize_t n = ::read(c.fd, buffer, sizeof buffer);
      if (n <= 0) {
        if (c.is_socket) {
          ::close(c.fd);
          c.fd = -1;
        } else if (n < 0 && errno == EIO) {
          std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        continue;
      }
      // Replies to everything one read brought go out in one write.
      Bytes out;
      bool cut = false;
      std::vector<Bytes> frames;
      c.decoder.feed(
          std::span(buffer, static_cast<std::size_t>(n)),
          [&](std::span<const std::uint8_t> raw) { frames.emplace_back(raw.begin(), raw.end()); });
      for (Bytes& raw : frames) {
        replies.clear();
        for (const Bytes& copy : faults.pass(std::move(raw))) {
          Frame frame;
          if (!decode_frame(copy, frame)) {
            debug_line("mock: dropped a frame that failed its check");
            continue;
          }
          if (debug_enabled()) debug_line("mock <- " + describe(frame));
          engine.handle(frame, seconds_now(), replies);
        }
        for (const Frame& reply : replies) {
          if (debug_enabled()) debug_line("mock -> " + describe(reply));
          for (const Bytes& wire : faults.pass(encode_wire(reply))) {
            out.insert(out.end(), wire.begin(), wire.end());
          }
        }
        const FaultInjector::Event event = faults.after_received_frame();
        if (event == FaultInjector::Event::Reboot) {
          engine.reboot(seconds_now());
          cut = true;
          break;
        }
        if (event == FaultInjector::Event::Disconnect) {
          debug_line("mock: injected disconnect");
          cut = true;
          break;
        }
        if (const std::uint32_t stall = faults.stall_now(); stall != 0) {
          std::this_thread::sleep_for(std::chrono::milliseconds(stall));
        }
      }
      // A cut link loses what was still to be sent.
      if (cut || (!out.empty() && !write_fully(c.fd, out, c.is_socket))) hang_up(index);
    }
    std::erase_if(connections, [](const Connection& c) { return c.fd < 0; });
    engine.tick(seconds_now());
    const JobState state = engine.state();
    if (options.exit_when_job_ends && ended_at < 0 &&
        (state == JobState::Done || state == JobState::Refused || state == JobState::Cancelled)) {
      ended_at = seconds_now();
    }
  }
  for (Connection& c : connections) {
    if (c.fd >= 0) ::close(c.fd);
  }
  if (listen_fd >= 0) ::close(listen_fd);
  if (pty_slave >= 0) ::close(pty_slave);
  return Ok{};
}

}  // namespace devices
