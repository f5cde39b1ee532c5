// The streaming reader allocates nothing per instruction once its buffers
// have grown: counted by replacing the global allocator in this test binary.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <sstream>

#include "knitout/generate.hpp"
#include "knitout/parser.hpp"

namespace {
std::atomic<long> g_allocations{0};
}

void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
// These replace the global operators, so free() does match the malloc() in
// operator new above; GCC cannot see that and warns at -O1 and up.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
#pragma GCC diagnostic pop

namespace knitout {
namespace {

long allocations_to_read(const std::string& text) {
  std::istringstream in(text);
  DiagnosticSink sink;
  Reader reader(in, "sheet.k", sink);
  Instruction instruction;
  const long before = g_allocations.load();
  long count = 0;
  while (reader.next(instruction)) ++count;
  EXPECT_GT(count, 100);
  EXPECT_FALSE(sink.has_errors());
  return g_allocations.load() - before;
}

TEST(AllocationTest, ReaderAllocatesNothingPerInstruction) {
  const std::string small = sheet_text({20, 10, "3", SheetPattern::Seed});
  const std::string large = sheet_text({200, 200, "3", SheetPattern::Seed});
  const long small_allocations = allocations_to_read(small);
  const long large_allocations = allocations_to_read(large);
  // 100 times the instructions, the same handful of allocations.
  EXPECT_LE(large_allocations, small_allocations + 2);
  EXPECT_LT(large_allocations, 20);
}

}  // namespace
}  // namespace knitout
