// dir:PATH — a mounted USB stick or network folder, the way Shima Seiki and
// Kniterate machines take jobs. The job is written as PATH/NAME through a
// temporary name, fsync'ed, renamed, then read back and its SHA-256 compared
// with the sent bytes; NAME.manifest.json goes beside it. There are no rows
// on this route: the machine knits the file when the operator loads it.
#pragma once

#include <filesystem>

#include "devices/job.hpp"
#include "devices/result.hpp"

namespace devices {

// Ok once the file is in place and read back identical.
Outcome deliver_to_folder(const Job& job, const std::filesystem::path& folder);

// The manifest text every store writes beside a job (JSON).
std::string manifest_json(const Job& job);

}  // namespace devices
