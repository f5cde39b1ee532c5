// The carriage passes beside another reader (pass_preview.hpp).
#include "backends/dat/pass_preview.hpp"

#include "backends/dat/profile.hpp"

namespace dat {

PassPreview::PassPreview(const std::string& source, const std::string& machine) {
  const Profile* profile = find_profile(machine);
  if (profile == nullptr) {
    why_none_ = "the DAT backend does not write for " + machine;
    return;
  }
  builder_.emplace(source, sink_, *profile);
}

void PassPreview::begin(bool has_magic, const std::vector<knitout::Header>& headers) {
  if (builder_) builder_->begin(has_magic, headers);
}

void PassPreview::add(const knitout::Instruction& instruction,
                      const knitout::CarrierTable& carriers, std::string_view text) {
  if (builder_ && !builder_->failed()) builder_->add(instruction, carriers, text);
}

std::optional<std::vector<CarriagePass>> PassPreview::finish(std::uint32_t last_line) {
  if (!builder_) return std::nullopt;
  builder_->finish(last_line);
  if (!builder_->failed()) return summarize(builder_->passes());
  if (!sink_.diagnostics().empty())
    why_none_ = "the DAT backend refuses the program: " + knitout::format(sink_.sorted().front());
  return std::nullopt;
}

}  // namespace dat
