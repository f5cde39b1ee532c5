// bed::BedView: the needle x time picture of a program (the paper's "bed
// view", Fig. 9b): which needles hold loops at each moment, coloured by the
// carrier of the top loop, with sweeps that transfer and racking changes
// marked by short ticks in a margin, so that the fabric is what one sees.
//
// Attach it to a Machine as its Observer; it samples the bed at the end of
// every sweep (docs/vm.md), so a row of the picture is one carriage crossing.
// Memory grows with sweeps x bed span (one byte per needle per bed per
// sweep). Long programs are drawn with several sweeps merged into one pixel
// row so the picture stays under kMaxRows rows.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "simulators/bed/machine.hpp"

namespace bed {

class BedView : public Observer {
 public:
  static constexpr int kMaxRows = 2400;
  // At most this many needles per bed are drawn (from the leftmost used).
  static constexpr int kMaxNeedles = 20000;

  void sweep_ended(const Machine& machine, std::uint32_t line) override;
  void loops_moved(knitout::Needle from, knitout::Needle to, int count,
                   std::uint32_t line) override;
  void racked(double racking, std::uint32_t line) override;

  std::size_t samples() const { return rows_.size(); }

  // Writes the picture; the format follows the extension (.png or .svg).
  // Returns an empty string on success, else what went wrong.
  std::string write(const std::string& path, const Machine& machine,
                    const std::string& title) const;

 private:
  struct Row {
    int min_slot = 0;                 // slot of cells[0]
    std::vector<std::uint8_t> front;  // 0 = empty, else 1 + carrier colour index
    std::vector<std::uint8_t> back;
    std::vector<std::uint8_t> front_count;  // loops held
    std::vector<std::uint8_t> back_count;
    std::vector<int> transfers;  // slots transferred from/to during the sweep
    double racking = 0;
    bool racked = false;  // racking changed before this sweep
    std::uint32_t line = 0;
  };
  std::vector<int> pending_transfers_;
  bool pending_rack_ = false;
  std::vector<Row> rows_;
};

}  // namespace bed
