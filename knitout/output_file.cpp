#include "knitout/output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>

namespace knitout {
namespace {

std::string os_error(const std::string& what, const std::string& path) {
  return what + " " + path + ": " + std::strerror(errno);
}

}  // namespace

std::string write_file_atomically(const std::string& path,
                                  const std::function<void(std::ostream&)>& produce) {
  std::string tmp = path + ".tmp-XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) return os_error("cannot create a temporary file for", path);
  // mkstemp makes the file private; give it the mode a plain create would.
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  ::close(fd);
  std::string failure;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    try {
      if (!out) {
        failure = os_error("cannot write", tmp);
      } else {
        produce(out);
        out.flush();
        if (!out) failure = os_error("cannot write", path);
      }
    } catch (const std::exception& e) {
      failure = "cannot write " + path + ": " + e.what();
    }
  }
  if (failure.empty()) {
    const int sync_fd = ::open(tmp.c_str(), O_RDONLY);
    if (sync_fd < 0 || ::fsync(sync_fd) != 0) failure = os_error("cannot write", path);
    if (sync_fd >= 0) ::close(sync_fd);
  }
  if (failure.empty() && std::rename(tmp.c_str(), path.c_str()) != 0) {
    failure = os_error("cannot rename the temporary file onto", path);
  }
  if (!failure.empty()) std::remove(tmp.c_str());
  return failure;
}

}  // namespace knitout
