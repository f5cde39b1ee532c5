// Views of bytes that avoid copies of a whole job: a read-only memory map of
// a file, and an input stream over a span (for the readers that take an
// std::istream). A job of N bytes then costs N bytes, not a multiple.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <streambuf>
#include <vector>

#include "devices/result.hpp"

namespace devices {

class MappedFile {
 public:
  // Maps `path` read-only (an empty file maps to an empty span).
  static Result<MappedFile> open(const std::filesystem::path& path);
  MappedFile() = default;
  MappedFile(MappedFile&& other) noexcept;
  MappedFile& operator=(MappedFile&& other) noexcept;
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  ~MappedFile();

  std::span<const std::uint8_t> bytes() const {
    return {static_cast<const std::uint8_t*>(data_), size_};
  }

 private:
  void* data_ = nullptr;
  std::size_t size_ = 0;
};

// Reads a whole file into a buffer of its size, with no growth copies.
Result<std::vector<std::uint8_t>> read_file(const std::filesystem::path& path);

// An std::streambuf that reads a span in place.
class SpanStreambuf : public std::streambuf {
 public:
  explicit SpanStreambuf(std::span<const std::uint8_t> bytes) {
    // The get area is read-only: nothing here writes through it.
    char* begin = const_cast<char*>(reinterpret_cast<const char*>(bytes.data()));
    setg(begin, begin, begin + bytes.size());
  }
};

}  // namespace devices
