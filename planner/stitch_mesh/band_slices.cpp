// Step 2 of the stitch mesher (stitch_mesher.hpp): the disc's triangles cut
// along the row levels into slices, the slices grouped into strips, and
// points added on the boundary for row ends.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "planner/common/union_find.hpp"
#include "planner/stitch_mesh/stitch_meshing.hpp"

namespace planner::stitch_meshing {
namespace {

// A corner of a slice: a disc vertex, or where a level crosses a side of the
// triangle.
struct Corner {
  int vertex;
  int edge;     // triangle side (0..2) of a crossing, -1 for a disc vertex
  int level;    // of a crossing or a pinned vertex
  bool pinned;  // a disc vertex on `level`
};

// Cuts the triangles one by one into the slices of `out`.
class Slicer {
 public:
  // `pin` as for slice().
  Slicer(const LabelledDisc& disc, const Eigen::VectorXd& t, double spacing, int bands,
         const std::vector<int>& pin)
      : disc_(disc), bands_(bands), pin_(pin) {
    polygons_.positions = disc.positions;
    out_.pinned.assign(disc.positions.size(), false);
    for (std::size_t v = 0; v < pin.size(); ++v) out_.pinned[v] = pin[v] >= 0;
    for (std::size_t f = 0; f < disc.faces.size(); ++f) {
      const std::vector<int>& face = disc.faces[f];
      for (std::size_t i = 0; i < face.size(); ++i) {
        directed_[key(face[i], face[(i + 1) % face.size()])] = {static_cast<int>(f),
                                                                static_cast<int>(i)};
      }
    }
    // Values a hair off the levels, so no vertex lies on one.
    value_.resize(at(static_cast<int>(t.size())));
    for (int i = 0; i < t.size(); ++i) {
      double x = t[i] / spacing;
      const double nearest = std::round(x);
      if (pin_of(i) >= 0) {
        x = pin_of(i);
      } else if (std::abs(x - nearest) < 1e-6) {
        x = nearest + 2e-6;
      }
      value_[at(i)] = x;
    }
  }

  // The slices of triangle k, one per band it reaches into.
  void add_triangle(const Triangle& tri, int k) {
    int lo = bands_;
    int hi = -1;
    for (int v : tri.v) {
      lo = std::min(lo, lowest_band(v));
      hi = std::max(hi, highest_band(v));
    }
    for (int b = lo; b <= hi; ++b) {
      const std::vector<Corner> corners = slice_corners(tri, b);
      if (corners.size() >= 3) add_slice(tri, k, b, corners);
    }
  }

  BandSlices finish() {
    out_.mesh = HalfedgeMesh(std::move(polygons_));
    return std::move(out_);
  }

 private:
  int pin_of(int v) const { return pin_.empty() ? -1 : pin_[at(v)]; }
  int band_of(double x) const { return std::clamp(static_cast<int>(std::floor(x)), 0, bands_ - 1); }
  // A pinned vertex on level k belongs to bands k - 1 and k.
  int lowest_band(int v) const { return pin_of(v) >= 0 ? pin_of(v) - 1 : band_of(value_[at(v)]); }
  int highest_band(int v) const { return pin_of(v) >= 0 ? pin_of(v) : band_of(value_[at(v)]); }

  // The vertex where `level` crosses the side a - b, made when first asked for.
  int crossing(int a, int b, int level) {
    const int lo = std::min(a, b);
    const int hi = std::max(a, b);
    auto [it, inserted] = crossings_.emplace(std::make_tuple(lo, hi, level), 0);
    if (inserted) {
      const double s = (level - value_[at(lo)]) / (value_[at(hi)] - value_[at(lo)]);
      it->second = static_cast<int>(polygons_.positions.size());
      polygons_.positions.push_back((1 - s) * disc_.positions[at(lo)] +
                                    s * disc_.positions[at(hi)]);
    }
    return it->second;
  }

  // The corners of the part of `tri` in band b, counter-clockwise.
  std::vector<Corner> slice_corners(const Triangle& tri, int b) {
    std::vector<Corner> corners;
    for (int i = 0; i < 3; ++i) {
      const int p = tri.v[at(i)];
      const int q = tri.v[at((i + 1) % 3)];
      if (lowest_band(p) == b || highest_band(p) == b) {
        corners.push_back({p, -1, pin_of(p), pin_of(p) >= 0});
      }
      const double vp = value_[at(p)];
      const double vq = value_[at(q)];
      // Levels b (bottom) and b + 1 (top) crossed by p -> q, in travel
      // order (not the level of a pinned end: the curve passes through it).
      std::vector<int> levels;
      for (int level : {b, b + 1}) {
        if (level <= 0 || level >= bands_ || level == pin_of(p) || level == pin_of(q)) continue;
        if ((vp < level) != (vq < level)) levels.push_back(level);
      }
      if (levels.size() == 2 && vp > vq) std::swap(levels[0], levels[1]);
      for (int level : levels) corners.push_back({crossing(p, q, level), i, level, false});
    }
    return corners;
  }

  // The slice of triangle k in band b, with its half-edges' level and
  // disc-boundary side.
  void add_slice(const Triangle& tri, int k, int b, const std::vector<Corner>& corners) {
    std::vector<int>& face = polygons_.faces.emplace_back();
    out_.band.push_back(b);
    out_.tri.push_back(k);
    for (std::size_t c = 0; c < corners.size(); ++c) {
      const Corner& a = corners[c];
      const Corner& z = corners[(c + 1) % corners.size()];
      face.push_back(a.vertex);
      int level = -1;
      int side = -1;  // triangle side the half-edge lies on
      const bool a_on = a.edge >= 0 || a.pinned;
      const bool z_on = z.edge >= 0 || z.pinned;
      if (a_on && z_on && a.level == z.level && !(a.pinned && z.pinned) &&
          (a.pinned || z.pinned || a.edge != z.edge)) {
        level = a.level;
      } else if (a.edge >= 0) {
        side = a.edge;
      } else if (z.edge >= 0) {
        side = z.edge;
      } else {
        // Two disc vertices: the side that starts at a.
        for (int i = 0; i < 3; ++i) {
          if (tri.v[at(i)] == a.vertex) side = i;
        }
      }
      out_.level.push_back(level);
      int source_face = -1;
      int source_side = -1;
      if (side >= 0) {
        const int p = tri.v[at(side)];
        const int q = tri.v[at((side + 1) % 3)];
        if (directed_.find(key(q, p)) == directed_.end()) {
          auto it = directed_.find(key(p, q));
          if (it != directed_.end()) {
            source_face = it->second.first;
            source_side = it->second.second;
          }
        }
      }
      out_.source_face.push_back(source_face);
      out_.source_side.push_back(source_side);
    }
  }

  const LabelledDisc& disc_;
  const int bands_;
  const std::vector<int>& pin_;
  // Sides of disc faces by directed vertex pair: (face, side).
  std::unordered_map<std::uint64_t, std::pair<int, int>> directed_;
  std::vector<double> value_;                           // per disc vertex, in levels
  std::map<std::tuple<int, int, int>, int> crossings_;  // (lower, higher vertex, level)
  PolygonMesh polygons_;
  BandSlices out_;
};

}  // namespace

BandSlices slice(const LabelledDisc& disc, const std::vector<Triangle>& tris,
                 const Eigen::VectorXd& t, double spacing, int bands, const std::vector<int>& pin) {
  Slicer slicer(disc, t, spacing, bands, pin);
  for (std::size_t k = 0; k < tris.size(); ++k) slicer.add_triangle(tris[k], static_cast<int>(k));
  return slicer.finish();
}

BandSlices split_halfedges(const BandSlices& in, std::vector<HalfedgeSplit> splits) {
  std::sort(splits.begin(), splits.end(), [](const HalfedgeSplit& a, const HalfedgeSplit& b) {
    return std::tie(a.halfedge, a.s) < std::tie(b.halfedge, b.s);
  });
  BandSlices out;
  PolygonMesh polygons;
  polygons.positions = in.mesh.polygons().positions;
  out.band = in.band;
  out.tri = in.tri;
  out.pinned = in.pinned;
  std::size_t next_split = 0;
  for (int p = 0; p < in.num_slices(); ++p) {
    std::vector<int>& face = polygons.faces.emplace_back();
    for (int h = in.mesh.face_start(p); h < in.mesh.face_start(p) + in.mesh.degree(p); ++h) {
      auto push = [&](int from) {
        face.push_back(from);
        out.level.push_back(in.level[at(h)]);
        out.source_face.push_back(in.source_face[at(h)]);
        out.source_side.push_back(in.source_side[at(h)]);
      };
      push(in.from(h));
      while (next_split < splits.size() && splits[next_split].halfedge == h) {
        polygons.positions.push_back(splits[next_split].point);
        push(static_cast<int>(polygons.positions.size()) - 1);
        ++next_split;
      }
    }
  }
  out.mesh = HalfedgeMesh(std::move(polygons));
  return out;
}

bool Strips::has_hole() const {
  return std::any_of(loops.begin(), loops.end(),
                     [](const auto& entry) { return entry.second.size() > 1; });
}

namespace {

// A point of the disc as "(x, y, z) mm" for a message.
std::string point_mm(const Vec3& p) {
  std::ostringstream text;
  text << std::fixed << std::setprecision(1) << '(' << p.x() << ", " << p.y() << ", " << p.z()
       << ") mm";
  return text.str();
}

}  // namespace

Strips find_strips(const BandSlices& slices) {
  Strips strips;
  // Uniting the larger root under the smaller keeps each strip's root its
  // lowest slice.
  UnionFind sets(at(slices.num_slices()));
  for (int h = 0; h < slices.num_halfedges(); ++h) {
    const int tw = slices.twin(h);
    if (tw < 0 || slices.level[at(h)] >= 0) continue;
    const int a = sets.find(slices.slice(h));
    const int b = sets.find(slices.slice(tw));
    if (a != b) sets.unite(std::max(a, b), std::min(a, b));
  }
  strips.root.resize(at(slices.num_slices()));
  for (int p = 0; p < slices.num_slices(); ++p) strips.root[at(p)] = sets.find(p);
  auto on_boundary = [&](int h) { return slices.twin(h) < 0 || slices.level[at(h)] >= 0; };
  std::vector<bool> visited(at(slices.num_halfedges()), false);
  for (int h0 = 0; h0 < slices.num_halfedges(); ++h0) {
    if (visited[at(h0)] || !on_boundary(h0)) continue;
    std::vector<int> loop;
    int h = h0;
    do {
      visited[at(h)] = true;
      loop.push_back(h);
      int c = slices.next(h);
      int guard = 0;
      while (!on_boundary(c)) {
        c = slices.next(slices.twin(c));
        if (++guard > 100000) {
          throw std::runtime_error("the rows meet in a point the strips cannot go round, at " +
                                   point_mm(slices.position(slices.from(c))));
        }
      }
      h = c;
    } while (h != h0 && !visited[at(h)]);
    if (h != h0) {
      throw std::runtime_error("a strip's boundary does not close, at " +
                               point_mm(slices.position(slices.from(h0))));
    }
    strips.loops[strips.root[at(slices.slice(h0))]].push_back(std::move(loop));
  }
  return strips;
}

}  // namespace planner::stitch_meshing
