#include "planner/wearability/coarse_cloth.hpp"

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "planner/common/index.hpp"
#include "planner/mesh/decimation_mesh.hpp"
#include "planner/mesh/soup.hpp"

namespace planner {

namespace {

using TriMesh = DecimationMesh;

// The key of the undirected edge a–b: the smaller index in the high bits.
std::uint64_t undirected(int a, int b) {
  const auto [lo, hi] = undirected_edge(a, b);
  return pair_key(lo, hi);
}

// The cut edges (arcs, then one chain per boundary loop) while the mesh is
// simplified: which chain each edge is on, each vertex's cut edges, and
// which vertices may not move.
class Chains {
 public:
  Chains(const CoverMesh& mesh, const std::vector<std::array<int, 2>>& boundary)
      : links_(mesh.positions.size()), locked_(mesh.positions.size(), 0) {
    auto add = [&](int a, int b, int chain) {
      if (!chain_of_.emplace(undirected(a, b), chain).second) return;
      links_[at(a)].push_back({b, chain});
      links_[at(b)].push_back({a, chain});
    };
    int chain = 0;
    for (const CoverArc& arc : mesh.arcs) {
      for (const auto& [a, b] : arc.edges) add(a, b, chain);
      ++chain;
    }
    // Boundary edges, one chain per loop.
    std::unordered_map<int, int> next;
    for (const auto& [a, b] : boundary) next[a] = b;
    std::unordered_map<int, bool> walked;
    for (const auto& [a, b] : boundary) {
      if (walked[a]) continue;
      for (int v = a; !walked[v] && next.count(v) != 0; v = next[v]) {
        walked[v] = true;
        add(v, next[v], chain);
      }
      ++chain;
    }
    size_.assign(static_cast<std::size_t>(chain), 0);
    std::vector<char> anchored(static_cast<std::size_t>(chain), 0);
    for (std::size_t v = 0; v < links_.size(); ++v) {
      const auto& l = links_[v];
      if (l.empty()) continue;
      for (const auto& link : l) ++size_[at(link[1])];
      if (l.size() != 2 || l[0][1] != l[1][1]) {
        locked_[v] = 1;
        for (const auto& link : l) anchored[at(link[1])] = 1;
      }
    }
    for (int& s : size_) s /= 2;  // each edge was counted at both ends
    // A closed chain with no end keeps one vertex where it is.
    for (std::size_t v = 0; v < links_.size(); ++v) {
      if (links_[v].empty()) continue;
      const int c = links_[v][0][1];
      if (anchored[at(c)] == 0) {
        anchored[at(c)] = 1;
        locked_[v] = 1;
      }
    }
  }

  // Whether v0 may collapse into its neighbour v1.
  bool may_collapse(int v0, int v1) const {
    if (locked_[at(v0)] != 0) return false;
    const auto& l = links_[at(v0)];
    if (l.empty()) return true;
    // Inside a chain: only along it, and not so that the chain's two
    // neighbours of v0 end up joined twice or the chain shrinks to a
    // triangle.
    const int along = l[0][0] == v1 ? 0 : (l[1][0] == v1 ? 1 : -1);
    if (along < 0) return false;
    const int other = l[1 - along][0];
    if (other == v1 || chain_of_.count(undirected(other, v1)) != 0) return false;
    return size_[at(l[0][1])] > 3;
  }

  // Records the collapse of v0 into v1 (may_collapse was true).
  void collapse(int v0, int v1) {
    auto& l = links_[at(v0)];
    if (l.empty()) return;
    const int along = l[0][0] == v1 ? 0 : 1;
    const int other = l[1 - along][0];
    const int chain = l[0][1];
    chain_of_.erase(undirected(v0, v1));
    chain_of_.erase(undirected(v0, other));
    chain_of_.emplace(undirected(other, v1), chain);
    for (auto& link : links_[at(v1)])
      if (link[0] == v0) link[0] = other;
    for (auto& link : links_[at(other)])
      if (link[0] == v0) link[0] = v1;
    l.clear();
    --size_[at(chain)];
  }

  bool is_cut(int a, int b) const { return chain_of_.count(undirected(a, b)) != 0; }
  // Every cut edge (undirected key of its original vertices) → its chain.
  const std::unordered_map<std::uint64_t, int>& edges() const { return chain_of_; }

 private:
  std::unordered_map<std::uint64_t, int> chain_of_;
  std::vector<std::vector<std::array<int, 2>>> links_;  // (neighbour, chain) per cut edge
  std::vector<char> locked_;
  std::vector<int> size_;  // edges per chain
};

// The decimater's module: refuses every collapse the chains do not allow,
// keeps them up to date, and takes first the collapse whose longest new
// edge is shortest, so that the cloth's edges come out of about one length
// (taking the shortest edge first leaves a dense row wherever a chain's
// edges start longer than the edges across it).
template <class MeshT>
class ModChains : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModChains, MeshT, Chains);
  explicit ModChains(MeshT& mesh) : Base(mesh, false) {}
  void set_chains(Chains* chains) { chains_ = chains; }
  float collapse_priority(const CollapseInfo& ci) override {
    if (!chains_->may_collapse(ci.v0.idx(), ci.v1.idx())) return float(Base::ILLEGAL_COLLAPSE);
    double longest = 0;
    for (const auto w : Base::mesh().vv_range(ci.v0))
      if (w != ci.v1) longest = std::max(longest, (Base::mesh().point(w) - ci.p1).sqrnorm());
    return static_cast<float>(longest);
  }
  void preprocess_collapse(const CollapseInfo& ci) override {
    chains_->collapse(ci.v0.idx(), ci.v1.idx());
  }

 private:
  Chains* chains_ = nullptr;
};

std::vector<std::array<int, 2>> boundary_edges(const CoverMesh& mesh) {
  std::unordered_map<std::uint64_t, int> count;
  for (const auto& face : mesh.faces)
    for (std::size_t i = 0; i < face.size(); ++i)
      ++count[undirected(face[i], face[(i + 1) % face.size()])];
  std::vector<std::array<int, 2>> result;
  for (const auto& face : mesh.faces)
    for (std::size_t i = 0; i < face.size(); ++i) {
      const int a = face[i], b = face[(i + 1) % face.size()];
      if (count[undirected(a, b)] == 1) result.push_back({a, b});
    }
  return result;
}

constexpr double kDegree = std::numbers::pi / 180.0;

// Corner angle at b between a and c, in degrees.
double corner(const Vec3& a, const Vec3& b, const Vec3& c) {
  return angle_between(a - b, c - b) / kDegree;
}

// Triangles paired across free edges into quads, nearest-square first; a
// pair is taken when every corner is within 45° of square and the two
// triangles bend by less than 40° across the edge.
std::vector<std::vector<int>> paired(const std::vector<Vec3>& positions,
                                     const std::vector<std::array<int, 3>>& triangles,
                                     const Chains& chains, const std::vector<int>& original) {
  std::unordered_map<std::uint64_t, std::array<int, 2>> half;  // (from,to) → (triangle, corner)
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int i = 0; i < 3; ++i) {
      const int a = triangles[t][at(i)], b = triangles[t][at((i + 1) % 3)];
      half[pair_key(a, b)] = {static_cast<int>(t), i};
    }
  struct Candidate {
    double score;
    int t1, t2;
    std::array<int, 4> quad;
  };
  std::vector<Candidate> candidates;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int i = 0; i < 3; ++i) {
      const auto& tri = triangles[t];
      const int p = tri[at((i + 2) % 3)], u = tri[at(i)], v = tri[at((i + 1) % 3)];
      if (u > v) continue;  // each edge once
      const auto across = half.find(pair_key(v, u));
      if (across == half.end() || chains.is_cut(original[at(u)], original[at(v)])) continue;
      const auto& other = triangles[at(across->second[0])];
      const int q = other[at((across->second[1] + 2) % 3)];
      const Vec3 &P = positions[at(p)], &U = positions[at(u)], &Q = positions[at(q)],
                 &V = positions[at(v)];
      const Vec3 n1 = (U - P).cross(V - P), n2 = (U - V).cross(Q - V);
      const double bend = angle_between(n1, n2) / kDegree;
      if (bend >= 40.0) continue;
      // Convex seen along the pair's mean normal, every corner within 45°
      // of square.
      const std::array<Vec3, 4> quad = {P, U, Q, V};
      const Vec3 normal = n1.normalized() + n2.normalized();
      bool convex = true;
      double worst = 0;
      for (int k = 0; k < 4; ++k) {
        const Vec3& before = quad[at((k + 3) % 4)];
        const Vec3& here = quad[at(k)];
        const Vec3& after = quad[at((k + 1) % 4)];
        convex = convex && (here - before).cross(after - here).dot(normal) > 0;
        worst = std::max(worst, std::abs(corner(before, here, after) - 90.0));
      }
      if (!convex || worst >= 45.0) continue;
      candidates.push_back({worst, static_cast<int>(t), across->second[0], {p, u, q, v}});
    }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.score < b.score; });
  std::vector<char> used(triangles.size(), 0);
  std::vector<std::vector<int>> faces;
  for (const Candidate& c : candidates) {
    if (used[at(c.t1)] != 0 || used[at(c.t2)] != 0) continue;
    used[at(c.t1)] = used[at(c.t2)] = 1;
    faces.push_back({c.quad[0], c.quad[1], c.quad[2], c.quad[3]});
  }
  for (std::size_t t = 0; t < triangles.size(); ++t)
    if (used[t] == 0) faces.push_back({triangles[t][0], triangles[t][1], triangles[t][2]});
  return faces;
}

}  // namespace

CoverMesh coarsened(const CoverMesh& mesh, int target_vertices) {
  if (target_vertices <= 0 || static_cast<int>(mesh.positions.size()) <= target_vertices)
    return mesh;
  TriMesh tri;
  std::vector<TriMesh::VertexHandle> handles;
  handles.reserve(mesh.positions.size());
  for (const Vec3& p : mesh.positions)
    handles.push_back(tri.add_vertex(TriMesh::Point(p.x(), p.y(), p.z())));
  for (const auto& face : mesh.faces)
    for (std::size_t i = 1; i + 1 < face.size(); ++i) {
      if (!tri.add_face(handles[at(face[0])], handles[at(face[i])], handles[at(face[i + 1])])
               .is_valid())
        return mesh;  // not a manifold OpenMesh accepts: simulate the garment as it is
    }
  Chains chains(mesh, boundary_edges(mesh));
  OpenMesh::VPropHandleT<int> original;
  tri.add_property(original);
  for (const auto vh : tri.vertices()) tri.property(original, vh) = vh.idx();
  tri.update_face_normals();
  tri.update_vertex_normals();
  {
    using Decimater = OpenMesh::Decimater::DecimaterT<TriMesh>;
    OpenMesh::Decimater::ModNormalFlippingT<TriMesh>::Handle normal_flipping;
    ModChains<TriMesh>::Handle keep_chains;
    Decimater decimater(tri);
    decimater.add(normal_flipping);
    decimater.add(keep_chains);
    decimater.module(normal_flipping).set_max_normal_deviation(60.0);
    decimater.module(keep_chains).set_chains(&chains);
    decimater.initialize();
    decimater.decimate_to(static_cast<std::size_t>(target_vertices));
  }
  tri.garbage_collection();

  // Surviving vertices keep their original index in `original`; a collapsed
  // vertex went into a neighbour, so arcs are rebuilt from the chains.
  CoverMesh result;
  std::vector<int> index_of(mesh.positions.size(), -1);
  std::vector<int> original_of;
  for (const auto vh : tri.vertices()) {
    const auto& p = tri.point(vh);
    index_of[at(tri.property(original, vh))] = static_cast<int>(result.positions.size());
    original_of.push_back(tri.property(original, vh));
    result.positions.emplace_back(p[0], p[1], p[2]);
  }
  std::vector<std::array<int, 3>> triangles;
  for (const auto fh : tri.faces()) {
    std::array<int, 3> t{};
    int i = 0;
    for (const auto vh : tri.fv_range(fh)) t[at(i++)] = vh.idx();
    triangles.push_back(t);
  }
  result.faces = paired(result.positions, triangles, chains, original_of);

  // Each arc: the cut edges left on its chain, in the result's indices.
  result.arcs.resize(mesh.arcs.size());
  for (std::size_t a = 0; a < mesh.arcs.size(); ++a) result.arcs[a].name = mesh.arcs[a].name;
  for (const auto& [key, chain] : chains.edges()) {
    if (chain >= static_cast<int>(mesh.arcs.size())) continue;  // a boundary loop
    const int a = index_of[at(static_cast<int>(key >> 32))];
    const int b = index_of[at(static_cast<int>(key & 0xffffffffU))];
    result.arcs[at(chain)].edges.push_back({a, b});
  }
  for (CoverArc& arc : result.arcs) std::sort(arc.edges.begin(), arc.edges.end());
  if (!validate(result).empty()) return mesh;
  return result;
}

}  // namespace planner
