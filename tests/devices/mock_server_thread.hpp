// Runs the mock device server on a thread for the duration of a test.
#pragma once

#include <atomic>
#include <future>
#include <thread>

#include "devices/mock_server.hpp"

namespace devices::test {

class MockServerThread {
 public:
  explicit MockServerThread(MockServerOptions options) {
    std::promise<std::string> listening;
    auto uri = listening.get_future();
    options.stop = &stop_;
    options.on_listening = [&listening](const std::string& where) { listening.set_value(where); };
    thread_ = std::thread([this, options = std::move(options)]() mutable {
      try {
        result_ = run_mock_server(std::move(options));
      } catch (const std::exception& e) {
        failure_ = e.what();
      }
    });
    if (uri.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
      throw std::runtime_error("mock server did not start listening");
    }
    uri_ = uri.get();
  }
  ~MockServerThread() { stop(); }
  void stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  const std::string& uri() const { return uri_; }
  const std::string& failure() const { return failure_; }

 private:
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::string uri_;
  Outcome result_ = Ok{};
  std::string failure_;
};

}  // namespace devices::test
