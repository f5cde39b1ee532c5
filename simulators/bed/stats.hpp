// bed::Stats: what a dry run of a knitout program measures.
//
// Filled by bed::Machine as it runs; `write_stats_text` and
// `write_stats_json` print it for `wearknit simulate --stats [--json]`.
// Units are in the names. The time and yarn models are documented in
// docs/vm.md ("Estimated machine time", "Yarn length").
#pragma once

#include <array>
#include <cstdint>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "knitout/program.hpp"

namespace bed {

struct CarrierStats {
  std::string name;
  std::uint64_t loops = 0;   // loops this carrier made (knit, tuck, split)
  double float_pitches = 0;  // sum of the distances between its consecutive loops
  double longest_float_pitches = 0;
  double yarn_m = 0;  // estimated yarn length (docs/vm.md)
};

struct Stats {
  std::uint64_t lines = 0;         // source lines read
  std::uint64_t instructions = 0;  // operations (comment-only lines not counted)
  std::array<std::uint64_t, knitout::kOpCount> by_op{};  // indexed by knitout::Op
  std::uint64_t loops_made = 0;
  std::uint64_t transfers = 0;  // xfer instructions that moved at least one loop
  std::uint64_t loops_transferred = 0;
  std::uint64_t racks = 0;  // rack instructions that changed the racking
  int largest_stack = 0;    // most loops on one needle at any time
  std::string largest_stack_needle;
  std::uint32_t largest_stack_line = 0;
  // Front-bed slots used (back needle b n at racking r counts as n + floor(r)).
  bool has_span = false;
  int min_slot = 0;
  int max_slot = 0;
  std::vector<CarrierStats> carriers;  // every carrier that came in, by first entry
  // Carriage sweeps as the machine model estimates them (docs/vm.md).
  std::uint64_t sweeps = 0;
  std::uint64_t knit_sweeps = 0;
  std::uint64_t transfer_sweeps = 0;
  std::uint64_t drop_sweeps = 0;
  double sweep_needles = 0;  // carriage travel in needle pitches, overrun included
  double estimated_time_s = 0;
  // Carriage passes as the DAT backend forms them; unset until a backend
  // that forms passes fills it in (the VM does not guess it).
  std::optional<std::uint64_t> dat_passes;
  std::uint64_t errors = 0;
  std::uint64_t warnings = 0;

  std::int64_t bed_span() const { return has_span ? std::int64_t{max_slot} - min_slot + 1 : 0; }
};

void write_stats_text(std::ostream& out, const Stats& stats, const std::string& source,
                      const std::string& machine);
void write_stats_json(std::ostream& out, const Stats& stats, const std::string& source,
                      const std::string& machine);

}  // namespace bed
