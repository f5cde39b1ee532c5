// Writes the bunny-cover-sized synthetic stitch mesh as a plan folder:
//   make_cover_smobj DIR   -> DIR/stitch-mesh.smobj
#include <filesystem>
#include <iostream>

#include "knitout/output_file.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "tests/planner/schedule_fixtures.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_cover_smobj DIR\n";
    return 2;
  }
  std::filesystem::create_directories(argv[1]);
  const std::string failure = knitout::write_file_atomically(
      (std::filesystem::path(argv[1]) / "stitch-mesh.smobj").string(),
      [](std::ostream& out) { planner::write_smobj(out, planner::fixtures::cover_like()); });
  if (!failure.empty()) {
    std::cerr << "make_cover_smobj: " << failure << '\n';
    return 2;
  }
  return 0;
}
