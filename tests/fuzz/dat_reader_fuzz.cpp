// libFuzzer target for the DAT reader (backends/dat: decode, read_layout):
//   scripts/fuzz.sh SECONDS dat_reader_fuzz   builds it with clang and runs it.
// Aborts when check_read finds a broken property; the sanitizers catch
// memory errors and undefined behaviour.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>

#include "tests/backends/dat_read_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem = dat::check_read(std::span<const std::uint8_t>(data, size));
  if (!problem.empty()) {
    std::fprintf(stderr, "DAT reader property broken: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
