// The strip-off simulation of the wearability test (§5, §8.2).
//
// The garment is a mass-spring system solved with position-based dynamics
// (Müller et al. 2007, the method behind the paper's NVIDIA Flex): one unit
// mass per vertex; stretch springs on every edge, shear springs on both
// diagonals of every quad, bend springs between every other vertex along the
// wale and course lines (two quads sharing an edge); no inextensibility
// constraint, because knit fabric stretches (§8.2). The wearer is a rigid
// signed distance field; garment vertices and edge midpoints are kept at
// least `clearance` away from it.
//
// Two stripping forces act on every vertex (§5, Fig. 6): the local force
// along the field's gradient with magnitude ∝ 1/d², and the global force of
// constant magnitude along an axis direction (±x, ±y, ±z) that changes to a
// different random axis direction every `switch_steps` steps (§8.2). The test
// succeeds once every vertex is at least `success_distance` from the wearer
// and fails when `max_steps` pass first, or earlier once it stops making
// progress (ClothParams::stall_switches).
//
// All lengths in ClothParams are fractions of the wearer's scale (the
// diagonal of its bounding box, SignedDistanceField::scale()), times in
// seconds, accelerations in scale/s², so one set of defaults serves meshes in
// any unit.
//
// Deterministic: the same garment, wearer, parameters and seed give the same
// trajectory bit for bit, whatever the thread count — springs are projected in
// colour classes whose members share no vertex, so the order within a class
// cannot matter.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "simulators/cloth/polygon_mesh.hpp"
#include "simulators/cloth/sdf.hpp"

namespace cloth {

// The garment is a PolygonMesh with its open cuts already split (vertices on
// either side of an open cut are distinct).

enum class SpringKind : std::uint8_t { Stretch, Shear, Bend };

struct Spring {
  int a = 0, b = 0;
  double rest_length = 0;
  SpringKind kind = SpringKind::Stretch;
};

// §8.2: stretch springs on edges, shear on quad diagonals, bend across pairs
// of quads sharing an edge (the vertex before and after along a wale or
// course line). Rest lengths are the current distances. Each vertex pair
// appears once (the strongest kind wins). Throws std::invalid_argument on a
// face index out of range.
std::vector<Spring> build_springs(const PolygonMesh& mesh);

struct ClothParams {
  // Step size. 10 ms with the velocity cap below lets a vertex cross at most
  // half the clearance per step, so it cannot tunnel through the wearer.
  double time_step_s = 0.01;
  // Constraint iterations per step. Stiffnesses are corrected for the count
  // (k' = 1 - (1 - k)^(1/n), Müller et al. 2007), so changing it changes
  // convergence, not the material.
  int iterations = 6;
  // Per-step PBD stiffness in [0, 1] of the three spring kinds (§8.2:
  // "manually set"). Stretch is stiff enough that a garment stretches by
  // tens of percent under the forces below, as knit does, but not so soft
  // that a ring of cloth slides over a solid; shear and bend are weaker, as
  // knit fabric shears and bends easily.
  double stretch_stiffness = 0.9;
  double shear_stiffness = 0.3;
  double bend_stiffness = 0.1;
  // Fraction of the velocity removed each step (air drag); keeps the cloth
  // from ringing after the global force switches.
  double damping = 0.02;
  // Collision thickness: the least distance kept between garment and wearer.
  double clearance = 0.012;
  // Velocity cap as displacement per step, in clearances (anti-tunnelling).
  double max_step_clearances = 0.5;
  // Local force (§5): acceleration local_acceleration * (clearance / d)²
  // along the gradient, with d floored at half the clearance.
  double local_acceleration = 2.0;
  // Global force (§5, §8.2): constant magnitude, axis-aligned direction
  // switched every switch_steps steps (the paper's 300).
  double global_acceleration = 3.0;
  int switch_steps = 300;
  // Success once every vertex is this far from the wearer.
  double success_distance = 0.05;
  // Failure after this many steps (§5: a fixed span of simulated time). The
  // paper's Fig. 20 saturates at 1800 iterations; 3000 = 10 direction
  // switches leaves margin.
  int max_steps = 3000;
  // Success is checked every this many steps.
  int check_every = 10;
  // A trial stops as a failure before max_steps when it has stopped making
  // progress for this many direction switches in a row (0 = never): neither
  // fewer vertices within success_distance (by at least 1 % of them) nor its
  // centroid farther from where it started (by at least a clearance) than at
  // any earlier switch. Stopping early can only turn a success into a
  // failure, so the test stays conservative.
  int stall_switches = 3;
  // Threads for one simulation (0: OMP_NUM_THREADS, else all hardware threads).
  int threads = 1;
};

struct StripResult {
  bool success = false;
  int steps = 0;                  // steps simulated
  bool stalled = false;           // stopped early for lack of progress (stall_switches)
  double min_distance = 0;        // least vertex distance to the wearer at the end, in scale units
  std::uint64_t projections = 0;  // spring and collision projections done
  // At the end of a trial that failed: the garment's vertices still nearer
  // the wearer than success asks (the success distance), and their centroid
  // (where the garment is caught).
  int caught = 0;
  Vec3 caught_at = Vec3::Zero();
  double caught_radius = 0;  // the farthest of them from their centroid
};

// The global force directions of one trial: axis indices 0..5 (+x, -x, +y,
// -y, +z, -z), each different from the one before, drawn from `seed`.
std::vector<int> global_directions(std::uint64_t seed, int count);
Vec3 axis_direction(int axis);

class ClothSimulation {
 public:
  // The rest shape is `garment` as given; positions are taken from it.
  ClothSimulation(const PolygonMesh& garment, const SignedDistanceField& wearer,
                  const ClothParams& params);

  // One time step with the global force along `global_axis` (0..5).
  void step(int global_axis);
  // The whole trial: global directions from `seed`; `observer` (optional)
  // sees the state after every step and may stop the run by returning false
  // (the result then says failure).
  StripResult run(std::uint64_t seed,
                  const std::function<bool(int step, const ClothSimulation&)>& observer = {});

  // Least distance of any vertex to the wearer (mesh units).
  double min_distance() const;
  // Whether every vertex is at least `distance` (mesh units) from the
  // wearer: min_distance() >= distance, but it stops at the first vertex
  // that is nearer, which is the first one looked at while the garment is on.
  bool all_farther_than(double distance) const;
  // How many vertices are nearer than `distance` (mesh units) to the wearer.
  int count_nearer_than(double distance) const;
  Vec3 centroid() const;
  const std::vector<Vec3>& positions() const { return x_; }
  const std::vector<Spring>& springs() const { return springs_; }
  const PolygonMesh& mesh() const { return mesh_; }
  std::uint64_t projections() const { return projections_; }

 public:
  // The springs of one pass, as the step reads them: colour classes one
  // after the other, each sorted by vertex (memory order).
  struct SpringArrays {
    std::vector<int> a, b;
    std::vector<double> rest_length;
    std::vector<double> half_stiffness;  // 0.5 × the per-iteration stiffness
    std::vector<int> colour_begin;       // class c is [colour_begin[c], colour_begin[c+1])
  };

 private:
  // Which part of each loop the calling thread takes (one thread: all).
  struct Share {
    int index = 0, count = 1;
  };

  PolygonMesh mesh_;
  const SignedDistanceField& wearer_;
  ClothParams params_;
  double scale_ = 1.0;
  std::vector<Spring> springs_;  // sorted by colour
  SpringArrays pass_;            // springs_, for the constraint iterations
  SpringArrays edges_;           // the stretch springs, for the edge collision
  std::vector<Vec3> x_, v_, p_;
  std::vector<Vec3> contact_normal_;    // per vertex, this step's contact plane:
  std::vector<double> contact_offset_;  // distance(p) ≈ offset + normal·p
  // The field at x_[i], when the last exact vertex collision looked it up
  // there and did not move the vertex: the next step starts from it instead
  // of a second, identical lookup.
  std::vector<char> lookup_valid_;
  std::vector<double> lookup_distance_;
  std::vector<Vec3> lookup_normal_;
  std::uint64_t projections_ = 0;
  mutable std::size_t nearest_hint_ = 0;  // all_farther_than's first vertex to look at
  double plane_distance(int i) const { return contact_offset_[i] + contact_normal_[i].dot(p_[i]); }
  // springs[chosen[i]] for every i, class by class as `colour_begin` splits
  // `chosen`, with the kinds' per-iteration `stiffness`.
  static SpringArrays arrange(const std::vector<Spring>& springs, std::vector<int> chosen,
                              const std::vector<int>& colour_begin,
                              const std::array<double, 3>& stiffness);
  void step_share(int global_axis, Share share);
};

// Pushes every vertex of `mesh` out of the wearer until it is `clearance`
// (a fraction of the wearer's scale) away: a garment modelled on the
// wearer's own surface starts just outside it.
void dress(PolygonMesh& mesh, const SignedDistanceField& wearer, double clearance);

}  // namespace cloth
