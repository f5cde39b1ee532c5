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

// The files of a plan folder the guide reads.
struct PlanFiles {
  explicit PlanFiles(const std::filesystem::path& dir)
      : cuts(dir / "cuts.json"),
        report(dir / "report.json"),
        smobj(dir / "stitch-mesh.smobj"),
        proxy(dir / "proxy.obj") {}
  std::filesystem::path cuts;
  std::filesystem::path report;
  std::filesystem::path smobj;
  std::filesystem::path proxy;
};

// Where a cut-arc runs: its polyline through proxy.obj's vertices, and the
// arc length at each point.
struct ArcLine {
  std::vector<Eigen::Vector3d> points;
  std::vector<double> start;
};

// The scheduler's cuts (`schedule_cuts` of cuts.json, §7.3), one seam each
// joining the lower rows' course sides to the upper rows'. With
// `check_rebuilt`, they must be the cuts of m.schedule (rebuilt from
// report.json). Throws Failure (A002, A004).
std::vector<Seam> schedule_cut_seams(const Model& m, const nlohmann::json& cuts,
                                     const std::filesystem::path& cuts_path, bool check_rebuilt);

// Wale seams (§7.1): the shared wale sides of m.schedule.wale_seams, grouped
// into stretches that touch and join the same two pieces.
std::vector<Seam> wale_seams(const Model& m);

struct ArcSeams {
  std::vector<Seam> sew;
  std::vector<Seam> lace;
};

// The seams along the cut-arcs: every boundary side on an arc (`arc_of_key`,
// from the stitch mesh's `# arc` lines) placed along the arc's line, split
// where either side passes from one piece to another. Sets m.arcs[i].seams.
// Throws Failure (A004) for a side on an arc cuts.json does not list.
ArcSeams arc_seams(Model& m, const std::unordered_map<std::uint64_t, int>& arc_of_key,
                   const std::map<int, ArcLine>& lines, const PlanFiles& files);

// Puts the seams in closing order into m.seams and numbers them: the ones to
// sew (scheduler cuts, wale seams, arcs to sew), then the laced ones (§5).
void number_seams(Model& m, std::vector<Seam> cut_seams, std::vector<Seam> wale, ArcSeams arcs);

}  // namespace planner::assembly
