// Seams as a person closes them: the cut-arcs (§4.2) chained into maximal
// runs of one label (§5: sew or lace) that pass through cut vertices no
// other arc touches (docs/assembly.md, "What a seam is").
//
// An arc ends at singular vertices, branch nodes of the cut graph, the
// mesh's boundary and sharp turns of the cut. At a sharp turn, or wherever
// exactly two arcs end at a vertex, the cut runs on as one line; when both
// arcs carry the same label a person closes them in one go, so they are one
// seam. Where three or more arcs meet, or the label changes, a seam ends.
#pragma once

#include <cstddef>
#include <vector>

namespace planner {

// One cut-arc as the chaining sees it: its end vertices (any vertex ids, as
// long as arcs that share an end give it the same id; a closed arc has
// first == last) and its label, as a small integer: arcs join only when
// their labels are equal. The seams come out ordered by label, so a caller
// that wants sewn seams first gives sew the smaller value.
struct ArcEnds {
  int first = 0;
  int last = 0;
  int label = 0;
};

// A seam: its arcs in order along it, each with the direction it is walked.
struct SeamChain {
  std::vector<int> arcs;       // indices into the ArcEnds list
  std::vector<bool> reversed;  // arcs[k] is walked from its last vertex to its first
  int label = 0;
  bool closed = false;  // the seam ends where it starts (a loop of arcs)
};

// Groups every arc into exactly one seam. Two arcs are joined at a vertex
// when it is an end of those two arcs and of no other arc of `arcs` (a
// vertex of degree 2 in the arc graph; a closed arc counts twice at its
// vertex) and their labels are equal; seams are the maximal chains of
// joined arcs, a loop of joined arcs being one closed seam. An open seam
// is walked from the end whose arc has the smaller index, a closed one
// from its smallest arc in that arc's own direction. The seams are ordered
// by label, then by their smallest arc index. Deterministic; time linear in
// the number of arcs (plus sorting).
std::vector<SeamChain> chain_arcs(const std::vector<ArcEnds>& arcs);

// The seam of every arc: the index in `seams` of the seam holding arc a,
// for a in 0..arc_count-1 (-1 for an arc in none).
std::vector<int> seam_of_arc(const std::vector<SeamChain>& seams, std::size_t arc_count);

}  // namespace planner
