// The plan folder's page, DIR/index.html: one self-contained HTML file
// (simulators/bed/web_page.hpp) that shows, offline from file://, the garment
// on its wearer in 3D with its seams numbered and coloured sew / lace, the
// stitch mesh by face type, the pieces laid flat as in the assembly guide,
// each piece's figures and bed view, and the stage times and figures of
// report.json. The script is planner/viewer/web/ (docs/plan.md, "The page").
//
// The data comes from the stage files through the stages' readers and the
// assembly guide's model of the folder (planner/assembly/assembly_model.hpp:
// the seams, their numbers and both their sides, the pieces laid flat), so
// the page and the guide always agree. A folder whose later stages have not
// run (cut only, no schedule) gives a page with what exists: the cut-arcs,
// labelled when wearability.json is there, on the cut disc or the stitch mesh.
#pragma once

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "simulators/bed/web_page.hpp"

namespace planner::viewer {

// What the page is made of: `meta` (block "plan") holds the seams, pieces,
// figures and what is missing; the other blocks are little-endian binary
// arrays (Float32 positions in mm, Uint32 indices, Uint8 face types) named in
// meta["blocks"].
struct PlanPageData {
  nlohmann::json meta;
  std::vector<bed::PageData> blocks;  // meta first, as block "plan"
};

// Collects the page's data from plan folder `dir`. Never throws for a
// folder that lacks stages or whose files do not belong together: what
// cannot be shown is named in meta["notes"]. Throws std::runtime_error when
// `dir` is not a folder.
PlanPageData collect_plan_page(const std::filesystem::path& dir);

// The pieces' knitout sources embedded in the page, at most (bytes before
// compression): a piece past it has its bed view with line numbers only.
inline constexpr std::size_t kMaxPageSourceBytes = 24u << 20;

struct PlanPageSummary {
  std::size_t bytes = 0;  // size of index.html
  int seams = 0;          // seams (or cut-arcs, before the schedule) shown; parts count once
  int pieces = 0;
  bool wearer = false;
};

// Writes dir/index.html atomically; returns "" or the failure, naming the file.
std::string write_plan_page(const std::filesystem::path& dir, PlanPageSummary* summary = nullptr);

}  // namespace planner::viewer
