// Checksums of the job protocol: CRC-32 (zlib's, the IEEE 802.3 polynomial)
// on every frame, SHA-256 (OpenSSL's libcrypto) over every whole job.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

namespace devices {

using Sha256 = std::array<std::uint8_t, 32>;

std::uint32_t crc32(std::span<const std::uint8_t> bytes);
Sha256 sha256(std::span<const std::uint8_t> bytes);
std::string to_hex(std::span<const std::uint8_t> bytes);

}  // namespace devices
