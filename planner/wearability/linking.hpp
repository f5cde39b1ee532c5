// Whether a garment is linked with its wearer: a test that needs no cloth.
//
// A closed curve of the garment that winds around a handle of the wearer
// (a sleeve sewn shut around the ring of a torus, a band around one arm of
// a figure eight) can never be slid off it, however far the cloth moves or
// stretches: the curve would have to pass through the wearer. The linking
// number of two disjoint closed curves counts how often one winds around the
// other; it does not change while neither passes through the other, and it
// is zero once they are far apart. So when a garment curve has a non-zero
// linking number with any closed curve lying in the wearer, the garment
// cannot come off. The converse does not hold (two curves can be entangled
// with linking number zero, and a closed shell around a ball is caught
// without any curve winding around anything): a configuration this test
// does not catch is simulated as §5 says.
//
// The curves that matter on each side are few. Linking numbers add, so the
// curves of one side need only span its first homology: a closed surface of
// genus g has 2g such curves, a surface with b boundary loops 2g + b - 1
// (cut along the tree and cotree of a spanning tree, Eppstein 2003), a
// sphere or a disc none. A wearer of genus 0 therefore has no curve to test
// against, and a garment cut into a disc (every arc laced) has none either.
#pragma once

#include <optional>
#include <vector>

#include "simulators/cloth/cloth.hpp"
#include "simulators/cloth/sdf.hpp"

namespace planner {

using Loop = std::vector<cloth::Vec3>;  // a closed polyline: the last point joins the first

// Vertex cycles spanning the first homology of the surface `faces` over
// `vertex_count` vertices (faces may be polygons; edges used by more than
// two faces are allowed and give more cycles): each a fundamental cycle of
// a breadth-first spanning tree through an edge in neither that tree nor a
// spanning tree of the faces, the boundary counted as one face. At most
// `max_loops` of them.
std::vector<std::vector<int>> homology_cycles(int vertex_count,
                                              const std::vector<std::vector<int>>& faces,
                                              int max_loops);

// The linking number of two disjoint closed polylines, from the signed
// crossings of `a` over `b` in a projection along `view`; nothing when the
// projection is degenerate there (a crossing at a vertex, segments seen
// edge-on over each other).
std::optional<int> linking_number(const Loop& a, const Loop& b, const cloth::Vec3& view);

// The curves of a wearer, computed once, and the test of a garment.
class LinkingTest {
 public:
  // Loops of the wearer's surface (the distance field's mesh, its vertices
  // welded), at most `max_loops`.
  explicit LinkingTest(const cloth::SignedDistanceField& wearer, int max_loops = 64);

  struct Linked {
    int linking_number = 0;  // of the garment curve found with one of the wearer's curves
  };
  // A curve of `garment` (a configuration from open_cuts, dressed outside
  // the wearer) linked with the wearer; nothing when none is found. Each
  // cycle of the garment is followed outside the wearer (outside_curve), and
  // a linking number counts only when two projections agree on it.
  std::optional<Linked> linked(const cloth::PolygonMesh& garment) const;

  int wearer_loops() const { return static_cast<int>(loops_.size()); }

  // The garment polyline `loop` as a curve outside the wearer: each vertex
  // pushed out along the distance field's gradient to half a cell outside,
  // and each edge followed by halving where a chord passes inside (sampled
  // every quarter cell), the middles pushed out as well. Nothing when a point
  // lies deeper than a quarter of its edge's length (a chord through a thin
  // part of the wearer, not across a curve of it) or cannot be pushed out,
  // or when the curve needs more than 16 points per edge.
  std::optional<Loop> outside_curve(const Loop& loop) const;

 private:
  const cloth::SignedDistanceField* wearer_;
  std::vector<Loop> loops_;
  int max_loops_;
};

}  // namespace planner
