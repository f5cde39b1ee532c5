// libFuzzer target for the job protocol's framing and messages (devices/:
// SlipDecoder, decode_frame, the message decoders):
//   scripts/fuzz.sh SECONDS device_frame_fuzz   builds it with clang and runs it.
// Aborts when check_frames finds a broken property; the sanitizers catch
// memory errors and undefined behaviour.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>

#include "tests/devices/frame_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = devices::check_frames(std::span<const std::uint8_t>(data, size));
  if (!problem.empty()) {
    std::fprintf(stderr, "frame property broken: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
