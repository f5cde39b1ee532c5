// libFuzzer target for the mesh reader (planner/mesh: the scan, OpenMesh's
// readers, check_mesh):
//   scripts/fuzz.sh SECONDS mesh_reader_fuzz   builds it with clang and runs it.
// Aborts when check_read finds a broken property; the sanitizers catch
// memory errors and undefined behaviour, libFuzzer's -rss_limit_mb runaway
// allocations.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>

#include "tests/planner/mesh_read_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string problem =
      planner::mesh_fuzz::check_read(std::span<const std::uint8_t>(data, size));
  if (!problem.empty()) {
    std::fprintf(stderr, "mesh reader property broken: %s\n", problem.c_str());
    std::abort();
  }
  return 0;
}
