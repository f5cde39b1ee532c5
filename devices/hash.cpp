#include "devices/hash.hpp"

#include <openssl/evp.h>
#include <zlib.h>

#include <stdexcept>

namespace devices {

std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  uLong crc = ::crc32(0L, Z_NULL, 0);
  // zlib takes a uInt length; feed large spans in pieces.
  std::size_t offset = 0;
  while (offset < bytes.size()) {
    const std::size_t piece = std::min<std::size_t>(bytes.size() - offset, 1u << 30);
    crc = ::crc32(crc, bytes.data() + offset, static_cast<uInt>(piece));
    offset += piece;
  }
  return static_cast<std::uint32_t>(crc);
}

Sha256 sha256(std::span<const std::uint8_t> bytes) {
  Sha256 digest{};
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest.data(), &length, EVP_sha256(), nullptr) != 1 ||
      length != digest.size()) {
    throw std::logic_error("devices::sha256: libcrypto EVP_Digest failed");
  }
  return digest;
}

std::string to_hex(std::span<const std::uint8_t> bytes) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  out.reserve(bytes.size() * 2);
  for (std::uint8_t b : bytes) {
    out.push_back(digits[b >> 4]);
    out.push_back(digits[b & 15]);
  }
  return out;
}

}  // namespace devices
