// Internals of the stitch mesher (stitch_mesher.hpp has the method and the
// public interface): the types and functions its steps share, in namespace
// planner::stitch_meshing. Only planner/stitch_mesh/ includes this header.
//
//   geometry.cpp                  helpers: face normals, the disc as a surface, length cost
//   row_time.cpp                  step 1: triangles, the row time t; step 2: rows by height
//   row_time_critical_points.cpp  step 2: interior extrema levelled, saddles held on a level
//   band_slices.cpp               step 2: triangles cut along the levels, strips
//   chains.cpp                    step 3: a strip's boundary as bottom, top and wale chains
//   row_sampling.cpp              step 3: stitch vertices along the chains, segment counts
//   strips.cpp                    step 4: each strip brought to one bottom and one top chain
//   zip.cpp                       step 4: the faces between the two chains
//   relax.cpp                     step 5: inner stitch vertices relaxed over the surface
//   stitch_mesher.cpp             the input check and the steps in order
//   stitch_mesh_figures.cpp       figures of a finished stitch mesh
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <utility>
#include <vector>

#include "planner/common/index.hpp"
#include "planner/mesh/mesh.hpp"
#include "planner/stitch_mesh/stitch_mesher.hpp"
#include "simulators/cloth/sdf.hpp"

namespace planner::stitch_meshing {

// The steps in order (stitch_mesher.cpp) into `result`: the mesh, its
// figures and the problems of faces it could not make valid. Throws
// std::runtime_error, naming the place, where the rows cannot be made
// into strips at all; make_stitch_mesh reports that as a problem.
void mesh_disc(const LabelledDisc& disc, const StitchMeshParams& params, StitchMeshResult& result);

// ---------------------------------------------------------------------------
// Geometry helpers (geometry.cpp).

// The directed vertex pair a -> b as one key.
inline std::uint64_t key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

// Twice the vector area of a disc face (Newell), not normalised.
Vec3 face_normal(const LabelledDisc& disc, const std::vector<int>& face);

// The surface the stitches lie on, as triangles (fans of its faces), for
// exact distances and nearest points: the garment's (LabelledDisc::surface)
// where the disc has it, else the disc itself.
cloth::TriangleMeshQuery disc_surface(const LabelledDisc& disc);

// The larger t at which a + t e is `radius` from `centre`, or nullopt when
// the line misses that sphere (or e is zero).
std::optional<double> sphere_exit(const Vec3& a, const Vec3& e, const Vec3& centre, double radius);

// A side is the right length when it is within this fraction of its target
// (StitchMeshFigures::within_15_percent; the shared-mesh test asks 90% of
// course and of wale sides to be).
constexpr double kLengthTolerance = 0.15;

// The cost of a side whose length is off its target by the fraction `off`:
// its square, and `outside` more if it is over kLengthTolerance.
double length_cost(double off, double outside);

// ---------------------------------------------------------------------------
// Step 1: triangles with a wale direction each, and the row time t
// (row_time.cpp).

// A triangle of the disc (its faces split into triangles).
struct Triangle {
  std::array<int, 3> v{};
  int face = -1;
  Vec3 normal = Vec3::Zero();  // unit
  double area = 0;
  Vec3 wale = Vec3::Zero();  // unit, in the triangle's plane
  Vec3 grad = Vec3::Zero();  // gradient of t
};

// The disc's faces as triangles, each with the wale direction its face's
// labels give: the course sides turned a quarter turn about the normal, or
// the +v sides where a face has no course side. Quads are split along the
// shorter diagonal, other polygons as a fan.
std::vector<Triangle> triangulate(const LabelledDisc& disc);

// Least-squares fit of t to the target gradients (Poisson equation with
// the cotangent Laplacian), then straightening fits towards unit speed
// until t settles. t is in rows (|grad t| = 1 / wale_mm) and starts at 0.
// Sets each triangle's `grad` and stats.straighten_fits and
// label_deviation_deg. Throws std::runtime_error when the Laplacian cannot
// be factorised.
Eigen::VectorXd row_time(const LabelledDisc& disc, std::vector<Triangle>& tris,
                         const StitchMeshParams& params, StitchMeshStats& stats);

// ---------------------------------------------------------------------------
// Step 2, rows (row_time.cpp, row_time_critical_points.cpp).

// Row placement: t mapped monotonically so that rows are wale_mm tall on
// average over each stretch of t. Where t is flat (labels that converge or
// curl keep |grad t| below 1 / wale_mm), equal steps of t would give rows
// that are too tall; there the mapped value rises faster. Per thin slab of t
// the height is its area over the length of its level curve; the mapped
// value at t is the height below t in rows (scaled so there is a whole
// number of rows). Returns the mapped value per vertex; `bands` receives the
// number of rows.
Eigen::VectorXd row_levels(const LabelledDisc& disc, const std::vector<Triangle>& tris,
                           const Eigen::VectorXd& t, const StitchMeshParams& params, int& bands);

// The vertices joined to each vertex by a side of the triangles.
std::vector<std::vector<int>> vertex_neighbours(const std::vector<Triangle>& tris, std::size_t n);

// Per vertex of the disc: whether it lies on the disc boundary.
std::vector<bool> on_disc_boundary(const LabelledDisc& disc);

// A row time with an interior extremum has closed level curves round it:
// the band there is a strip with a hole, which no zip can fill. The
// least-squares fit can make one even on consistent labels (its curl-free
// part need not follow the labels' turning everywhere). This levels t so
// that from every vertex a path runs down to the disc boundary on which t
// never rises, and another on which t never falls: pits are filled to their
// spill level and peaks cut to theirs (morphological reconstruction by
// priority flood from the boundary, alternated until neither changes t).
// Then every component of {t < c} and of {t > c} reaches the boundary, so
// no band has a hole. Returns how many vertices changed.
int level_interior_extrema(const LabelledDisc& disc, const std::vector<Triangle>& tris,
                           Eigen::VectorXd& t);

// Interior extrema drained (step 2, docs/stitch-mesh.md "Interior
// extrema"): levelling a pit or peak leaves a flat region inside one band,
// a row many wales tall there. Instead each region level_interior_extrema
// would flatten is given targets that rise away from the point where it
// spills (a pit) or fall away from it (a peak), and t is fitted again, as a
// whole, up to `rounds` times while extrema remain. Returns how many
// vertices were in drained regions; t may still have extrema afterwards.
int drain_interior_extrema(const LabelledDisc& disc, std::vector<Triangle>& tris,
                           Eigen::VectorXd& t, const StitchMeshParams& params, int rounds);

// Saddles on a level (step 2, docs/stitch-mesh.md "Saddles on a level").
// Near a saddle of t the level curves form an X. A saddle inside a band
// makes a strip with two bottom and two top chains, which split_folds can
// only cut between corners of its chains, far from the saddle, so the
// band's height there ends up in long wale sides; a saddle on the disc
// boundary (half of one, where a cut runs through it, or a fold of the cut
// across the rows) makes a strip whose bottom and top differ in length,
// zipped with a fan of shaping. Held exactly on a level, the saddle is where
// the level curve meets itself or the boundary: the bands on either side are
// strips that meet at the saddle, and no strip needs to go round it.
// The rows are raised or lowered round each saddle among `candidates` by a
// bump, flat up to `inner_mm` from it and falling smoothly to nothing at
// `outer_mm` (along the mesh's edges), so that the saddle's value is a
// whole level; saddles already held stay where they are. A bump is not made
// where it would turn a vertex inside the disc into an extremum, stop a held
// saddle being one, or bring a neighbour of a held saddle onto its level.
// Returns the level per vertex (-1 for none).
std::vector<int> pin_saddles(const LabelledDisc& disc, const std::vector<Triangle>& tris,
                             Eigen::VectorXd& rows, int bands, double inner_mm, double outer_mm,
                             const std::vector<bool>& candidates, int& pinned);

// ---------------------------------------------------------------------------
// Step 2, slices and strips (band_slices.cpp).

// Each face of `mesh` is a slice: the part of one triangle inside one band
// (between consecutive levels). Its vertices are the disc's vertices, then
// the points where level curves cross the triangles' sides. Slices of one
// band that share a side (not a level curve) make up a strip.
struct BandSlices {
  HalfedgeMesh mesh;
  std::vector<int> band;         // per slice
  std::vector<int> tri;          // per slice: the triangle it is part of
  std::vector<int> level;        // per half-edge: level index of a level-curve side, else -1
  std::vector<int> source_face;  // per half-edge on the disc boundary: disc face, else -1
  std::vector<int> source_side;  // ... and its side
  std::vector<bool> pinned;      // per disc vertex: a saddle of t held on a level

  int num_slices() const { return mesh.num_faces(); }
  int num_halfedges() const { return mesh.num_halfedges(); }
  const Vec3& position(int v) const { return mesh.position(v); }
  int from(int h) const { return mesh.from(h); }
  int to(int h) const { return mesh.to(h); }
  int next(int h) const { return mesh.next(h); }
  int twin(int h) const { return mesh.twin(h); }
  int slice(int h) const { return mesh.face(h); }
  double length(int h) const { return mesh.edge_length(h); }
  bool is_pinned(int v) const { return at(v) < pinned.size() && pinned[at(v)]; }
};

// The triangles cut at the whole levels of t / spacing (levels 1 .. bands-1).
// `pin` holds, per disc vertex, the level a saddle of t is held on (-1 for
// none; empty for no saddles held): such a vertex lies on its level, a
// corner of the slices of both bands, and the level curves through it meet
// there. Slices are numbered triangle by triangle, bottom band first; the
// half-edges of each in counter-clockwise order.
BandSlices slice(const LabelledDisc& disc, const std::vector<Triangle>& tris,
                 const Eigen::VectorXd& t, double spacing, int bands, const std::vector<int>& pin);

// A point to add on a half-edge of the disc boundary: at parameter s from its start.
struct HalfedgeSplit {
  int halfedge = -1;
  double s = 0;
  Vec3 point = Vec3::Zero();
};

// The slices with points added on boundary half-edges (each split half-edge
// becomes two with the same origin; boundary half-edges have no twin).
BandSlices split_halfedges(const BandSlices& in, std::vector<HalfedgeSplit> splits);

// The strips of a slicing, each with its boundary loops: the half-edges on
// a level curve or on the disc boundary, in walk order (the strip on the
// left). A strip is named by its root, its lowest slice.
struct Strips {
  std::vector<int> root;                               // per slice
  std::map<int, std::vector<std::vector<int>>> loops;  // root -> boundary loops
  // Whether a strip has more than one boundary loop (a hole).
  bool has_hole() const;
};
Strips find_strips(const BandSlices& slices);

// ---------------------------------------------------------------------------
// Step 3, chains (chains.cpp).

// Which way a stretch of a strip's boundary runs: along its bottom (course-in
// sides), along its top (course-out sides), or up a row's end (wale sides).
enum class Side : std::uint8_t { Low, High, Wale };

// Consecutive half-edges of a strip's boundary loop of one side and kind.
struct Run {
  Side side = Side::Wale;
  bool level = false;          // a level curve (shared with the next strip), not the disc boundary
  std::vector<int> halfedges;  // in loop order
  double length = 0;
};

// Consecutive runs of one side.
struct Chain {
  Side side = Side::Wale;
  std::vector<Run> runs;
};

double chain_length(const Chain& chain);

// A chain of disc boundary only (no level curve).
bool boundary_only(const Chain& chain);

// Neighbouring boundary runs of a chain are one stretch of boundary: join
// them into one run (level-curve runs stay apart).
void join_boundary_runs(Chain& chain);

// Makes the chains of strips' boundary loops (§6.2): level curves below are
// bottom chains and above top chains; the disc boundary is classified by
// the angle between its outward normal and grad t (facing down: bottom, a
// cast-on; facing up: top, a bind-off; along the rows' ends: a wale side).
// Steps of a jagged cut and folds of the boundary against the rows give way
// to their neighbours, and rows that end in a point on an oblique boundary
// end in a wale side instead (end_rows_in_wale_sides).
class ChainMaker {
 public:
  ChainMaker(const BandSlices& slices, const std::vector<Triangle>& tris,
             const StitchMeshParams& params)
      : slices_(slices), tris_(tris), params_(params) {}

  // The chains of one boundary loop of a strip in `band`, in loop order.
  std::vector<Chain> chains(const std::vector<int>& loop, int band);

  // Row ends made or lengthened by the calls so far.
  int tip_sides() const { return tip_sides_; }
  // Points to add on boundary half-edges so that the row ends found so far
  // can end at a slice vertex (split_halfedges; the chains are then made
  // again).
  const std::vector<HalfedgeSplit>& tip_splits() const { return tip_splits_; }

 private:
  // The loop's half-edges grouped into runs of one side and kind.
  std::vector<Run> loop_runs(const std::vector<int>& loop, int band) const;
  // Wale chains between chains of one kind, jagged steps and folds against
  // the rows give way until each kind is one chain where the loop allows.
  void settle_kinds(std::vector<Chain>& out) const;
  // Short boundary runs at the ends of a course chain beside a wale side
  // join the wale side: a wale edge, not a sliver course edge.
  void short_ends_to_wale_sides(std::vector<Chain>& out) const;
  void end_rows_in_wale_sides(std::vector<Chain>& out);
  // Where boundary run r, walked forward from its front or backward from its
  // back, is row_end_length() from `origin` in a straight line: the number of
  // half-edges before that vertex, or nullopt (a split point to add is
  // recorded in tip_splits_ when the distance is reached inside a half-edge).
  std::optional<std::size_t> cut_at(const Vec3& origin, const Run& r, bool from_front);
  // Takes the stretch from the back of `a` (origin_a: the point its
  // distance is measured from) or the front of `b`, the longer first.
  // Returns the stretch as a wale run, or nullopt.
  std::optional<Run> take_stretch(Chain& a, Chain& b, const Vec3& origin_a, const Vec3& origin_b,
                                  bool& from_b);
  double row_end_length() const { return params_.tip_side_wales * params_.wale_mm; }
  double row_end_tolerance() const { return 0.02 * params_.wale_mm; }

  const BandSlices& slices_;
  const std::vector<Triangle>& tris_;
  const StitchMeshParams& params_;
  int tip_sides_ = 0;
  std::vector<HalfedgeSplit> tip_splits_;
};

// ---------------------------------------------------------------------------
// Steps 3-4, stitch vertices and faces (row_sampling.cpp, zip.cpp, strips.cpp).

// Which ends of a strip of a bottom and b top sides, the chains sharing
// their left and/or right end, get a short-row triangle (§6.3).
std::pair<bool, bool> end_triangles(int a, int b, bool left_shared, bool right_shared);

// A strip's two chains as stitch vertices, both left to right, and the part
// of them still to zip: bottom[i0 .. i1] and top[j0 .. j1], between wale
// sides with the cut-arcs left_arc and right_arc.
struct ZipSpan {
  std::vector<int> bottom;
  std::vector<int> top;
  std::vector<std::int32_t> bottom_arcs;  // per bottom segment
  std::vector<std::int32_t> high_arcs;  // per top segment, in the top chain's (right to left) order
  int top_segments = 0;
  int i0 = 0;
  int j0 = 0;
  int i1 = 0;
  int j1 = 0;
  std::int32_t left_arc = kNoArc;
  std::int32_t right_arc = kNoArc;
  // The cut-arc of top segment j (left to right).
  std::int32_t top_arc(int j) const { return high_arcs[at(top_segments - 1 - j)]; }
};

// Makes the stitch mesh strip by strip (§6.2-6.3): stitch vertices along
// each strip's chains and the faces between them. Strips are given bottom
// row first, so each level curve is sampled by the strip below it and the
// strip above reuses its stitch vertices.
class StripMesher {
 public:
  StripMesher(const LabelledDisc& disc, const StitchMeshParams& params, const BandSlices& slices);

  // Before any strip is zipped: a strip whose bottom is one level curve and
  // whose top needs more sides (one for each run, or the run's own minimum)
  // than twice that curve's sides can feed asks the strip below to sample the
  // curve more finely. Called from the top row down, so a minimum passes
  // down through as many rows as need it.
  void plan_minimums(const std::vector<Chain>& loop);

  // Adds the faces of the strip with these chains (in loop order). `where`
  // names the strip in problems: chains the strip cannot be zipped from.
  void strip(const std::string& where, std::vector<Chain> loop);

  void add_problem(std::string problem) { problems_.push_back(std::move(problem)); }

  // Of the strips so far: lenses_skipped, saddles_split, invalid_faces,
  // boundary_sides and sides_split_below (the other figures are 0).
  const StitchMeshStats& stats() const { return stats_; }
  StitchMesh& mesh() { return mesh_; }
  std::vector<std::string>& problems() { return problems_; }

 private:
  // Row sampling (row_sampling.cpp).
  int stitch_vertex(int slice_vertex);
  std::int32_t arc_of(int h) const;
  // A boundary run's length in straight steps of course_mm: a jagged cut
  // boundary is longer along its edges than across the stitches it holds
  // (docs/stitch-mesh.md, step 3).
  double straight_length(const Run& run) const;
  // Segments of a run `length` long: one per ~course_mm.
  int auto_count(double length) const;
  // Arc length at the end of each half-edge of a polyline (0 first).
  std::vector<double> lengths_along(const std::vector<int>& halfedges) const;
  // The point of a polyline at arc length t.
  Vec3 point_along(const std::vector<int>& halfedges, const std::vector<double>& along,
                   double t) const;
  // Arc lengths of the points of a walk along a polyline that steps `step`
  // in a straight line each time from its start.
  std::vector<double> straight_walk(const std::vector<int>& halfedges,
                                    const std::vector<double>& along, double step) const;
  // Arc lengths of the n - 1 inner points of a boundary run cut into n
  // straight sides as close to course_mm as can be: fewest sides off by more
  // than 15%, then the least squared relative deviation (dynamic programming
  // over points every course_mm / 16 along the run). A jagged or folded cut
  // boundary is longer along its edges than across the stitches it holds:
  // the sides are its chords (docs/stitch-mesh.md, step 3).
  std::vector<double> straight_sides(const std::vector<int>& halfedges,
                                     const std::vector<double>& along, int n) const;
  // Stitch vertices along a run, n segments (arcs[i] for segment i): evenly
  // along it, or with `straight` (a boundary run) in n straight sides as
  // close to course_mm as can be (straight_sides), so the stitches along a
  // jagged boundary are as wide as the others.
  std::vector<int> sample(const std::vector<int>& halfedges, std::vector<std::int32_t>* arcs, int n,
                          bool straight = false);
  std::uint64_t undirected(int h) const;
  // A level curve is sampled once (by the strip below it, with n segments);
  // the strip above reuses the samples.
  const std::vector<int>* sampled_curve(const Run& run) const;
  std::vector<int> level_samples(const Run& run, int n);
  // Fewest segments a run may have: one, or for a level curve what the strip
  // above it needs (plan_minimums).
  int minimum(const Run& run) const;
  // Segments per run of a chain: fixed for level curves sampled already,
  // else ~length / course_mm.
  std::vector<int> run_counts(const Chain& chain) const;
  // Changes the free runs' counts (not fixed ones) so they sum to `total`
  // where possible, in proportion to their length; each keeps its minimum.
  void rescale(const Chain& chain, const std::vector<bool>& fixed, std::vector<int>& counts,
               int total) const;
  std::vector<bool> fixed_runs(const Chain& chain) const;
  // Vertices of a course chain and the arcs of its segments.
  std::vector<int> chain_vertices(const Chain& chain, const std::vector<int>& counts,
                                  std::vector<std::int32_t>& arcs,
                                  std::vector<bool>* on_level = nullptr);

  // Zipping (zip.cpp).
  void add_face(std::vector<int> vertices, std::vector<EdgeRole> roles,
                std::vector<std::int32_t> arcs);
  std::int32_t wale_arc(const Chain& chain) const;
  // Sides taken from the bottom and top chain by each face between the wale
  // sides (l[i0], t[j0]) and (l[i1], t[j1]). Each step is (1, 1), (2, 1) or
  // (1, 2) when the chains allow it (neither more than twice the other);
  // otherwise the counts are spread evenly and the faces come out invalid.
  std::vector<std::pair<int, int>> zip_steps(const std::vector<int>& l, const std::vector<int>& t,
                                             int i0, int j0, int i1, int j1, bool left_boundary,
                                             bool right_boundary) const;
  // The faces of a strip of one bottom and one top chain with these segment
  // counts, between the wale chains (nullptr where the chains share an end):
  // short-row triangles at shared ends, then the zip.
  void zip_strip(const Chain& low, const Chain& high, const Chain* left_wale,
                 const Chain* right_wale, const std::vector<int>& low_counts,
                 const std::vector<int>& high_counts);
  // Nothing valid fits: one face with all that is left, reported by check.
  void add_leftover_face(const ZipSpan& z);
  // Zip (§6.3): faces with one or two sides on each chain (knit, decrease,
  // increase), chosen by dynamic programming so wale sides are as close to
  // wale_mm as possible and pentagons are used only where rows change length.
  void add_zipped_faces(const ZipSpan& z, bool left_boundary, bool right_boundary);

  // Strips (strips.cpp).
  // Brings the loop to one bottom and one top chain where it can; otherwise
  // splits it round saddles (split_folds) or reports it, and returns false.
  bool one_bottom_and_top(const std::string& where, std::vector<Chain>& loop);
  // Segment counts: the zip needs, after the end triangles of `shared`
  // ends, either nothing left or one chain at most twice the other (§6.3).
  void fit_counts(const Chain& low, const Chain& high, int shared, std::vector<int>& low_counts,
                  std::vector<int>& high_counts) const;
  // A strip around saddles of the row time (m >= 2 bottom and m top chains,
  // alternating; X-shaped for one saddle): one wale edge between two corners
  // two course chains apart (a corner is where a bottom and a top chain
  // meet) cuts off a simple strip of the two chains between them, and leaves
  // m - 1 pairs. A side chain at such a corner is first joined to the
  // bottom chain there (cast-on stitches), so the corner is a point. Of the
  // 2m possible edges the one of least cost is used; the rest is split again.
  // The cost is the edge's length plus, for each of the two strips it makes,
  // kSplitBalance wales per unit of |ln(bottom / top)|: a strip whose bottom
  // is much longer or shorter than its top is zipped with a run of decreases
  // or increases whose wale sides fan out across it (docs/stitch-mesh.md,
  // "Saddle splits"), so the split pairs chains of like length where the
  // edges differ little.
  bool split_folds(const std::string& where, std::vector<Chain> loop);
  // A decrease whose course-out side was split at `middle` (two sides in,
  // two out) becomes two knit stitches sharing a wale edge.
  void split_decrease(std::size_t index, int middle);
  // Splits the longest side of a fixed bottom chain whose face below is a
  // knit stitch (it becomes an increase, §6.3) or a decrease (it becomes two
  // knit stitches), or that has no face below (a cast-on side, possibly
  // under glued lenses: one more stitch is cast on), so the bottom chain has
  // one more side. False when no side qualifies.
  bool split_side_below(const Chain& low);

  const LabelledDisc& disc_;
  const StitchMeshParams& params_;
  const BandSlices& slices_;
  StitchMesh mesh_;
  std::unordered_map<int, int> anchor_;  // slice vertex -> stitch vertex
  // Level curve (by any of its undirected slice edges) -> its stitch vertices
  // in the order of the first strip that sampled it, and that order's first slice vertex.
  std::unordered_map<std::uint64_t, int> curve_of_edge_;
  std::vector<std::vector<int>> curve_samples_;
  std::vector<int> curve_first_;
  std::vector<std::string> problems_;
  StitchMeshStats stats_;
  // Bottom sides (as the row above walks them) of increases and decreases.
  std::unordered_set<std::uint64_t> shaped_below_;
  // Course-out sides (as the row above walks them) -> the face below.
  std::unordered_map<std::uint64_t, std::size_t> face_below_;
  // Level curve (by any of its undirected slice edges) -> fewest segments.
  std::unordered_map<std::uint64_t, int> min_segments_;
};

// ---------------------------------------------------------------------------
// Step 5 (relax.cpp).

// Step 5, relaxing (docs/stitch-mesh.md): the stitch vertices inside the
// sheet move over the cut mesh so that the sides come closer to their
// target lengths, course or wale; the boundary's vertices stay. Each sweep
// moves each inner vertex to where its sides, as springs of their target
// lengths, would hold it (each weighted by 1 / target^2, and less the
// farther it is off, so a fan's chord across a hole does not drag the
// sheet), then onto the nearest point of the surface. A move that turns an
// incident face over is not made. The faces and their types do not change.
// Returns the number of sweeps made.
int relax_positions(StitchMesh& mesh, const LabelledDisc& disc, int sweeps);

}  // namespace planner::stitch_meshing
