// make_sheet: writes a generated knitout sheet, the benchmarks' big input.
//   make_sheet OUT.k [WIDTH ROWS [plain|seed]]   (default 500 x 2000 plain: ~1,000,000 lines)
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <string>

#include "knitout/generate.hpp"

int main(int argc, char** argv) {
  if (argc != 2 && argc != 4 && argc != 5) {
    std::cerr << "usage: make_sheet OUT.k [WIDTH ROWS [plain|seed]]\n";
    return 2;
  }
  knitout::SheetParams params;
  params.width_needles = 500;
  params.rows = 2000;
  if (argc >= 4) {
    params.width_needles = std::atoi(argv[2]);
    params.rows = std::atoi(argv[3]);
  }
  if (argc == 5 && std::string(argv[4]) == "seed") params.pattern = knitout::SheetPattern::Seed;
  std::ofstream out(argv[1], std::ios::binary);
  knitout::write_sheet(out, params);
  out.close();
  if (!out) {
    std::cerr << "make_sheet: cannot write " << argv[1] << '\n';
    return 2;
  }
  return 0;
}
