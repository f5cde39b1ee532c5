// A job: the bytes of a DAT or knitout file cut into rows, the unit the job
// protocol sends, acknowledges and counts as knitted (docs/protocol.md §4).
//
// What a row is:
//  - DAT: row 0 is the 0x600-byte header and palette; row k >= 1 is the
//    run-length pairs of raster row k-1 (the machine knits the raster one
//    row at a time), as the DAT backend's reader finds them
//    (dat::scan_runs). A trailing zero-length pair (the encoder's 255-run
//    quirk) stays with the row it follows.
//  - knitout: row 0 is everything up to the first instruction (magic line,
//    headers, leading comments); then one row per carriage pass: a new row
//    starts at a knit, tuck, split or miss whose direction differs from the
//    direction of the pass so far. Other lines (xfer, rack, in, out, comments,
//    extensions) join the pass they sit in. A pass longer than kMaxRowBytes
//    is cut at a line boundary.
// Rows concatenated give the file back byte for byte.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "devices/hash.hpp"
#include "devices/protocol.hpp"
#include "devices/result.hpp"

namespace devices {

inline constexpr std::size_t kMaxRowBytes = 32768;

struct Job {
  std::string name;  // the file name without folders: what the device stores it as
  JobFormat format = JobFormat::Unknown;
  Bytes bytes;
  std::vector<std::size_t> row_offsets;  // row i = bytes[row_offsets[i], row_offsets[i+1])
  Sha256 sha256{};

  std::uint32_t row_count() const { return static_cast<std::uint32_t>(row_offsets.size()) - 1; }
  std::span<const std::uint8_t> row(std::uint32_t index) const;
  ManifestMessage manifest() const;
};

// The format from the name (.dat; .k/.knitout) or, failing that, from the
// content (";!knitout-" magic).
JobFormat detect_format(const std::string& name, std::span<const std::uint8_t> bytes);

// Row boundaries (offsets, first 0, last bytes.size()) or an InvalidArgument
// error saying why the bytes cannot be cut into rows.
Result<std::vector<std::size_t>> split_rows(JobFormat format, std::span<const std::uint8_t> bytes);

// Builds a job from bytes; fails when the format is unknown, the name is not a
// plain file name, or the rows cannot be cut.
Result<Job> make_job(std::string name, Bytes bytes);
// Reads a job file.
Result<Job> load_job(const std::filesystem::path& path);

// The longest job name, in bytes. The longest file a store derives from a
// name, `NAME.manifest.json.tmp-XXXXXX` (docs/protocol.md §7), is 25 bytes
// longer, and file systems hold names of at most 255 bytes.
inline constexpr std::size_t kMaxJobNameBytes = 200;

// Why a device may not store a job under `name` ("[J001] ..."), or an empty
// string when it may (docs/protocol.md §7): valid UTF-8 of 1..200 bytes; no
// folders, control characters or characters a FAT stick cannot hold; not
// hidden; not a name the store derives for its own files (`*.manifest.json`,
// `*.part`, `*.knitlog`, temporary files).
std::string job_name_problem(std::string_view name);
inline bool valid_job_name(std::string_view name) {
  return job_name_problem(name).empty();
}

// The name as text that is safe to print and to write into JSON: bytes that
// are not valid UTF-8 and control characters become `\xNN`; longer than 80
// bytes, the middle is left out.
std::string printable_name(std::string_view name);

// What a device runs on a received job before knitting a row: empty string =
// accepted, otherwise the reason for refusing it. The application supplies
// these (docs/devices.md): the knitout one parses with knitout::parse; the
// needle-bed VM and the DAT reader plug in here.
struct JobCheckers {
  std::function<std::string(const std::string& name, std::span<const std::uint8_t> bytes)> knitout;
  std::function<std::string(const std::string& name, std::span<const std::uint8_t> bytes)> dat;
};

// knitout syntax check with knitout::parse: the reason names the first error
// as `NAME:LINE:COL: error: [CODE] message`.
std::string check_knitout_syntax(const std::string& name, std::span<const std::uint8_t> bytes);

}  // namespace devices
