// The seams of the assembly guide (internal to planner/assembly/; what a seam
// is: docs/assembly.md, "What a seam is"). The steps of `load` that turn the
// scheduler's cuts, the wale seams and the cut-arcs into numbered seams.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <unordered_map>
#include <vector>

#include "planner/assembly/assembly_model.hpp"

namespace planner::assembly {

// Where a cut-arc runs: its polyline through the proxy's vertices, and the
// arc length at each point.
struct ArcLine {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> start;
};

// The scheduler's cuts (`schedule_cuts` of schedule.json, §7.3), one seam
// each joining the lower rows' course sides to the upper rows'. Throws
// Failure (A002, A004) naming `path`.
std::vector<Seam> schedule_cut_seams(const Model& m, const nlohmann::json& schedule_cuts,
                                     const std::filesystem::path& path);

// Wale seams (§7.1): the shared wale sides of m.wale_seams, grouped
// into stretches that touch and join the same two pieces.
std::vector<Seam> wale_seams(const Model& m);

struct ArcSeams {
  std::vector<Seam> sew;
  std::vector<Seam> lace;
};

// The seams along the cut-arcs, one per chain of m.chains (the arcs chained
// by planner/cut/seam_chains.hpp): every boundary side on an arc
// (`arc_of_key`, from the stitch mesh's `# arc` lines) placed along its
// arc's line, and so along its chain, split into parts where either side
// passes from one piece to another. Sets m.arcs[i].seams. Throws Failure
// (A004) for a side on an arc the cut does not have.
ArcSeams chain_seams(Model& m, const std::unordered_map<std::uint64_t, int>& arc_of_key,
                     const std::map<int, ArcLine>& lines);

// Puts the seams in closing order into m.seams and numbers them: the ones to
// sew (scheduler cuts, wale seams, arcs to sew), then the laced ones (§5);
// the parts of a seam share its number. Sets m.numbered, m.sewn, the sides'
// seams and each stretch's length.
void number_seams(Model& m, std::vector<Seam> cut_seams, std::vector<Seam> wale, ArcSeams arcs);

}  // namespace planner::assembly
