#include "simulators/cloth/cloth.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "simulators/cloth/parallel.hpp"

namespace cloth {

namespace {

std::uint64_t pair_key(int a, int b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b));
  const auto hi = static_cast<std::uint32_t>(std::max(a, b));
  return (static_cast<std::uint64_t>(lo) << 32) | hi;
}

std::uint64_t directed_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
         static_cast<std::uint32_t>(b);
}

// Greedy colouring of vertex pairs: no two pairs of one colour share a
// vertex, so a colour class can be projected in parallel, in any order, with
// the same result. Returns the items reordered by colour and the class starts.
void colour_pairs(std::size_t vertex_count, const std::vector<std::array<int, 2>>& pairs,
                  std::vector<int>& order, std::vector<int>& begin) {
  std::vector<std::vector<bool>> used(vertex_count);
  std::vector<int> colour(pairs.size());
  int colours = 0;
  for (std::size_t s = 0; s < pairs.size(); ++s) {
    auto& ua = used[pairs[s][0]];
    auto& ub = used[pairs[s][1]];
    int c = 0;
    while ((c < static_cast<int>(ua.size()) && ua[c]) ||
           (c < static_cast<int>(ub.size()) && ub[c])) {
      ++c;
    }
    if (static_cast<int>(ua.size()) <= c) ua.resize(c + 1, false);
    if (static_cast<int>(ub.size()) <= c) ub.resize(c + 1, false);
    ua[c] = ub[c] = true;
    colour[s] = c;
    colours = std::max(colours, c + 1);
  }
  begin.assign(colours + 1, 0);
  for (int c : colour) ++begin[c + 1];
  for (int c = 0; c < colours; ++c) begin[c + 1] += begin[c];
  order.assign(pairs.size(), 0);
  std::vector<int> next(begin.begin(), begin.end() - 1);
  for (std::size_t s = 0; s < pairs.size(); ++s) order[next[colour[s]]++] = static_cast<int>(s);
}

}  // namespace

// Within a class (no shared vertex, so the order cannot change the result)
// the springs are sorted by vertex, so a pass reads the positions in memory
// order.
ClothSimulation::SpringArrays ClothSimulation::arrange(const std::vector<Spring>& springs,
                                                       std::vector<int> chosen,
                                                       const std::vector<int>& colour_begin,
                                                       const std::array<double, 3>& stiffness) {
  SpringArrays arrays;
  arrays.colour_begin = colour_begin;
  for (std::size_t c = 0; c + 1 < colour_begin.size(); ++c) {
    std::sort(chosen.begin() + colour_begin[c], chosen.begin() + colour_begin[c + 1],
              [&](int x, int y) {
                const Spring &sx = springs[x], &sy = springs[y];
                return std::min(sx.a, sx.b) < std::min(sy.a, sy.b) ||
                       (std::min(sx.a, sx.b) == std::min(sy.a, sy.b) && x < y);
              });
  }
  for (int index : chosen) {
    const Spring& s = springs[index];
    arrays.a.push_back(s.a);
    arrays.b.push_back(s.b);
    arrays.rest_length.push_back(s.rest_length);
    arrays.half_stiffness.push_back(0.5 * stiffness[static_cast<int>(s.kind)]);
  }
  return arrays;
}

std::vector<Spring> build_springs(const PolygonMesh& mesh) {
  const int n = static_cast<int>(mesh.positions.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (mesh.faces[f].size() < 3) {
      throw std::invalid_argument("garment face " + std::to_string(f) +
                                  " has fewer than 3 vertices");
    }
    for (int v : mesh.faces[f]) {
      if (v < 0 || v >= n) {
        throw std::invalid_argument("garment face " + std::to_string(f) + " refers to vertex " +
                                    std::to_string(v) + " of " + std::to_string(n));
      }
    }
  }
  std::vector<Spring> springs;
  std::unordered_map<std::uint64_t, std::size_t> seen;
  auto add = [&](int a, int b, SpringKind kind) {
    if (a == b) return;
    const auto [it, inserted] = seen.emplace(pair_key(a, b), springs.size());
    if (!inserted) return;  // kinds are added strongest first
    springs.push_back({a, b, (mesh.positions[a] - mesh.positions[b]).norm(), kind});
  };
  for (const auto& face : mesh.faces) {
    for (std::size_t i = 0; i < face.size(); ++i)
      add(face[i], face[(i + 1) % face.size()], SpringKind::Stretch);
  }
  for (const auto& face : mesh.faces) {
    if (face.size() != 4) continue;
    add(face[0], face[2], SpringKind::Shear);
    add(face[1], face[3], SpringKind::Shear);
  }
  // Bend: a quad a→b→c… and the quad across its edge (b, c) (which holds the
  // half-edge c→b followed by b→x): a, b, x lie on one wale or course line
  // through b, and a–x joins every other vertex along it.
  std::unordered_map<std::uint64_t, std::array<int, 2>> half_edges;  // (from,to) → (face, corner)
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      half_edges[directed_key(face[i], face[(i + 1) % face.size()])] = {static_cast<int>(f),
                                                                        static_cast<int>(i)};
    }
  }
  for (const auto& face : mesh.faces) {
    if (face.size() != 4) continue;
    for (std::size_t i = 0; i < 4; ++i) {
      const int a = face[i], b = face[(i + 1) % 4], c = face[(i + 2) % 4];
      const auto across = half_edges.find(directed_key(c, b));
      if (across == half_edges.end()) continue;
      const auto& other = mesh.faces[across->second[0]];
      if (other.size() != 4) continue;
      const int x = other[(across->second[1] + 2) % 4];  // c→b→x
      add(a, x, SpringKind::Bend);
    }
  }
  return springs;
}

Vec3 axis_direction(int axis) {
  Vec3 d = Vec3::Zero();
  d[axis / 2] = (axis % 2 == 0) ? 1.0 : -1.0;
  return d;
}

std::vector<int> global_directions(std::uint64_t seed, int count) {
  // mt19937_64's output sequence is fixed by the standard; the mapping to
  // axes uses plain modulo so no library's distribution can change it.
  std::mt19937_64 random(seed);
  std::vector<int> axes;
  int previous = -1;
  for (int i = 0; i < count; ++i) {
    int axis = static_cast<int>(random() % 6);
    if (axis == previous) axis = (axis + 1 + static_cast<int>(random() % 5)) % 6;
    axes.push_back(axis);
    previous = axis;
  }
  return axes;
}

ClothSimulation::ClothSimulation(const PolygonMesh& garment, const SignedDistanceField& wearer,
                                 const ClothParams& params)
    : mesh_(garment), wearer_(wearer), params_(params), scale_(wearer.scale()) {
  if (params_.iterations < 1) throw std::invalid_argument("iterations must be at least 1");
  if (params_.time_step_s <= 0) throw std::invalid_argument("time step must be positive");
  auto springs = build_springs(mesh_);
  std::vector<std::array<int, 2>> pairs;
  for (const auto& s : springs) pairs.push_back({s.a, s.b});
  std::vector<int> order, colour_begin;
  colour_pairs(mesh_.positions.size(), pairs, order, colour_begin);
  springs_.reserve(springs.size());
  for (int s : order) springs_.push_back(springs[s]);

  const double iterations = params_.iterations;
  auto per_iteration = [&](double k) {
    return 1.0 - std::pow(1.0 - std::clamp(k, 0.0, 1.0), 1.0 / iterations);
  };
  const std::array<double, 3> stiffness = {per_iteration(params_.stretch_stiffness),
                                           per_iteration(params_.shear_stiffness),
                                           per_iteration(params_.bend_stiffness)};
  std::vector<int> all(springs_.size());
  for (std::size_t s = 0; s < all.size(); ++s) all[s] = static_cast<int>(s);
  pass_ = arrange(springs_, all, colour_begin, stiffness);

  pairs.clear();
  std::vector<int> stretch;
  for (std::size_t s = 0; s < springs_.size(); ++s) {
    if (springs_[s].kind == SpringKind::Stretch) {
      stretch.push_back(static_cast<int>(s));
      pairs.push_back({springs_[s].a, springs_[s].b});
    }
  }
  colour_pairs(mesh_.positions.size(), pairs, order, colour_begin);
  std::vector<int> edges;
  for (int s : order) edges.push_back(stretch[s]);
  edges_ = arrange(springs_, edges, colour_begin, stiffness);

  x_ = mesh_.positions;
  v_.assign(x_.size(), Vec3::Zero());
  p_ = x_;
  contact_normal_.assign(x_.size(), Vec3::Zero());
  contact_offset_.assign(x_.size(), 0.0);
  lookup_valid_.assign(x_.size(), 0);
  lookup_distance_.assign(x_.size(), 0.0);
  lookup_normal_.assign(x_.size(), Vec3::Zero());
}

namespace {

// [first, last) of `n` items: the `index`-th of `count` nearly equal parts.
std::pair<int, int> part(int n, int index, int count) {
  const auto share = [&](int k) { return static_cast<int>(static_cast<long long>(n) * k / count); };
  return {share(index), share(index + 1)};
}

// PBD projection of springs [first, last), which share no vertex (Müller et
// al. 2007): each end moves half the correction. Springs go kLanes at a
// time through the square root and the division, which are the slowest
// operations of a step and run as fast on a vector of lanes as on one
// number; the result is the same as one spring at a time.
void project_springs(const ClothSimulation::SpringArrays& springs, int first, int last, Vec3* p) {
  const int* a = springs.a.data();
  const int* b = springs.b.data();
  const double* rest = springs.rest_length.data();
  const double* half_k = springs.half_stiffness.data();
  int s = first;
  for (; s + 2 <= last; s += 2) {
    const Vec3 d0 = p[b[s]] - p[a[s]];
    const Vec3 d1 = p[b[s + 1]] - p[a[s + 1]];
    // Built from registers: a vector loaded from two separate stores would
    // wait for them to reach the cache.
    const Eigen::Array2d length = Eigen::Array2d(d0.squaredNorm(), d1.squaredNorm()).sqrt();
    const Eigen::Array2d factor = Eigen::Array2d(half_k[s], half_k[s + 1]) *
                                  (length - Eigen::Array2d(rest[s], rest[s + 1])) / length;
    if (length[0] > 1e-300) {
      const Vec3 correction = factor[0] * d0;
      p[a[s]] += correction;
      p[b[s]] -= correction;
    }
    if (length[1] > 1e-300) {
      const Vec3 correction = factor[1] * d1;
      p[a[s + 1]] += correction;
      p[b[s + 1]] -= correction;
    }
  }
  for (; s < last; ++s) {
    const Vec3 d = p[b[s]] - p[a[s]];
    const double length = d.norm();
    if (length <= 1e-300) continue;
    const Vec3 correction = (half_k[s] * (length - rest[s]) / length) * d;
    p[a[s]] += correction;
    p[b[s]] -= correction;
  }
}

// Every thread of the step's team waits here for the others.
void wait_for_team(int count) {
  if (count > 1) {
#pragma omp barrier
  }
}

}  // namespace

void ClothSimulation::step(int global_axis) {
  const int threads = resolve_threads(params_.threads);
  if (threads <= 1) {
    step_share(global_axis, {});
  } else {
    // One parallel region for the whole step: a barrier after each loop
    // whose results the next one reads, instead of a region per loop.
#pragma omp parallel num_threads(threads)
    step_share(global_axis, {omp_get_thread_num(), omp_get_num_threads()});
  }
  projections_ += static_cast<std::uint64_t>(params_.iterations) * (pass_.a.size() + x_.size()) +
                  edges_.a.size() + x_.size();
}

// The step, on the part of every loop that falls to `share` (each loop is
// split evenly between the threads; a spring loop runs over one colour class
// at a time, whose springs share no vertex). Every item is computed the same
// way whichever thread takes it, so the result does not depend on the number
// of threads.
void ClothSimulation::step_share(int global_axis, Share share) {
  const double dt = params_.time_step_s;
  const double clearance = params_.clearance * scale_;
  const double max_move = params_.max_step_clearances * clearance;
  const double damping = 1.0 - std::clamp(params_.damping, 0.0, 1.0);
  const Vec3 global = axis_direction(global_axis) * (params_.global_acceleration * scale_);
  const double local = params_.local_acceleration * scale_;
  const auto [first, last] = part(static_cast<int>(x_.size()), share.index, share.count);

  for (int i = first; i < last; ++i) {
    Vec3 normal;
    double distance;
    if (lookup_valid_[i] != 0) {
      distance = lookup_distance_[i];
      normal = lookup_normal_[i];
      lookup_valid_[i] = 0;
    } else {
      distance = wearer_.value_and_gradient(x_[i], normal);
    }
    // The field near x, linearised: the contact plane of this step. A vertex
    // moves at most max_move per step, so the plane stays accurate, and the
    // iterations below need no further field lookups.
    contact_normal_[i] = normal;
    contact_offset_[i] = distance - normal.dot(x_[i]);
    // §5: local force along the distance gradient, magnitude ∝ 1/d².
    const double d = std::max(distance, 0.5 * clearance);
    const double ratio = clearance / d;
    const Vec3 acceleration = global + normal * (local * ratio * ratio);
    Vec3 velocity = damping * v_[i] + dt * acceleration;
    const double move = velocity.norm() * dt;
    if (move > max_move) velocity *= max_move / move;
    v_[i] = velocity;
    p_[i] = x_[i] + dt * velocity;
  }
  wait_for_team(share.count);

  for (int iteration = 0; iteration < params_.iterations; ++iteration) {
    for (std::size_t c = 0; c + 1 < pass_.colour_begin.size(); ++c) {
      const int begin = pass_.colour_begin[c];
      const auto [from, to] = part(pass_.colour_begin[c + 1] - begin, share.index, share.count);
      project_springs(pass_, begin + from, begin + to, p_.data());
      wait_for_team(share.count);
    }
    for (int i = first; i < last; ++i) {
      const double d = contact_offset_[i] + contact_normal_[i].dot(p_[i]);
      if (d < clearance) p_[i] += (clearance - d) * contact_normal_[i];
    }
    wait_for_team(share.count);
  }

  // Exact collision at the end of the step: edge midpoints, then vertices
  // against the field itself, so no vertex ends a step inside the wearer.
  // Vertices alone would let a stretched edge cut through a thin part of the
  // wearer (a ring of cloth slipping off a torus between two vertices), so
  // edge midpoints collide too, moving both ends.
  for (std::size_t c = 0; c + 1 < edges_.colour_begin.size(); ++c) {
    const int begin = edges_.colour_begin[c];
    const auto [from, to] = part(edges_.colour_begin[c + 1] - begin, share.index, share.count);
    for (int e = begin + from; e < begin + to; ++e) {
      const int a = edges_.a[e], b = edges_.b[e];
      // The interpolated field changes by at most √3 per unit length, so a
      // midpoint whose ends are far enough cannot touch: skip the lookup.
      const double half = 0.5 * (p_[a] - p_[b]).norm();
      if (std::min(plane_distance(a), plane_distance(b)) > clearance + 1.75 * half) continue;
      const Vec3 mid = 0.5 * (p_[a] + p_[b]);
      // Most midpoints that are looked at are clear: the gradient only
      // for those that are pushed.
      const double d = wearer_.value(mid);
      if (d < clearance) {
        Vec3 normal;
        wearer_.value_and_gradient(mid, normal);
        const Vec3 push = (clearance - d) * normal;
        p_[a] += push;
        p_[b] += push;
      }
    }
    wait_for_team(share.count);
  }

  for (int i = first; i < last; ++i) {
    // Far from the wearer by the contact plane: no lookup needed.
    if (plane_distance(i) <= 2 * clearance) {
      Vec3 normal;
      const double d = wearer_.value_and_gradient(p_[i], normal);
      if (d < clearance) {
        p_[i] += (clearance - d) * normal;
      } else {
        // Not moved: p_[i] becomes x_[i] as it is, so the next step's
        // lookup there would return exactly this.
        lookup_valid_[i] = 1;
        lookup_distance_[i] = d;
        lookup_normal_[i] = normal;
      }
    }
    Vec3 velocity = (p_[i] - x_[i]) / dt;
    const double move = velocity.norm() * dt;
    if (move > max_move) velocity *= max_move / move;
    v_[i] = velocity;
    x_[i] = p_[i];
  }
}

double ClothSimulation::min_distance() const {
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3& x : x_) best = std::min(best, wearer_.value(x));
  return best;
}

bool ClothSimulation::all_farther_than(double distance) const {
  // The vertex that was nearest at the last check is looked at first: while
  // the garment is on, one lookup usually settles it.
  if (!x_.empty() && wearer_.value(x_[nearest_hint_]) < distance) return false;
  for (std::size_t i = 0; i < x_.size(); ++i) {
    if (wearer_.value(x_[i]) < distance) {
      nearest_hint_ = i;
      return false;
    }
  }
  return true;
}

int ClothSimulation::count_nearer_than(double distance) const {
  int near = 0;
  for (const Vec3& x : x_) near += wearer_.value(x) < distance;
  return near;
}

Vec3 ClothSimulation::centroid() const {
  Vec3 sum = Vec3::Zero();
  for (const Vec3& x : x_) sum += x;
  return x_.empty() ? sum : Vec3(sum / static_cast<double>(x_.size()));
}

StripResult ClothSimulation::run(
    std::uint64_t seed, const std::function<bool(int step, const ClothSimulation&)>& observer) {
  const int switch_steps = std::max(params_.switch_steps, 1);
  const auto axes = global_directions(seed, params_.max_steps / switch_steps + 1);
  const double goal = params_.success_distance * scale_;
  const int check_every = std::max(params_.check_every, 1);
  StripResult result;
  // Progress, looked at every direction switch: the fewest vertices near the
  // wearer and the farthest the centroid has moved, so far.
  const Vec3 start = centroid();
  const int margin = std::max(1, static_cast<int>(x_.size()) / 100);
  int fewest_near = std::numeric_limits<int>::max();
  double farthest = 0;
  int idle_switches = 0;
  for (int s = 0; s < params_.max_steps; ++s) {
    step(axes[s / switch_steps]);
    result.steps = s + 1;
    if (observer && !observer(s + 1, *this)) break;
    if ((s + 1) % check_every == 0 && all_farther_than(goal)) {
      result.success = true;
      break;
    }
    if (params_.stall_switches > 0 && (s + 1) % switch_steps == 0) {
      const int near = count_nearer_than(goal);
      const double moved = (centroid() - start).norm();
      bool progress = false;
      if (fewest_near == std::numeric_limits<int>::max() || near <= fewest_near - margin) {
        fewest_near = std::min(fewest_near, near);
        progress = true;
      }
      if (moved >= farthest + params_.clearance * scale_) {
        farthest = moved;
        progress = true;
      }
      idle_switches = progress ? 0 : idle_switches + 1;
      if (idle_switches >= params_.stall_switches) {
        result.stalled = true;
        break;
      }
    }
  }
  result.min_distance = min_distance();
  result.projections = projections_;
  if (!result.success) {
    std::vector<Vec3> caught;
    for (const Vec3& x : x_) {
      if (wearer_.value(x) < goal) caught.push_back(x);
    }
    result.caught = static_cast<int>(caught.size());
    for (const Vec3& x : caught) result.caught_at += x;
    if (!caught.empty()) result.caught_at /= result.caught;
    for (const Vec3& x : caught) {
      result.caught_radius = std::max(result.caught_radius, (x - result.caught_at).norm());
    }
  }
  return result;
}

void dress(PolygonMesh& mesh, const SignedDistanceField& wearer, double clearance) {
  const double target = clearance * wearer.scale();
  for (Vec3& x : mesh.positions) {
    // The gradient of an interpolated field is only approximately the
    // direction to the surface, so a few steps are taken.
    for (int attempt = 0; attempt < 8; ++attempt) {
      Vec3 normal;
      const double d = wearer.value_and_gradient(x, normal);
      if (d >= target) break;
      x += (target - d + 1e-6 * wearer.scale()) * normal;
    }
  }
}

}  // namespace cloth
