// What the remesher (remesh.hpp) repairs in the extracted lattice: pinched
// vertices, folded quads, crumbs and holes.
#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>

#include "planner/common/index.hpp"
#include "planner/common/union_find.hpp"
#include "planner/mesh/soup.hpp"
#include "planner/proxy/remesh.hpp"
#include "planner/proxy/remesh_internal.hpp"

namespace planner {

int collapse_folded_quads(PolygonMesh& mesh, double ratio) {
  int collapsed = 0;
  for (bool changed = true; changed;) {
    changed = false;
    const std::size_t n = mesh.positions.size();
    std::vector<std::vector<int>> ring(n);
    std::vector<std::vector<int>> faces_of(n);
    std::map<std::pair<int, int>, int> uses;
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      const auto& face = mesh.faces[f];
      for (std::size_t i = 0; i < face.size(); ++i) {
        const int a = face[i];
        const int b = face[(i + 1) % face.size()];
        ring[at(a)].push_back(b);
        ring[at(b)].push_back(a);
        faces_of[at(a)].push_back(static_cast<int>(f));
        ++uses[undirected_edge(a, b)];
      }
    }
    std::vector<bool> boundary(n, false);
    for (const auto& [edge, count] : uses) {
      if (count == 1) boundary[at(edge.first)] = boundary[at(edge.second)] = true;
    }
    for (auto& list : ring) remesh_detail::sort_unique(list);
    for (std::size_t f = 0; f < mesh.faces.size() && !changed; ++f) {
      const auto& face = mesh.faces[f];
      if (face.size() != 4) continue;
      for (std::size_t i = 0; i < 2; ++i) {
        const int a = face[i];
        const int c = face[i + 2];
        const int b = face[i + 1];
        const int d = face[(i + 3) % 4];
        const double diagonal = (mesh.positions[at(a)] - mesh.positions[at(c)]).norm();
        const double other = (mesh.positions[at(b)] - mesh.positions[at(d)]).norm();
        if (!(diagonal < ratio * other) || (boundary[at(a)] && boundary[at(c)])) continue;
        std::vector<int> common;
        std::set_intersection(ring[at(a)].begin(), ring[at(a)].end(), ring[at(c)].begin(),
                              ring[at(c)].end(), std::back_inserter(common));
        if (common != std::vector<int>{std::min(b, d), std::max(b, d)}) continue;
        const auto& fa = faces_of[at(a)];
        const auto& fc = faces_of[at(c)];
        const bool shared = std::any_of(fa.begin(), fa.end(), [&](int g) {
          return g != static_cast<int>(f) && std::find(fc.begin(), fc.end(), g) != fc.end();
        });
        if (shared) continue;
        const Vec3 middle = boundary[at(a)] ? mesh.positions[at(a)]
                            : boundary[at(c)]
                                ? mesh.positions[at(c)]
                                : 0.5 * (mesh.positions[at(a)] + mesh.positions[at(c)]);
        mesh.positions[at(a)] = middle;
        mesh.faces.erase(mesh.faces.begin() + static_cast<std::ptrdiff_t>(f));
        for (auto& g : mesh.faces) std::replace(g.begin(), g.end(), c, a);
        ++collapsed;
        changed = true;
        break;
      }
    }
  }
  if (collapsed > 0) drop_unused_vertices(mesh);
  return collapsed;
}

namespace remesh_detail {

void split_pinched_vertices(PolygonMesh& mesh) {
  const std::vector<int> start = corner_starts(mesh);
  UnionFind corners = corner_fans(mesh, start);
  std::vector<int> owner(mesh.positions.size(), -1);  // fan root that keeps the original vertex
  std::map<int, int> copy_of_root;
  std::vector<int> split;  // the vertices split and their copies
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    for (std::size_t i = 0; i < mesh.faces[f].size(); ++i) {
      int& v = mesh.faces[f][i];
      const int root = corners.find(start[f] + static_cast<int>(i));
      if (owner[at(v)] < 0) owner[at(v)] = root;
      if (owner[at(v)] == root) continue;
      auto [it, inserted] = copy_of_root.emplace(root, static_cast<int>(mesh.positions.size()));
      if (inserted) {
        mesh.positions.push_back(mesh.positions[at(v)]);
        split.push_back(v);
        split.push_back(it->second);
      }
      v = it->second;
    }
  }
  if (split.empty()) return;
  std::vector<Vec3> centre(mesh.positions.size(), Vec3::Zero());
  std::vector<int> count(mesh.positions.size(), 0);
  for (const auto& face : mesh.faces) {
    Vec3 c = Vec3::Zero();
    for (int v : face) c += mesh.positions[at(v)];
    c /= static_cast<double>(face.size());
    for (int v : face) {
      centre[at(v)] += c;
      ++count[at(v)];
    }
  }
  std::sort(split.begin(), split.end());
  split.erase(std::unique(split.begin(), split.end()), split.end());
  for (int v : split) {
    if (count[at(v)] == 0) continue;
    Vec3& p = mesh.positions[at(v)];
    p += 0.02 * (centre[at(v)] / count[at(v)] - p);
  }
}

int weld_folds(PolygonMesh& mesh, double ratio) {
  int welded = 0;
  for (int folds; (folds = collapse_folded_quads(mesh, ratio)) > 0;) {
    welded += folds;
    split_pinched_vertices(mesh);
  }
  return welded;
}

void keep_largest_component(PolygonMesh& mesh) {
  UnionFind vertices = vertex_components(mesh);
  std::map<int, std::size_t> size;
  for (const auto& face : mesh.faces) ++size[vertices.find(face[0])];
  if (size.size() <= 1) return;
  const auto largest = std::max_element(size.begin(), size.end(), [](const auto& a, const auto& b) {
                         return a.second < b.second;
                       })->first;
  std::size_t others = 0;
  for (const auto& [root, count] : size) others += root == largest ? 0 : count;
  if (others * 50 > mesh.faces.size()) return;
  std::vector<std::vector<int>> kept;
  for (auto& face : mesh.faces) {
    if (vertices.find(face[0]) == largest) kept.push_back(std::move(face));
  }
  mesh.faces = std::move(kept);
  drop_unused_vertices(mesh);
}

int fill_holes(PolygonMesh& mesh, int keep, std::size_t max_corners) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& face : mesh.faces) {
    for (std::size_t i = 0; i < face.size(); ++i)
      ++directed[{face[i], face[(i + 1) % face.size()]}];
  }
  std::unordered_map<int, int> boundary_next;
  for (const auto& [edge, count] : directed) {
    if (directed.count({edge.second, edge.first}) == 0) boundary_next[edge.first] = edge.second;
  }
  std::vector<std::vector<int>> loops;
  std::vector<double> lengths;
  std::unordered_map<int, bool> seen;
  for (const auto& [start, unused] : boundary_next) {
    if (seen[start]) continue;
    std::vector<int> loop;
    double length = 0.0;
    for (int v = start; !seen[v]; v = boundary_next.at(v)) {
      seen[v] = true;
      loop.push_back(v);
      const auto next = boundary_next.find(v);
      if (next == boundary_next.end()) return 0;  // an open chain: not a manifold rim
      length += (mesh.positions[at(next->second)] - mesh.positions[at(v)]).norm();
    }
    loops.push_back(std::move(loop));
    lengths.push_back(length);
  }
  std::vector<std::size_t> order(loops.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return lengths[a] > lengths[b]; });
  int closed = 0;
  for (std::size_t k = at(std::max(keep, 0)); k < order.size(); ++k) {
    std::vector<int>& loop = loops[order[k]];
    if (loop.size() < 3 || loop.size() > max_corners) continue;
    // The rim runs against the faces around it; the new face runs along it.
    std::reverse(loop.begin(), loop.end());
    mesh.faces.push_back(std::move(loop));
    ++closed;
  }
  return closed;
}

}  // namespace remesh_detail

}  // namespace planner
