#include "devices/folder_drop.hpp"

#include <nlohmann/json.hpp>

#include "devices/file_view.hpp"
#include "knitout/output_file.hpp"

namespace devices {

std::string manifest_json(const Job& job) {
  nlohmann::json m;
  m["name"] = job.name;
  m["format"] = std::string(to_string(job.format));
  m["size"] = job.bytes.size();
  m["rows"] = job.row_count();
  m["sha256"] = to_hex(job.sha256);
  return m.dump(2) + "\n";
}

Outcome deliver_to_folder(const Job& job, const std::filesystem::path& folder) {
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) {
    return make_error(ErrorClass::InvalidArgument,
                      "dir:" + folder.string() + ": no such folder (is the stick mounted?)");
  }
  const std::filesystem::path target = folder / job.name;
  std::string failure = knitout::write_file_atomically(target.string(), [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(job.bytes.data()),
              static_cast<std::streamsize>(job.bytes.size()));
  });
  if (!failure.empty()) return make_error(ErrorClass::OsFailure, failure);
  // A job file is never left without its manifest: the machine would take
  // it for a job still being copied.
  auto withdraw = [&](Outcome failed) {
    std::filesystem::remove(target, ec);
    return failed;
  };
  // Read back through the file system: a stick that lies about writes is
  // caught here rather than at the machine.
  const Result<Bytes> read = read_file(target);
  if (!read) return withdraw(read.error());
  const Bytes& back = read.value();
  if (back.size() != job.bytes.size() || sha256(back) != job.sha256) {
    return withdraw(make_error(ErrorClass::Protocol,
                               target.string() + ": read back " + std::to_string(back.size()) +
                                   " bytes with SHA-256 " + to_hex(sha256(back)) + ", wrote " +
                                   std::to_string(job.bytes.size()) + " bytes with " +
                                   to_hex(job.sha256)));
  }
  failure = knitout::write_file_atomically((folder / (job.name + ".manifest.json")).string(),
                                           [&](std::ostream& out) { out << manifest_json(job); });
  if (!failure.empty()) return withdraw(make_error(ErrorClass::OsFailure, failure));
  return Ok{};
}

}  // namespace devices
