#include "planner/wearability/wearability.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <random>
#include <stdexcept>
#include <unordered_map>

#include "planner/common/union_find.hpp"
#include "planner/mesh/soup.hpp"
#include "planner/wearability/linking.hpp"
#include "simulators/cloth/parallel.hpp"

namespace planner {

namespace {

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint32_t>(std::min(a, b));
  const auto hi = static_cast<std::uint32_t>(std::max(a, b));
  return (static_cast<std::uint64_t>(lo) << 32) | hi;
}

// SplitMix64: decorrelates the seeds of runs, tests and trials derived from
// one user seed.
constexpr std::uint64_t mix(std::uint64_t x) {
  return mix64(x);
}
std::uint64_t derive(std::uint64_t seed, std::uint64_t a, std::uint64_t b = 0) {
  return mix(mix(mix(seed) ^ a) ^ (b * 0x632BE59BD9B4E019ULL));
}

// Fisher–Yates with modulo draws: the permutation depends only on the seed,
// not on the standard library's shuffle.
std::vector<int> random_order(int n, std::uint64_t seed) {
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::mt19937_64 random(seed);
  for (int i = n - 1; i > 0; --i) std::swap(order[i], order[random() % (i + 1)]);
  return order;
}

}  // namespace

std::uint64_t fingerprint(const CoverMesh& mesh) {
  std::string bytes;
  auto put = [&](const void* data, std::size_t size) {
    bytes.append(static_cast<const char*>(data), size);
  };
  for (const Vec3& v : mesh.positions) {
    const double xyz[3] = {v.x(), v.y(), v.z()};
    put(xyz, sizeof xyz);
  }
  for (const auto& face : mesh.faces) {
    const int size = static_cast<int>(face.size());
    put(&size, sizeof size);
    put(face.data(), face.size() * sizeof(int));
  }
  for (const auto& arc : mesh.arcs) {
    const int size = static_cast<int>(arc.edges.size());
    put(&size, sizeof size);
    for (const auto& edge : arc.edges) put(edge.data(), sizeof(int) * 2);
  }
  return fingerprint(bytes, 0x434F564552);
}

std::uint64_t test_key(std::uint64_t garment, const std::vector<bool>& open, std::uint64_t seed) {
  std::string bits((open.size() + 7) / 8, '\0');
  for (std::size_t a = 0; a < open.size(); ++a) {
    if (open[a]) bits[a / 8] = static_cast<char>(bits[a / 8] | (1 << (a % 8)));
  }
  return derive(fingerprint(bits, garment), seed, open.size());
}

const char* to_string(ArcOrder order) {
  return order == ArcOrder::Opening ? "opening" : "random";
}

const char* to_string(Label label) {
  return label == Label::Sew ? "sew" : "lace";
}

std::vector<std::string> validate(const CoverMesh& mesh) {
  std::vector<std::string> problems;
  const int n = static_cast<int>(mesh.positions.size());
  std::unordered_map<std::uint64_t, int> edge_faces;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    if (face.size() < 3) {
      problems.push_back("face " + std::to_string(f) + " has fewer than 3 vertices");
      continue;
    }
    bool in_range = true;
    for (int v : face) {
      if (v < 0 || v >= n) {
        problems.push_back("face " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                           ", but there are " + std::to_string(n));
        in_range = false;
      }
    }
    if (!in_range) continue;
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      if (a == b) {
        problems.push_back("face " + std::to_string(f) + " repeats vertex " + std::to_string(a));
        continue;
      }
      if (++edge_faces[edge_key(a, b)] == 3) {
        problems.push_back("edge " + std::to_string(a) + "-" + std::to_string(b) +
                           " has more than two faces (face " + std::to_string(f) + ")");
      }
    }
  }
  std::unordered_map<std::uint64_t, int> arc_of_edge;
  for (std::size_t a = 0; a < mesh.arcs.size(); ++a) {
    const auto& arc = mesh.arcs[a];
    if (arc.edges.empty()) problems.push_back("arc " + std::to_string(a) + " has no edges");
    for (std::size_t e = 0; e < arc.edges.size(); ++e) {
      const auto [u, v] = arc.edges[e];
      const std::string where = "arc " + std::to_string(a) + " edge " + std::to_string(e) + " (" +
                                std::to_string(u) + "-" + std::to_string(v) + ")";
      if (!edge_faces.contains(edge_key(u, v))) {
        problems.push_back(where + " is not an edge of the mesh");
        continue;
      }
      const auto [it, inserted] = arc_of_edge.emplace(edge_key(u, v), static_cast<int>(a));
      if (!inserted) {
        problems.push_back(where + " is also in arc " + std::to_string(it->second));
      }
    }
  }
  return problems;
}

CoverArc arc_from_path(const std::vector<int>& path, std::string name) {
  CoverArc arc;
  arc.name = std::move(name);
  for (std::size_t i = 0; i + 1 < path.size(); ++i) arc.edges.push_back({path[i], path[i + 1]});
  return arc;
}

std::vector<int> shortest_edge_path(const CoverMesh& mesh, int from, int to) {
  const std::size_t n = mesh.positions.size();
  std::vector<std::vector<int>> neighbours(n);
  for (const auto& face : mesh.faces) {
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      neighbours[a].push_back(b);
      neighbours[b].push_back(a);
    }
  }
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<int> previous(n, -1);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  distance[from] = 0;
  queue.push({0.0, from});
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > distance[v]) continue;
    if (v == to) break;
    for (int w : neighbours[v]) {
      const double candidate = d + (mesh.positions[v] - mesh.positions[w]).norm();
      if (candidate < distance[w]) {
        distance[w] = candidate;
        previous[w] = v;
        queue.push({candidate, w});
      }
    }
  }
  if (from != to && previous[to] < 0) return {};
  std::vector<int> path;
  for (int v = to; v != -1; v = previous[v]) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

int nearest_vertex(const CoverMesh& mesh, const Vec3& point) {
  int best = -1;
  double best_distance = std::numeric_limits<double>::infinity();
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const double d = (mesh.positions[v] - point).squaredNorm();
    if (d < best_distance) {
      best_distance = d;
      best = static_cast<int>(v);
    }
  }
  return best;
}

std::vector<int> weld_vertices(std::vector<Vec3>& vertices, std::vector<std::vector<int>>& faces,
                               double tolerance) {
  // Grid hashing at the tolerance: candidates sit in the 27 cells around.
  const double cell = std::max(tolerance, 1e-300);
  auto cell_of = [&](const Vec3& p) {
    return std::array<long long, 3>{static_cast<long long>(std::floor(p.x() / cell)),
                                    static_cast<long long>(std::floor(p.y() / cell)),
                                    static_cast<long long>(std::floor(p.z() / cell))};
  };
  std::map<std::array<long long, 3>, std::vector<int>> grid;
  std::vector<int> map(vertices.size());
  std::vector<Vec3> kept;
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const auto c = cell_of(vertices[v]);
    int found = -1;
    for (int dx = -1; dx <= 1 && found < 0; ++dx) {
      for (int dy = -1; dy <= 1 && found < 0; ++dy) {
        for (int dz = -1; dz <= 1 && found < 0; ++dz) {
          const auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (int k : it->second) {
            if ((kept[k] - vertices[v]).norm() <= tolerance) {
              found = k;
              break;
            }
          }
        }
      }
    }
    if (found < 0) {
      found = static_cast<int>(kept.size());
      kept.push_back(vertices[v]);
      grid[c].push_back(found);
    }
    map[v] = found;
  }
  vertices = std::move(kept);
  for (auto& face : faces) {
    for (int& v : face) v = map[v];
  }
  return map;
}

CoverMesh subdivided(const CoverMesh& mesh) {
  CoverMesh result;
  result.positions = mesh.positions;
  std::unordered_map<std::uint64_t, int> midpoint;
  auto middle = [&](int a, int b) {
    const auto [it, inserted] =
        midpoint.emplace(edge_key(a, b), static_cast<int>(result.positions.size()));
    if (inserted) result.positions.push_back(0.5 * (mesh.positions[a] + mesh.positions[b]));
    return it->second;
  };
  for (const auto& face : mesh.faces) {
    const std::size_t n = face.size();
    Vec3 centre = Vec3::Zero();
    for (int v : face) centre += mesh.positions[v];
    const int c = static_cast<int>(result.positions.size());
    result.positions.push_back(centre / static_cast<double>(n));
    for (std::size_t i = 0; i < n; ++i) {
      const int previous = face[(i + n - 1) % n], here = face[i], next = face[(i + 1) % n];
      result.faces.push_back({here, middle(here, next), c, middle(previous, here)});
    }
  }
  for (const auto& arc : mesh.arcs) {
    CoverArc half{arc.name, {}};
    for (const auto& [u, v] : arc.edges) {
      const int m = middle(u, v);
      half.edges.push_back({u, m});
      half.edges.push_back({m, v});
    }
    result.arcs.push_back(std::move(half));
  }
  return result;
}

CoverMesh refined_for_cloth(CoverMesh mesh, int min_vertices) {
  for (int step = 0; step < 4 && static_cast<int>(mesh.positions.size()) < min_vertices; ++step) {
    mesh = subdivided(mesh);
  }
  return mesh;
}

cloth::PolygonMesh open_cuts(const CoverMesh& mesh, const std::vector<bool>& open,
                             std::vector<int>* source) {
  std::unordered_map<std::uint64_t, bool> cut;
  for (std::size_t a = 0; a < mesh.arcs.size(); ++a) {
    if (a < open.size() && open[a]) {
      for (const auto& [u, v] : mesh.arcs[a].edges) cut[edge_key(u, v)] = true;
    }
  }
  // Corners (face, position) are united across every edge that stays
  // closed; each class of corners at one vertex becomes one vertex copy.
  std::vector<int> first_corner(mesh.faces.size() + 1, 0);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    first_corner[f + 1] = first_corner[f] + static_cast<int>(mesh.faces[f].size());
  }
  std::unordered_map<std::uint64_t, int> half_edge;  // (from,to) → corner of `from`
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const std::uint64_t key = (static_cast<std::uint64_t>(face[i]) << 32) |
                                static_cast<std::uint32_t>(face[(i + 1) % face.size()]);
      half_edge[key] = first_corner[f] + static_cast<int>(i);
    }
  }
  UnionFind corners(first_corner.back());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      if (cut.contains(edge_key(a, b))) continue;
      const std::uint64_t twin =
          (static_cast<std::uint64_t>(b) << 32) | static_cast<std::uint32_t>(a);
      const auto it = half_edge.find(twin);
      if (it == half_edge.end()) continue;  // boundary
      // Twin b→a starts at corner `it->second` (vertex b); its next corner
      // is vertex a.
      const int corner_a = first_corner[f] + static_cast<int>(i);
      const int corner_b = first_corner[f] + static_cast<int>((i + 1) % face.size());
      const int twin_b = it->second;
      int twin_face =
          static_cast<int>(std::upper_bound(first_corner.begin(), first_corner.end(), twin_b) -
                           first_corner.begin()) -
          1;
      const int twin_size = static_cast<int>(mesh.faces[twin_face].size());
      const int twin_a =
          first_corner[twin_face] + (twin_b - first_corner[twin_face] + 1) % twin_size;
      corners.unite(corner_a, twin_a);
      corners.unite(corner_b, twin_b);
    }
  }
  cloth::PolygonMesh result;
  std::unordered_map<int, int> copy_of_class;
  if (source != nullptr) source->clear();
  result.faces.resize(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int root = corners.find(first_corner[f] + static_cast<int>(i));
      const auto [it, inserted] =
          copy_of_class.emplace(root, static_cast<int>(result.positions.size()));
      if (inserted) {
        result.positions.push_back(mesh.positions[face[i]]);
        if (source != nullptr) source->push_back(face[i]);
      }
      result.faces[f].push_back(it->second);
    }
  }
  return result;
}

std::vector<bool> EliminationResult::open() const {
  std::vector<bool> result(arcs.size());
  for (std::size_t a = 0; a < arcs.size(); ++a) result[a] = arcs[a].label == Label::Lace;
  return result;
}

CoverMesh dressed(const CoverMesh& mesh, const cloth::SignedDistanceField& wearer,
                  const cloth::ClothParams& params) {
  CoverMesh result = mesh;
  cloth::PolygonMesh garment{result.positions, {}};
  cloth::dress(garment, wearer, params.clearance);
  result.positions = std::move(garment.positions);
  return result;
}

namespace {

// The two sides of every edge of the open arcs in the split garment: per
// arc, four garment vertices per edge (one side's ends, then the other's).
std::vector<std::vector<std::array<int, 4>>> arc_sides(const CoverMesh& mesh,
                                                       const std::vector<bool>& open,
                                                       const cloth::PolygonMesh& garment) {
  std::unordered_map<std::uint64_t, std::array<int, 2>> half_edge;  // (from,to) → face, corner
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const auto& face = mesh.faces[f];
    for (std::size_t i = 0; i < face.size(); ++i) {
      half_edge[pair_key(face[i], face[(i + 1) % face.size()])] = {static_cast<int>(f),
                                                                   static_cast<int>(i)};
    }
  }
  auto corner = [&](const std::array<int, 2>& at, int next) {
    const auto& face = garment.faces[at[0]];
    return face[(at[1] + next) % face.size()];
  };
  std::vector<std::vector<std::array<int, 4>>> sides(mesh.arcs.size());
  for (std::size_t a = 0; a < mesh.arcs.size(); ++a) {
    if (a >= open.size() || !open[a]) continue;
    for (const auto& [u, w] : mesh.arcs[a].edges) {
      const auto one = half_edge.find(pair_key(u, w));
      const auto other = half_edge.find(pair_key(w, u));
      if (one == half_edge.end() || other == half_edge.end()) continue;
      sides[a].push_back({corner(one->second, 0), corner(one->second, 1), corner(other->second, 1),
                          corner(other->second, 0)});
    }
  }
  return sides;
}

// Per edge of the open arcs (sides' order), the widest its two sides have
// parted so far while one of them is still within `on` of the wearer: how
// far the garment opened the arc to pass the wearer, not how it flaps once
// it is off.
void widen_gaps(const std::vector<std::vector<std::array<int, 4>>>& sides,
                const std::vector<Vec3>& x, const cloth::SignedDistanceField& wearer, double on,
                std::vector<double>& gaps) {
  std::size_t e = 0;
  for (const auto& arc : sides) {
    for (const auto& [p, q, r, s] : arc) {
      const Vec3 one = 0.5 * (x[p] + x[q]), other = 0.5 * (x[r] + x[s]);
      const double gap = (one - other).norm();
      if (gap > gaps[e] && std::min(wearer.value(one), wearer.value(other)) < on) gaps[e] = gap;
      ++e;
    }
  }
}

// Per arc, the mean of its edges' gaps (widen_gaps).
std::vector<double> arc_openings(const std::vector<std::vector<std::array<int, 4>>>& sides,
                                 const std::vector<double>& gaps) {
  std::vector<double> openings(sides.size(), 0.0);
  std::size_t e = 0;
  for (std::size_t a = 0; a < sides.size(); ++a) {
    double sum = 0;
    for (std::size_t k = 0; k < sides[a].size(); ++k) sum += gaps[e++];
    if (!sides[a].empty()) openings[a] = sum / static_cast<double>(sides[a].size());
  }
  return openings;
}

// Trials of one configuration, run in parallel and handed out in order.
// With `every` false the configuration passes when one trial strips the
// garment off: trials after the first success are stopped and not
// recorded. With `every` true it passes only when all of them do: trials
// after the first failure are stopped and not recorded. Either way the
// trials recorded all ran to their end, so the record is the same for any
// thread count.
TestResult run_trials(const CoverMesh& dressed_mesh, const std::vector<bool>& open,
                      const cloth::SignedDistanceField& wearer, const WearabilityParams& params,
                      std::uint64_t seed, int count, bool every, bool measure_openings = false) {
  const cloth::PolygonMesh garment = open_cuts(dressed_mesh, open);
  std::vector<std::vector<std::array<int, 4>>> sides;
  if (measure_openings) sides = arc_sides(dressed_mesh, open, garment);
  const int trials = std::max(count, 1);
  const int workers = std::min(cloth::resolve_threads(params.threads), trials);
  cloth::ClothParams simulation = params.cloth;
  simulation.threads = 1;  // parallelism is over trials

  std::vector<TrialOutcome> outcomes(trials);
  std::vector<std::uint64_t> steps(trials, 0), projections(trials, 0);
  std::size_t side_edges = 0;
  for (const auto& arc : sides) side_edges += arc.size();
  std::vector<std::vector<double>> gaps(measure_openings ? trials : 0,
                                        std::vector<double>(side_edges, 0.0));
  const double on = params.cloth.success_distance * wearer.scale();
  // The first trial whose outcome decides the test: a success (one of
  // them) or a failure (every one).
  std::atomic<int> decisive{trials};
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, workers))
  for (int t = 0; t < trials; ++t) {
    if (t > decisive.load()) continue;
    TrialOutcome& outcome = outcomes[t];
    outcome.seed = derive(seed, static_cast<std::uint64_t>(t));
    cloth::ClothSimulation sim(garment, wearer, simulation);
    // A trial after the decisive one cannot change the answer: stop it.
    const auto result = sim.run(outcome.seed, [&](int step, const cloth::ClothSimulation& state) {
      if (measure_openings && step % simulation.check_every == 0) {
        widen_gaps(sides, state.positions(), wearer, on, gaps[t]);
      }
      return decisive.load(std::memory_order_relaxed) > t;
    });
    outcome.success = result.success;
    outcome.steps = result.steps;
    outcome.stalled = result.stalled;
    outcome.min_distance = result.min_distance / wearer.scale();
    outcome.caught = result.caught;
    outcome.caught_at = result.caught_at;
    outcome.caught_radius = result.caught_radius;
    outcome.cloth_vertices = static_cast<int>(garment.positions.size());
    steps[t] = static_cast<std::uint64_t>(result.steps);
    projections[t] = result.projections;
    if (result.success != every) {
      int current = decisive.load();
      while (t < current && !decisive.compare_exchange_weak(current, t)) {
      }
    }
  }
  TestResult result;
  const int first = decisive.load();
  result.wearable = every ? first == trials : first < trials;
  const int recorded = first < trials ? first + 1 : trials;
  result.trials.assign(outcomes.begin(), outcomes.begin() + recorded);
  if (measure_openings) result.openings = arc_openings(sides, gaps[std::min(first, trials - 1)]);
  for (int t = 0; t < trials; ++t) {
    result.steps += steps[t];
    result.projections += projections[t];
  }
  return result;
}

}  // namespace

TestResult test_wearability(const CoverMesh& dressed_mesh, const std::vector<bool>& open,
                            const cloth::SignedDistanceField& wearer,
                            const WearabilityParams& params, std::uint64_t seed, bool openings) {
  return run_trials(dressed_mesh, open, wearer, params, seed, params.trials, false, openings);
}

TestResult test_every_trial(const CoverMesh& dressed_mesh, const std::vector<bool>& open,
                            const cloth::SignedDistanceField& wearer,
                            const WearabilityParams& params, std::uint64_t seed, int trials) {
  return run_trials(dressed_mesh, open, wearer, params, seed, trials, true);
}

bool PassedConfigurations::covers(const std::vector<bool>& open) const {
  for (const auto& set : open_sets_) {
    bool inside = set.size() == open.size();
    for (std::size_t a = 0; inside && a < set.size(); ++a) inside = !set[a] || open[a];
    if (inside) return true;
  }
  return false;
}

void PassedConfigurations::add(const std::vector<bool>& open) {
  if (!covers(open)) open_sets_.push_back(open);
}

EliminationResult eliminate(const CoverMesh& mesh, const cloth::SignedDistanceField& wearer,
                            const WearabilityParams& params, int run,
                            const ProgressCallback& progress, PassedConfigurations* passed) {
  if (const auto problems = validate(mesh); !problems.empty()) {
    throw std::invalid_argument(problems.front());
  }
  const auto start = std::chrono::steady_clock::now();
  const CoverMesh garment = dressed(mesh, wearer, params.cloth);
  const int arcs = static_cast<int>(mesh.arcs.size());
  const auto run_seed = derive(params.seed, 0x52554E, static_cast<std::uint64_t>(run));
  EliminationResult result;
  result.arcs.resize(arcs);
  std::vector<bool> open(arcs, true);
  Progress report{run, 1, 0, arcs, 0};
  if (progress) progress(report);
  const std::uint64_t garment_key = params.record != nullptr ? fingerprint(garment) : 0;
  // A test from the record when it holds one, else simulated and recorded.
  // A test that measures the openings is recorded under its own key.
  auto simulate_test = [&](std::uint64_t seed, bool openings) {
    if (params.record == nullptr) {
      return test_wearability(garment, open, wearer, params, seed, openings);
    }
    std::uint64_t key = test_key(garment_key, open, seed);
    if (openings) key = mix64(key ^ 0x4F50454E494E4753ULL);
    if (auto known = params.record->find(key)) {
      ++result.replayed;
      return *known;
    }
    TestResult fresh = test_wearability(garment, open, wearer, params, seed, openings);
    params.record->add(key, fresh);
    return fresh;
  };
  // None for a wearer without handles: nothing can be linked with it, and
  // no test needs the configuration split for it.
  std::optional<LinkingTest> linking;
  if (params.linking) linking.emplace(wearer);
  if (linking && linking->wearer_loops() == 0) linking.reset();
  // A test failed by the linking test, else inferred from an earlier run's
  // pass, else simulate_test. The linking test comes first: a linked
  // configuration cannot come off even if a simulation let it through.
  auto run_test = [&](std::uint64_t seed, bool openings = false) {
    if (linking && linking->linked(open_cuts(garment, open))) {
      ++result.linked;
      TestResult known;
      known.linked = true;
      return known;
    }
    if (passed != nullptr && passed->covers(open)) {
      ++result.inferred;
      TestResult known;
      known.wearable = true;
      known.inferred = true;
      return known;
    }
    TestResult fresh = simulate_test(seed, openings);
    if (passed != nullptr && fresh.wearable) passed->add(open);
    return fresh;
  };
  // §5: first check that the garment with every cut open is wearable.
  const bool by_opening = params.order == ArcOrder::Opening && run == 0;
  result.initial = run_test(derive(run_seed, 0), by_opening);
  result.steps += result.initial.steps;
  result.projections += result.initial.projections;
  if (result.initial.wearable) {
    result.order = random_order(arcs, derive(run_seed, 1));
    const std::vector<double>& openings = result.initial.openings;
    if (by_opening && openings.size() == static_cast<std::size_t>(arcs)) {
      std::stable_sort(result.order.begin(), result.order.end(),
                       [&](int a, int b) { return openings[a] < openings[b]; });
    }
    int position = 0;
    // Runs one test of the garment with the arcs of order[first, last)
    // closed tentatively; a group's seed differs from any single arc's.
    auto test_closed = [&](int first, int last) {
      for (int p = first; p < last; ++p) open[result.order[p]] = false;
      const std::uint64_t seed =
          last - first == 1 ? derive(run_seed, 2, static_cast<std::uint64_t>(result.order[first]))
                            : derive(run_seed, 3,
                                     (static_cast<std::uint64_t>(first) << 32) |
                                         static_cast<std::uint64_t>(last));
      TestResult outcome = run_test(seed);
      outcome.group = last - first;
      result.steps += outcome.steps;
      result.projections += outcome.projections;
      ++result.tests;
      if (!outcome.wearable) {
        for (int p = first; p < last; ++p) open[result.order[p]] = true;
      }
      return outcome;
    };
    auto decide = [&](int first, int last, const TestResult& test) {
      for (int p = first; p < last; ++p) {
        ArcResult& outcome = result.arcs[result.order[p]];
        outcome.position = p;
        outcome.test = test;
        if (test.wearable) {
          outcome.label = Label::Sew;
          ++report.sewn;
        }
      }
      position = std::max(position, last);
      report.tested = position;
      if (progress) progress(report);
    };
    // Settles order[first, last); `failed` (may be null) is a test already
    // run of exactly the configuration with all of them closed, which did
    // not come off. Returns whether any of them was laced.
    std::function<bool(int, int, const TestResult*)> settle = [&](int first, int last,
                                                                  const TestResult* failed) {
      TestResult test;
      if (failed == nullptr) {
        test = test_closed(first, last);
        if (test.wearable) {
          decide(first, last, test);
          return false;
        }
        failed = &test;
      }
      if (last - first == 1) {
        decide(first, last, *failed);
        return true;
      }
      const int middle = first + (last - first) / 2;
      if (settle(first, middle, nullptr)) {
        settle(middle, last, nullptr);
        return true;
      }
      // The first half is all sewn, so closing the second half now gives
      // exactly the configuration that failed: split it without a test.
      settle(middle, last, failed);
      return true;
    };
    // §5 takes the arcs one at a time. With group testing (see
    // WearabilityParams::group_testing) a run of arcs is closed together
    // while the garment keeps coming off, the run doubling after each
    // success and halving after a run that laced an arc.
    int group = 1;
    while (position < arcs) {
      const int last = std::min(arcs, position + group);
      const bool laced = settle(position, last, nullptr);
      if (params.group_testing) {
        group = laced ? std::max(1, group / 2) : std::min(group * 2, std::max(params.max_group, 1));
      }
    }
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

int chosen_run(const LacingStudy& study) {
  int best = -1, best_sewn = -1;
  for (std::size_t r = 0; r < study.runs.size(); ++r) {
    if (!study.runs[r].wearable()) continue;
    int sewn = 0;
    for (const auto& arc : study.runs[r].arcs) sewn += arc.label == Label::Sew;
    if (sewn > best_sewn) {
      best = static_cast<int>(r);
      best_sewn = sewn;
    }
  }
  return best;
}

LacingStudy study_lacing(const CoverMesh& mesh, const cloth::SignedDistanceField& wearer,
                         const WearabilityParams& params, int runs,
                         const ProgressCallback& progress) {
  LacingStudy study;
  const std::size_t arcs = mesh.arcs.size();
  std::vector<int> laced(arcs, 0);
  PassedConfigurations passed;
  for (int r = 0; r < std::max(runs, 1); ++r) {
    ProgressCallback forward;
    if (progress) {
      forward = [&](const Progress& p) {
        Progress copy = p;
        copy.runs = std::max(runs, 1);
        progress(copy);
      };
    }
    study.runs.push_back(
        eliminate(mesh, wearer, params, r, forward, params.reuse_passes ? &passed : nullptr));
    const auto& result = study.runs.back();
    if (!result.wearable()) continue;
    ++study.wearable_runs;
    for (std::size_t a = 0; a < arcs; ++a) laced[a] += result.arcs[a].label == Label::Lace;
  }
  study.lace_probability.assign(arcs, 0.0);
  for (std::size_t a = 0; a < arcs && study.wearable_runs > 0; ++a) {
    study.lace_probability[a] = static_cast<double>(laced[a]) / study.wearable_runs;
  }
  return study;
}

}  // namespace planner
