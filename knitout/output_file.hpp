// Writing an output file so that nothing half-written is ever left behind:
// the content goes to a temporary file beside the target (same folder, so the
// rename is atomic), is flushed and fsync'ed, and is renamed over the target
// only when everything succeeded. On failure the temporary file is removed
// and the target is untouched.
#pragma once

#include <functional>
#include <iosfwd>
#include <string>

namespace knitout {

// Calls `produce` with a stream to the temporary file. Returns an empty
// string on success, else a message naming the path and the OS error (or the
// exception `produce` threw).
std::string write_file_atomically(const std::string& path,
                                  const std::function<void(std::ostream&)>& produce);

}  // namespace knitout
