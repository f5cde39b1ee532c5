// The carriage passes the DAT backend forms for a program that another
// reader is going through at the same time (`wearknit simulate` steps the
// needle-bed VM and shows the passes beside its statistics). The preview's
// diagnostics stay apart from the caller's: a program the backend refuses
// simply has no passes, and why_none() says why.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "backends/dat/passes.hpp"
#include "knitout/diagnostic.hpp"

namespace dat {

class PassPreview {
 public:
  // `machine` is a machine profile name; for one the backend does not write,
  // every call does nothing and why_none() says so.
  PassPreview(const std::string& source, const std::string& machine);
  PassPreview(const PassPreview&) = delete;
  PassPreview& operator=(const PassPreview&) = delete;

  void begin(bool has_magic, const std::vector<knitout::Header>& headers);
  void add(const knitout::Instruction& instruction, const knitout::CarrierTable& carriers,
           std::string_view text);
  // The passes of the whole program; nullopt when the backend refuses it
  // (a program it accepts may still form no pass).
  std::optional<std::vector<CarriagePass>> finish(std::uint32_t last_line);
  // Why there are no passes ("" when there are, or when the backend gave no
  // reason).
  const std::string& why_none() const { return why_none_; }

 private:
  knitout::DiagnosticSink sink_;
  std::optional<PassBuilder> builder_;
  std::string why_none_;
};

}  // namespace dat
