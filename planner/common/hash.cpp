#include "planner/common/hash.hpp"

#include <charconv>

namespace planner {

std::uint64_t fingerprint(std::string_view bytes, std::uint64_t seed) {
  std::uint64_t h = mix64(seed ^ bytes.size());
  std::size_t i = 0;
  for (; i + 8 <= bytes.size(); i += 8) {
    std::uint64_t word = 0;
    for (int b = 0; b < 8; ++b)
      word |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[i + b])) << (8 * b);
    h = mix64(h ^ word);
  }
  std::uint64_t tail = 0;
  for (int b = 0; i < bytes.size(); ++i, ++b)
    tail |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[i])) << (8 * b);
  return mix64(h ^ tail ^ 0xFF);
}

std::string hex64(std::uint64_t value) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text(16, '0');
  for (int i = 15; i >= 0; --i, value >>= 4)
    text[static_cast<std::size_t>(i)] = kDigits[value & 15];
  return text;
}

bool parse_hex64(std::string_view text, std::uint64_t& value) {
  if (text.size() != 16) return false;
  const auto result = std::from_chars(text.data(), text.data() + text.size(), value, 16);
  return result.ec == std::errc() && result.ptr == text.data() + text.size();
}

}  // namespace planner
