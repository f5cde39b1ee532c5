#include "devices/folder_drop.hpp"

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

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
  // Read back through the file system: a stick that lies about writes is
  // caught here rather than at the machine.
  std::ifstream in(target, std::ios::binary);
  const Bytes back((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.eof() && !in) return os_error("cannot read back " + target.string());
  if (back.size() != job.bytes.size() || sha256(back) != job.sha256) {
    return make_error(ErrorClass::Protocol,
                      target.string() + ": read back " + std::to_string(back.size()) +
                          " bytes with SHA-256 " + to_hex(sha256(back)) + ", wrote " +
                          std::to_string(job.bytes.size()) + " bytes with " + to_hex(job.sha256));
  }
  failure = knitout::write_file_atomically((folder / (job.name + ".manifest.json")).string(),
                                           [&](std::ostream& out) { out << manifest_json(job); });
  if (!failure.empty()) return make_error(ErrorClass::OsFailure, failure);
  return Ok{};
}

}  // namespace devices
