#include "devices/loopback.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <filesystem>
#include <thread>

#include "devices/device_engine.hpp"
#include "devices/framing.hpp"

namespace devices {
namespace {

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

class LoopbackTransport final : public Transport {
 public:
  LoopbackTransport(std::unique_ptr<DeviceEngine> engine, std::string store, int lock)
      : engine_(std::move(engine)), store_(std::move(store)), lock_(lock) {}
  ~LoopbackTransport() override { ::close(lock_); }
  LoopbackTransport(const LoopbackTransport&) = delete;
  LoopbackTransport& operator=(const LoopbackTransport&) = delete;

  Outcome write_all(std::span<const std::uint8_t> bytes, int) override {
    std::vector<Frame> replies;
    decoder_.feed(bytes, [&](std::span<const std::uint8_t> raw) {
      Frame frame;
      if (decode_frame(raw, frame)) engine_->handle(frame, seconds_now(), replies);
    });
    engine_->tick(seconds_now());
    for (const Frame& reply : replies) {
      const Bytes wire = encode_wire(reply);
      pending_.insert(pending_.end(), wire.begin(), wire.end());
    }
    return Ok{};
  }

  Result<std::size_t> read_some(std::span<std::uint8_t> buffer, int timeout_ms) override {
    if (pending_.empty()) {
      engine_->tick(seconds_now());
      std::this_thread::sleep_for(std::chrono::milliseconds(std::min(timeout_ms, 1)));
      return std::size_t{0};
    }
    const std::size_t n = std::min(buffer.size(), pending_.size());
    std::copy_n(pending_.begin(), n, buffer.begin());
    pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(n));
    return n;
  }

  std::string describe() const override { return "loopback:" + store_; }

 private:
  std::unique_ptr<DeviceEngine> engine_;
  std::string store_;
  int lock_;  // holds the store's lock while the machine is open
  SlipDecoder decoder_;
  Bytes pending_;
};

}  // namespace

Result<std::unique_ptr<Transport>> open_loopback(const std::string& store,
                                                 const JobCheckers& checkers) {
  // One machine serves one host at a time: a second process sending to the
  // same store waits until the first has closed it, as a job waits at a busy
  // machine. Without it both would spool into the same job files.
  std::error_code ec;
  std::filesystem::create_directories(store, ec);
  const std::string lock_path = (std::filesystem::path(store) / ".lock").string();
  const int lock = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  if (lock < 0) {
    return Error{ErrorClass::OsFailure, "cannot open the machine's lock " + lock_path, errno};
  }
  int locked;
  do {
    locked = ::flock(lock, LOCK_EX);
  } while (locked != 0 && errno == EINTR);
  if (locked != 0) {
    const int error = errno;
    ::close(lock);
    return Error{ErrorClass::OsFailure, "cannot lock the machine " + lock_path, error};
  }
  DeviceConfig config;
  config.store = store;
  config.checkers = checkers;
  auto engine = DeviceEngine::open(std::move(config));
  if (!engine) {
    ::close(lock);
    return engine.error();
  }
  return std::unique_ptr<Transport>(
      std::make_unique<LoopbackTransport>(std::move(engine.value()), store, lock));
}

}  // namespace devices
