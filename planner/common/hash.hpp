// Seeds and fingerprints: every random choice of the planner derives from
// the user's seed through SplitMix64, so a run is repeatable on any machine;
// fingerprints tell whether two inputs are the same bytes.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

namespace planner {

// The SplitMix64 finaliser (Steele, Lea, Flood 2014): a bijection of 64-bit
// words that mixes every input bit into every output bit.
constexpr std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

// A 64-bit fingerprint of bytes (mix64 over 8-byte words), for keys and for
// telling whether a record was made from the same inputs; not a
// cryptographic digest.
std::uint64_t fingerprint(std::string_view bytes, std::uint64_t seed = 0);

// A fingerprint as 16 lower-case hex digits, and back (nothing for text that
// is not 16 hex digits).
std::string hex64(std::uint64_t value);
bool parse_hex64(std::string_view text, std::uint64_t& value);

}  // namespace planner
