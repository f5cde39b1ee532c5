// The assembly guide's picture of a plan folder (internal to
// planner/assembly/): the stitch mesh, the pieces laid flat, the cut-arcs and
// the numbered seams, with the lookups the drawing code needs. `load` fills
// it (assembly_load.cpp); the seams are made by assembly_seams.cpp.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "knitout/diagnostic.hpp"
#include "planner/cut/seam_chains.hpp"
#include "planner/schedule/piece_layout.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"

namespace planner::assembly {

// A failure with its message already formatted (`PATH: error: [A0xx] ...`).
struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws the Failure `FILE: error: [CODE] message` (codes in docs/diagnostics.md).
[[noreturn]] void fail(const std::filesystem::path& file, const char* code,
                       const std::string& message);

// The text of the first error in `sink`, or "unknown problem".
std::string first_error(const knitout::DiagnosticSink& sink);

// The key of the undirected side between vertices a and b.
std::uint64_t side_key(std::uint32_t a, std::uint32_t b);

// Side `side` (from corner side to corner side + 1) of stitch-mesh face `face`.
struct SideRef {
  int face = 0;
  int side = 0;
  bool operator<(const SideRef& o) const { return face != o.face ? face < o.face : side < o.side; }
  bool operator==(const SideRef& o) const { return face == o.face && side == o.side; }
};

enum class SeamKind { ScheduleCut, WaleSeam, CutArc };

// One numbered seam, or one part of it: a seam whose stretches pass from
// one piece to another is split into parts (`seam 4 part 2 of 3`, drawn as
// 4.2), each joining exactly one stretch to one other.
struct Seam {
  int number = 0;  // shared by the parts of a seam
  bool lace = false;
  bool labelled = true;  // false: the arcs have no wearability label (treated as sew)
  SeamKind kind = SeamKind::CutArc;
  int arc = -1;           // the first of `arcs` (CutArc), or index in schedule_cuts (ScheduleCut)
  std::vector<int> arcs;  // CutArc: the cut's arc ids of the seam, in order along it
  int part = 1;
  int parts = 1;
  std::array<std::vector<SideRef>, 2> sides;  // the two stretches that are joined, in order
  std::array<int, 2> piece{{0, 0}};           // the piece each side's number is drawn on
  std::array<SideRef, 2> label_at;            // the side each side's number is drawn on
  std::array<double, 2> stretch_mm{{0, 0}};   // length of each stretch, stitch mesh mm
  // The name drawn on the pieces: the number, with the part for a seam in parts.
  std::string name() const {
    return parts > 1 ? std::to_string(number) + "." + std::to_string(part) : std::to_string(number);
  }
};

struct ArcInfo {
  int id = 0;
  bool lace = false;
  bool labelled = false;
  double length_mm = 0;
  int seam = -1;  // index of its chain in Model::chains
  int seams = 0;  // numbered seam parts made from its chain
};

struct Model {
  std::filesystem::path dir;
  double garment_mm_per_unit = 1;  // the cut's recorded units times its scale
  StitchMesh mesh;
  std::vector<std::pair<int, int>> wale_seams;  // faces joined across a wale seam (§7.1)
  std::vector<PieceLayout> layouts;
  std::vector<int> piece_of_face;
  std::vector<int> layout_index;  // face -> index in its piece's layout
  std::unordered_map<std::uint64_t, std::vector<SideRef>> sides_by_key;
  std::vector<Seam> seams;  // in closing order, numbered 1..numbered, parts in order
  std::vector<ArcInfo> arcs;
  std::vector<SeamChain> chains;  // the cut-arcs chained into seams (seam_chains.hpp)
  std::map<SideRef, int> seam_of_side;
  int numbered = 0;  // seam numbers
  int sewn = 0;      // seams 1..sewn are sewn, the rest laced
};

// The side of another face that `s` is shared with, or {kNone, kNone} on the
// boundary.
SideRef other_side(const Model& m, SideRef s);
// The vertices of side `s`, in the face's order.
std::array<std::uint32_t, 2> side_vertices(const Model& m, SideRef s);
Eigen::Vector3d side_mid(const Model& m, SideRef s);
// The side of `face` shared with `other` (of the given role), or kNone.
int shared_side(const Model& m, int face, int other, EdgeRole role);

// Reads the plan folder `dir` (docs/assembly.md) into `m`, seams numbered in
// closing order; throws Failure (A001-A004) when the folder cannot be read or
// its files do not belong together.
void load(Model& m, const std::filesystem::path& dir);

}  // namespace planner::assembly
