// Result<T>: what every device call returns instead of throwing.
//
// Errors come in the classes libserialport uses, so callers can decide what
// to do without parsing text: a caller bug (InvalidArgument), an operating
// system failure with its errno kept (OsFailure), something this build or
// this device cannot do (Unsupported), a deadline that passed (Timeout), and
// a peer or cable that went away (Disconnected). Protocol covers a peer that
// answered with something the protocol does not allow.
#pragma once

#include <cerrno>
#include <string>
#include <string_view>
#include <utility>
#include <variant>

namespace devices {

enum class ErrorClass { InvalidArgument, OsFailure, Unsupported, Timeout, Disconnected, Protocol };

std::string_view to_string(ErrorClass error_class);

struct Error {
  ErrorClass error_class = ErrorClass::OsFailure;
  std::string message;  // says what was attempted on what
  int os_errno = 0;     // OsFailure only; 0 otherwise

  // "MESSAGE" plus ": strerror(errno)" for OS failures.
  std::string text() const;
};

Error make_error(ErrorClass error_class, std::string message);
// An OsFailure carrying the current errno (read before anything else runs).
Error os_error(std::string message, int saved_errno = errno);

template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : data_(std::move(value)) {}      // NOLINT: implicit by design
  Result(Error error) : data_(std::move(error)) {}  // NOLINT: implicit by design

  bool ok() const { return data_.index() == 0; }
  explicit operator bool() const { return ok(); }
  T& value() & { return std::get<0>(data_); }
  const T& value() const& { return std::get<0>(data_); }
  T&& value() && { return std::get<0>(std::move(data_)); }
  const Error& error() const { return std::get<1>(data_); }

 private:
  std::variant<T, Error> data_;
};

// Result<void>: success carries nothing.
struct Ok {};
using Outcome = Result<Ok>;

}  // namespace devices
