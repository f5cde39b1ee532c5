// libFuzzer target for the knitout parser and writer:
//   scripts/fuzz.sh [SECONDS]   builds it with clang and runs it.
// Aborts when check_parse_round_trip finds a broken property; the sanitizers
// catch memory errors and undefined behaviour.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "tests/knitout/parse_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem =
      knitout::check_parse_round_trip(std::string_view(reinterpret_cast<const char*>(data), size));
  if (!problem.empty()) {
    std::fprintf(stderr, "round-trip property broken: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
