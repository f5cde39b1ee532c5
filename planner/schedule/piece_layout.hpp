// Each piece of a flat-sheet schedule laid flat the way it comes off the
// machine: x = needle, y = row (paper §7.2: every course edge has a needle;
// rows are stacked as the row graph of §7.1 orders them). The assembly guide
// (planner/assembly/assembly.hpp) draws pieces with it.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "planner/schedule/schedule.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"

namespace planner {

// One stitch of a piece. Needles are piece-local (the leftmost needle any of
// the piece's loops uses is 1, as in the piece's knitout file); heights are
// in rows (0 = the piece's first row).
struct FaceLayout {
  int face = 0;   // stitch-mesh face
  int level = 0;  // its row's height: one more than the highest row below it in the piece
  // Per course-in edge, left to right: the needle of the loop and the height
  // the stitch's bottom sits at (the top of the stitch below, or `level` when
  // the edge is cast on or cut).
  std::vector<int> in_needles;
  std::vector<int> in_levels;
  std::vector<int> out_needles;  // per course-out edge, left to right
};

struct PieceLayout {
  std::vector<FaceLayout> faces;  // in the piece's knitting order
  int needles = 0;                // width in needles
  int levels = 0;                 // height in rows
};

// One layout per schedule.pieces entry (same order). Needs a schedule that
// went through every stage of planner::schedule.
std::vector<PieceLayout> piece_layouts(const Schedule& schedule);

// pieces_dir/piece-N.layout.json for every piece (N from 1, as the knitout
// files), written atomically: {"format": "wearknit-piece-layout 1",
// "piece": N, "needles": W, "rows": H, "faces": [[face, level, [in needles],
// [in levels], [out needles]], ...]} with the fields of FaceLayout. The
// scheduler writes them so the assembly guide draws the pieces it knit.
// Returns "" or the failure.
std::string write_piece_layouts(const std::string& pieces_dir, const Schedule& schedule);

// Reads one such file; nullopt with `error` set (naming the file) when it is
// missing or malformed.
std::optional<PieceLayout> read_piece_layout(const std::string& path, std::string* error);

// A face's sides by role, as the scheduler reads them (§7.1): course-in
// sides left to right, course-out sides left to right, and the right and
// left wale sides (kNone when the face has none there, e.g. the point of a
// short-row triangle). Side i is vertices[i] -> vertices[i + 1].
struct FaceSideRoles {
  std::vector<int> in;
  std::vector<int> out;
  int right_wale = kNone;
  int left_wale = kNone;
};
FaceSideRoles face_side_roles(const StitchFace& face);

// Where side `side` of a face lies in its piece's layout, in (needle, row)
// units: counter-clockwise like the face. A course side is one needle wide
// (the needle +- 0.5); wale sides join the ends of the bottom and top.
std::array<std::array<double, 2>, 2> side_in_layout(const StitchFace& face, const FaceLayout& at,
                                                    int side);

// The four corners of a face in its piece's layout (bottom-left,
// bottom-right, top-right, top-left).
std::array<std::array<double, 2>, 4> face_corners(const FaceLayout& at);

}  // namespace planner
