// Surface cutting (§4): the proxy Q is cut into one topological disc with
// no interior singularity, so every face has a consistent course/wale
// direction.
//
// Directions. Every half-edge of Q gets a direction in the frame of its
// face: 0 = +u, 1 = +v, 2 = -u, 3 = -v. u is the course (row) direction,
// v the wale direction. Walking counter-clockwise around a face the
// direction turns by 1 at every corner, except at the vanishing corner of a
// triangle (§4.1), where it turns by 2: its two sides are a pair of opposite
// edges. Inside the cut disc the frames agree across every edge: the two
// half-edges of an uncut edge have opposite directions (d and d + 2).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "planner/mesh/mesh.hpp"
#include "planner/mesh/mesh_io.hpp"

namespace planner {

// §4.1: vanishing corners and irregular vertices of Q (all faces of Q have 3 or 4 corners).
struct FieldLabels {
  // Per face: the corner index (0-based, in the face's order) of the
  // vanishing corner of a triangle (VanishingRule says which); -1 for quads.
  std::vector<int> vanishing_corner;
  // Per vertex: corners around it, not counting vanishing corners.
  std::vector<int> corner_count;
  // Interior vertices with corner_count != 4 (§4.2).
  std::vector<int> irregular_vertices;
  // Interior vertices with corner_count % 4 != 0: no consistent labelling
  // around them exists, so they must end up on the cut.
  std::vector<int> singular_vertices;
};
// How the vanishing corner of each triangle is chosen (docs/cutting.md,
// "Choosing the vanishing corners"):
//   Optimal: the corners that make the sum of |corner count - 4| over Q's
//     interior vertices the least it can be, the most acute ones among those
//     (optimal_vanishing_corners, vanishing.hpp); departs from §4.1.
//   Acute: §4.1, every triangle's most acute corner.
//   Regular: from the acute corners, a triangle may move to any corner at
//     most `slack_deg` degrees wider than its most acute one when that lowers
//     the same sum; triangles are swept until none moves.
struct VanishingRule {
  enum class Method : std::uint8_t { Optimal, Acute, Regular };
  Method method = Method::Acute;
  double slack_deg = 0.0;  // Regular only
};
// The method's name as `--vanishing` and cut.json spell it: optimal, acute or regular.
const char* vanishing_name(VanishingRule::Method method);
// The method of that name; nullopt for any other name.
std::optional<VanishingRule::Method> vanishing_method(std::string_view name);
FieldLabels label_field(const HalfedgeMesh& q, const VanishingRule& rule = {});
// The same for given vanishing corners (as read back from labels.json).
FieldLabels labels_with_vanishing(const HalfedgeMesh& q, std::vector<int> vanishing_corner);

// Direction turn at the corner where half-edge h starts (1, or 2 at a vanishing corner).
int corner_turn(const HalfedgeMesh& q, const FieldLabels& labels, int h);
// Direction of half-edge h in a face whose first half-edge has direction `frame`.
int halfedge_direction(const HalfedgeMesh& q, const FieldLabels& labels, int frame, int h);

struct CutParams {
  std::uint64_t seed = 1;
  double cs = 1000.0;  // §4.2 straightness weight (motorcycle-graph edges)
  double co = 1.0;     // §4.2 overlap weight
  VanishingRule vanishing;
  // A cut-arc ends where the cut turns by more than this many degrees,
  // measured between the chords two cut edges back and two ahead.
  double arc_turn_deg = 120.0;
  // Equal scores: the face nearest the seed in the (u, v) grid's rings
  // (max(|u|, |v|)) first, so the patch grows as a square; else in the
  // order of the random keys (§4.2).
  bool square_growth = false;
  // Replace the grown cut by a shorter one that opens Q into the same kind
  // of disc (tighten.hpp); departs from §4.2, docs/cutting.md says why.
  bool tighten = false;
};

// A cut-arc: a sequence of cut edges of Q (§3, §4) between nodes of the cut
// graph, as the path of Q's vertices it runs along (edges are consecutive
// pairs). A node is a singular vertex, a vertex on the mesh boundary, a
// vertex where other than two cut edges meet, or one where the cut turns by
// more than CutParams::arc_turn_deg (cut.cpp, find_arcs, says how a turn is
// measured). A closed arc repeats its first vertex
// at the end.
struct CutArc {
  std::vector<int> vertices;
  double length_mm = 0.0;
  bool closed = false;
};

// The result of cutting (the planner's `CutMesh`; a Cut, cut_stage.hpp, holds it with its report).
struct CutMesh {
  HalfedgeMesh proxy;  // Q: quads and triangles
  FieldLabels labels;
  std::vector<int> face_frame;              // per face: direction of its first half-edge
  std::vector<int> direction;               // per half-edge of Q (see top of file)
  std::vector<std::array<int, 2>> face_uv;  // §4.2 integer parametric position
  std::vector<int> overlap_count;           // per face: faces of the patch in its (u, v) cell
  std::vector<bool> cut_edge;               // per edge of Q: both sides are on the disc boundary
  std::vector<int> motorcycle_edges;        // per edge of Q: how many motorcycles crossed it
  // The disc: the faces of Q in the same order and corner order, with the
  // vertices along cuts duplicated. disc_source[i] is Q's vertex of disc vertex i.
  PolygonMesh disc;
  std::vector<int> disc_source;
  std::vector<CutArc> arcs;
  int seed_face = -1;
};

// §4.1–4.2: patch growing from a seed quad (picked by params.seed) with the
// cuttability score c_s * (motorcycle crossings) + c_o * (overlap score);
// equal scores are ordered by a random key from params.seed. Q must be one
// connected oriented manifold of triangles and quads.
// `vanishing_corner`, when given, labels Q instead of params.vanishing
// (the field-guided proxy's corners, field_proxy.hpp).
CutMesh cut_surface(HalfedgeMesh proxy, const CutParams& params,
                    const std::vector<int>* vanishing_corner = nullptr);

// Per vertex of q: the indices of the cut edges at it.
std::vector<std::vector<int>> cut_edges_at(const HalfedgeMesh& q,
                                           const std::vector<bool>& cut_edge);

// No consistent labelling exists around a vertex whose corner count is not
// a multiple of 4 (§4.2): interior, it must be on the cut.
bool is_singular(const FieldLabels& labels, int v);

// A stretch of the cut: Q's vertices it runs along and its edges.
struct CutPath {
  std::vector<int> vertices;
  std::vector<int> edges;
};
// The cut split into paths at the vertices where `node` holds, found from
// the nodes in vertex order, then the loops through no node in edge order
// (such a loop starts and ends at its first vertex). `incident` is
// cut_edges_at(q, cut_edge).
std::vector<CutPath> split_cut(const HalfedgeMesh& q, const std::vector<bool>& cut_edge,
                               const std::vector<std::vector<int>>& incident,
                               const std::function<bool(int)>& node);

// Adjacent opposite pairs: interior vertices of index +1 and -1 one edge
// apart, matched so that each vertex is in one pair at most (greedily, in
// vertex order). They are the avoidable singularities of a proxy: the pair
// cancels in the field, yet the cut must pass through both.
int adjacent_opposite_pairs(const HalfedgeMesh& q, const FieldLabels& labels);

// Independent checks of a CutMesh: the disc has Euler characteristic 1 and
// one boundary loop, every uncut interior edge has opposite directions on
// its two sides, each face's directions turn as its corners say, no
// singular vertex is interior to the disc, and the arcs cover exactly the
// cut edges. Returns one line per problem; empty when all hold.
std::vector<std::string> verify_cut(const CutMesh& cut);

struct CutSummary {
  int irregular_vertices = 0;
  int cut_edges = 0;
  int arcs = 0;
  double cut_length_mm = 0.0;
  int overlapping_faces = 0;  // faces whose (u, v) cell holds more than one face
  int disc_vertices = 0;
  int boundary_loops = 0;
  int euler_characteristic = 0;
};
CutSummary summarize(const CutMesh& cut);

// Course (u) or wale (v) of an edge of Q, from the direction of its first half-edge.
inline bool is_course(int direction) {
  return direction % 2 == 0;
}

}  // namespace planner
