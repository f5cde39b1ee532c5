#include "devices/sender.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstring>
#include <random>
#include <thread>

#include "devices/debug.hpp"
#include "devices/loopback.hpp"

namespace devices {
namespace {

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void sleep_s(double s) {
  std::this_thread::sleep_for(std::chrono::duration<double>(s));
}

Result<std::unique_ptr<Transport>> open_stream(const DeviceUri& uri, const LinkOptions& link) {
  if (link.open) return link.open();
  if (uri.kind == DeviceUri::Kind::Loopback) return open_loopback(uri.path, link.loopback_checkers);
  return open_transport(uri);
}

// Tells a peer that speaks another protocol from a wearknit device on the
// first bytes it sends before any valid frame: text protocols greet or
// answer with a recognisable line, and none of them frames with SLIP.
class PeerCheck {
 public:
  void reset() {
    first_.clear();
    framed_ = false;
  }
  void frame_seen() { framed_ = true; }
  // Bytes as they arrive; returns what the peer looks like ("an HTTP
  // server"), or an empty string while it may still be a device.
  std::string feed(std::span<const std::uint8_t> bytes) {
    if (framed_ || first_.size() >= kKeep) return {};
    first_.insert(
        first_.end(), bytes.begin(),
        bytes.begin() + static_cast<std::ptrdiff_t>(std::min(bytes.size(), kKeep - first_.size())));
    const std::string text(first_.begin(), first_.end());
    const auto starts = [&](std::string_view prefix) { return text.rfind(prefix, 0) == 0; };
    if (first_.empty() || first_[0] == 0xC0) return {};
    if (starts("HTTP/")) return "an HTTP server";
    if (starts("SSH-")) return "an SSH server";
    if (starts("220 ") || starts("220-")) return "an FTP or mail server";
    if (starts("+OK") || starts("-ERR")) return "a POP3 or Redis server";
    if (starts("* OK")) return "an IMAP server";
    if (starts("RFB ")) return "a VNC server";
    if (first_.size() >= 2 && first_[0] == 0x16 && first_[1] == 0x03) return "a TLS server";
    if (first_.size() >= 2 && first_[0] == 0x15 && first_[1] == 0x03) return "a TLS server";
    // Any other text with no frame delimiter in its first 64 bytes.
    if (first_.size() >= 64) {
      const bool printable = std::all_of(first_.begin(), first_.end(), [](std::uint8_t c) {
        return c == '\r' || c == '\n' || c == '\t' || (c >= 0x20 && c < 0x7F);
      });
      if (printable) return "a text protocol";
    }
    return {};
  }
  // The first line the peer sent, shortened, for the message.
  std::string first_line() const {
    std::string line;
    for (std::uint8_t c : first_) {
      if (c == '\r' || c == '\n' || line.size() >= 60) break;
      line.push_back(c >= 0x20 && c < 0x7F ? static_cast<char>(c) : '?');
    }
    return line;
  }

 private:
  static constexpr std::size_t kKeep = 64;
  std::vector<std::uint8_t> first_;
  bool framed_ = false;
};

Error foreign_peer(const DeviceUri& uri, const std::string& kind, const PeerCheck& check) {
  return make_error(ErrorClass::Protocol, "[J010] " + uri.text +
                                              " is not a wearknit device: it answered like " +
                                              kind + " (\"" + check.first_line() + "\")");
}

// The path quoted for a shell when it holds anything but plain characters.
std::string shell_word(const std::string& text) {
  const bool plain = !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("/._-+:@%,=", c) != nullptr;
  });
  if (plain) return text;
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

Outcome write_frames(Transport& transport, std::vector<Frame> frames, int timeout_ms) {
  if (frames.empty()) return Ok{};
  Bytes wire;
  for (const Frame& f : frames) {
    if (debug_enabled()) debug_line("host -> " + describe(f));
    const Bytes w = encode_wire(f);
    wire.insert(wire.end(), w.begin(), w.end());
  }
  return transport.write_all(wire, timeout_ms);
}

// One request/response exchange on a fresh connection: repeats `request`
// until a STATUS answers it; `accept` decides whether that answer is final.
Result<DeviceStatus> exchange(
    const DeviceUri& uri, const LinkOptions& link,
    const std::function<Frame(std::uint32_t seq, const DeviceStatus* last)>& request,
    const std::function<bool(const DeviceStatus&)>& accept) {
  auto transport = open_stream(uri, link);
  if (!transport) return transport.error();
  SlipDecoder decoder;
  PeerCheck peer;
  std::uint8_t buffer[4096];
  std::uint32_t seq = 0;
  DeviceStatus last;
  bool have_last = false;
  for (int attempt = 0; attempt < 10; ++attempt) {
    Frame f = request(++seq, have_last ? &last : nullptr);
    f.seq = seq;
    if (Outcome w = write_frames(*transport.value(), {f}, link.write_timeout_ms); !w) {
      return w.error();
    }
    const double deadline = seconds_now() + 0.3;
    bool answered = false;
    while (!answered && seconds_now() < deadline) {
      auto n = transport.value()->read_some(buffer, 50);
      if (!n) return n.error();
      if (const std::string kind = peer.feed(std::span(buffer, n.value())); !kind.empty()) {
        return foreign_peer(uri, kind, peer);
      }
      decoder.feed(std::span(buffer, n.value()), [&](std::span<const std::uint8_t> raw) {
        Frame reply;
        StatusMessage status;
        if (decode_frame(raw, reply)) peer.frame_seen();
        if (decode_frame(raw, reply) && reply.type == FrameType::Status && reply.seq == seq &&
            decode(reply.payload, status)) {
          last = DeviceStatus{reply.job_id, status};
          have_last = true;
          answered = true;
        }
      });
    }
    if (answered && accept(last)) return last;
  }
  return make_error(ErrorClass::Timeout, uri.text + ": the device did not answer");
}

}  // namespace

Result<SendReport> send_job(const DeviceUri& uri, const Job& job, const SendOptions& options,
                            const LinkOptions& link, const ProgressCallback& on_progress) {
  std::uint32_t job_id = link.job_id;
  if (job_id == 0) {
    std::random_device random;
    while (job_id == 0) job_id = random();
  }
  HostSession session(job, options, job_id);
  const double start = seconds_now();
  int failed_attempts = 0;
  int connections = 0;
  std::string last_problem;
  SlipDecoder decoder;
  PeerCheck peer;
  std::vector<std::uint8_t> buffer(65536);
  const auto note = [&](const std::string& text) {
    if (on_progress) on_progress(session.progress(), text);
  };
  // What lasts: rows in the device's store, rows knitted, the job accepted
  // and verified. An attempt that moved none of them is a failed attempt.
  std::uint32_t best_durable = 0;
  std::uint32_t best_knitted = 0;
  bool accepted = false;
  bool verified = false;
  const auto lasting_progress = [&](const Progress& p) {
    const bool now_verified = p.phase == Phase::Knitting && p.device_state != JobState::Receiving;
    const bool moved = p.rows_durable > best_durable || p.rows_knitted > best_knitted ||
                       (p.job_accepted && !accepted) || (now_verified && !verified);
    best_durable = std::max(best_durable, p.rows_durable);
    best_knitted = std::max(best_knitted, p.rows_knitted);
    accepted = accepted || p.job_accepted;
    verified = verified || now_verified;
    return moved;
  };
  for (;;) {
    auto opened = open_stream(uri, link);
    if (!opened) {
      last_problem = opened.error().text();
      if (opened.error().error_class == ErrorClass::InvalidArgument ||
          opened.error().error_class == ErrorClass::Unsupported) {
        return opened.error();  // retrying cannot help
      }
    } else {
      Transport& transport = *opened.value();
      if (connections++ > 0) note("reconnected to " + uri.text);
      decoder.reset();
      peer.reset();
      session.on_connect(seconds_now());
      for (;;) {
        if (Outcome w = write_frames(transport, session.take_outbox(), link.write_timeout_ms); !w) {
          last_problem = w.error().text();
          break;
        }
        if (session.finished()) {
          SendReport report;
          report.done = session.phase() == Phase::Done;
          report.message = session.message();
          report.progress = session.progress();
          report.reconnects = connections - 1;
          report.seconds = seconds_now() - start;
          return report;
        }
        const double wait = session.next_timer_s(seconds_now());
        const int timeout_ms = std::clamp(static_cast<int>(wait * 1000) + 1, 1, 50);
        auto n = transport.read_some(buffer, timeout_ms);
        if (!n) {
          last_problem = n.error().text();
          break;
        }
        const std::span<const std::uint8_t> got(buffer.data(), n.value());
        if (const std::string kind = peer.feed(got); !kind.empty()) {
          return foreign_peer(uri, kind, peer);
        }
        decoder.feed(got, [&](std::span<const std::uint8_t> raw) {
          Frame frame;
          if (!decode_frame(raw, frame)) {
            debug_line("host: dropped a frame that failed its check");
            return;
          }
          peer.frame_seen();
          if (debug_enabled()) debug_line("host <- " + describe(frame));
          session.on_frame(frame, seconds_now());
        });
        session.poll(seconds_now());
        const Progress now = session.progress();
        if (lasting_progress(now)) failed_attempts = 0;
        if (on_progress) on_progress(now, "");
        if (session.wants_reconnect()) {
          last_problem = "no answer from the device for " +
                         std::to_string(static_cast<int>(options.silence_s)) + " s";
          break;
        }
      }
    }
    if (++failed_attempts > link.max_attempts) {
      const Progress p = session.progress();
      std::string message =
          "gave up on " + uri.text + " after " + std::to_string(link.max_attempts) +
          " attempts in a row that moved the job no further (" + last_problem + "); ";
      if (!accepted) {
        message += connections == 0 ? "nothing of the job reached the device"
                                    : "the device never acknowledged the job (send it again; "
                                      "if the device says it holds it, add --resume)";
        return make_error(ErrorClass::Disconnected, message);
      }
      message += std::to_string(best_durable) + " of " + std::to_string(p.rows_total) +
                 " rows are stored on the device and " + std::to_string(best_knitted) + " knitted";
      if (p.buffer_losses > 0) {
        message += "; the device lost the rows it had buffered " + std::to_string(p.buffer_losses) +
                   " times (is it restarting?)";
      }
      message += ". The device keeps its counters: run `wearknit send " +
                 shell_word(link.job_path.empty() ? job.name : link.job_path) + " --to " +
                 shell_word(uri.text) + " --resume` to finish the job";
      return make_error(ErrorClass::Disconnected, message);
    }
    const double backoff = std::min(link.first_backoff_s * (1 << std::min(failed_attempts - 1, 10)),
                                    link.max_backoff_s);
    note("connection lost (" + last_problem + "); retrying in " +
         std::to_string(static_cast<int>(backoff * 1000)) + " ms (attempt " +
         std::to_string(failed_attempts) + " of " + std::to_string(link.max_attempts) + ")");
    sleep_s(backoff);
  }
}

Result<DeviceStatus> query_status(const DeviceUri& uri, const LinkOptions& link) {
  return exchange(
      uri, link,
      [](std::uint32_t, const DeviceStatus*) {
        return Frame{FrameType::Hello, 0, 0, 0, encode(HelloMessage{})};
      },
      [](const DeviceStatus&) { return true; });
}

Result<DeviceStatus> send_command(const DeviceUri& uri, Command command, const LinkOptions& link) {
  auto first = query_status(uri, link);
  if (!first) return first.error();
  const DeviceStatus& current = first.value();
  if (!job_unfinished(current.status.state)) {
    return make_error(ErrorClass::Protocol,
                      uri.text + ": no unfinished job to " + std::string(to_string(command)) +
                          " (the device is " + std::string(to_string(current.status.state)) + ")");
  }
  const std::uint32_t job_id = current.job_id;
  return exchange(
      uri, link,
      [&](std::uint32_t, const DeviceStatus*) {
        return Frame{FrameType::Command, 0, job_id, 0, encode(CommandMessage{command})};
      },
      [&](const DeviceStatus& s) {
        if (s.job_id != job_id) return true;  // someone else's job now: report it
        switch (command) {
          case Command::Pause:
            return s.status.state == JobState::Paused || (s.status.state == JobState::Receiving) ||
                   !job_unfinished(s.status.state);
          case Command::Resume:
            return s.status.state != JobState::Paused && s.status.state != JobState::Alarm;
          case Command::Cancel:
            return s.status.state == JobState::Cancelled || !job_unfinished(s.status.state);
        }
        return true;
      });
}

}  // namespace devices
