#include "devices/loopback.hpp"

#include <chrono>
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
  LoopbackTransport(std::unique_ptr<DeviceEngine> engine, std::string store)
      : engine_(std::move(engine)), store_(std::move(store)) {}

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
  SlipDecoder decoder_;
  Bytes pending_;
};

}  // namespace

Result<std::unique_ptr<Transport>> open_loopback(const std::string& store,
                                                 const JobCheckers& checkers) {
  DeviceConfig config;
  config.store = store;
  config.checkers = checkers;
  auto engine = DeviceEngine::open(std::move(config));
  if (!engine) return engine.error();
  return std::unique_ptr<Transport>(
      std::make_unique<LoopbackTransport>(std::move(engine.value()), store));
}

}  // namespace devices
