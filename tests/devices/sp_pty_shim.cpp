// Test-only LD_PRELOAD library that lets Debian's libserialport 0.1.1 open a
// Linux pseudo-terminal (transport notes §2a). libserialport refuses ptys
// twice: sp_get_port_by_name() looks the port up under /sys/class/tty/NAME,
// which ptys do not have, and sp_open() reads the modem lines with TIOCMGET,
// which ptys reject with ENOTTY. This library (1) answers lookups of
// /sys/class/tty/pts/N with /sys/class/tty/ptmx and (2) emulates
// TIOCMGET/TIOCMSET/TIOCMBIS/TIOCMBIC with a per-descriptor bit mask when the
// kernel says ENOTTY. Nothing else changes; real serial ports are untouched.
//
// glibc's own declarations are deliberately not included: the definitions
// below replace them, and the kernel headers give the constants.
#include <asm-generic/ioctls.h>
#include <asm-generic/termios.h>
#include <dlfcn.h>
#include <sys/types.h>

#include <cerrno>
#include <cstdarg>
#include <cstring>

struct stat;

namespace {

constexpr char kPts[] = "/sys/class/tty/pts/";
int modem_bits[1024];

const char* redirect(const char* path) {
  return path != nullptr && std::strncmp(path, kPts, sizeof kPts - 1) == 0 ? "/sys/class/tty/ptmx"
                                                                           : path;
}

template <typename F>
F next_symbol(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" {

int lstat(const char* path, struct stat* st) {
  static auto real = next_symbol<int (*)(const char*, struct stat*)>("lstat");
  return real(redirect(path), st);
}

// Debian's libserialport0 binary imports __lxstat rather than lstat.
int __lxstat(int version, const char* path, struct stat* st) {
  static auto real = next_symbol<int (*)(int, const char*, struct stat*)>("__lxstat");
  return real(version, redirect(path), st);
}

ssize_t readlink(const char* path, char* buffer, size_t size) {
  static auto real = next_symbol<ssize_t (*)(const char*, char*, size_t)>("readlink");
  return real(redirect(path), buffer, size);
}

int ioctl(int fd, unsigned long request, ...) {
  static auto real = next_symbol<int (*)(int, unsigned long, ...)>("ioctl");
  va_list args;
  va_start(args, request);
  void* arg = va_arg(args, void*);
  va_end(args);
  const int result = real(fd, request, arg);
  if (result < 0 && errno == ENOTTY && fd >= 0 && fd < 1024 && arg != nullptr) {
    int* bits = static_cast<int*>(arg);
    switch (request) {
      case TIOCMGET:
        *bits = modem_bits[fd] | TIOCM_CTS | TIOCM_DSR | TIOCM_CAR;
        return 0;
      case TIOCMSET:
        modem_bits[fd] = *bits;
        return 0;
      case TIOCMBIS:
        modem_bits[fd] |= *bits;
        return 0;
      case TIOCMBIC:
        modem_bits[fd] &= ~*bits;
        return 0;
      default:
        break;
    }
  }
  return result;
}

}  // extern "C"
