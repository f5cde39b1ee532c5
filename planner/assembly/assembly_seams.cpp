#include "planner/assembly/assembly_seams.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <set>
#include <string>
#include <utility>

#include "planner/common/index.hpp"
#include "planner/common/union_find.hpp"

namespace planner::assembly {

using nlohmann::json;

std::vector<Seam> schedule_cut_seams(const Model& m, const json& schedule_cuts,
                                     const std::filesystem::path& path) {
  std::vector<Seam> cut_seams;
  try {
    for (std::size_t c = 0; c < schedule_cuts.size(); ++c) {
      Seam seam;
      seam.kind = SeamKind::ScheduleCut;
      seam.arc = static_cast<int>(c);
      seam.lace = schedule_cuts[c].value("label", std::string("sew")) == "lace";
      for (const json& pair : schedule_cuts[c].at("faces")) {
        const int lower = pair.at(0).get<int>();
        const int upper = pair.at(1).get<int>();
        if (lower < 0 || upper < 0 || at(lower) >= m.mesh.faces.size() ||
            at(upper) >= m.mesh.faces.size())
          fail(path, "A004",
               "schedule_cuts[" + std::to_string(c) + "]: face out of range (the stitch mesh has " +
                   std::to_string(m.mesh.faces.size()) + " faces)");
        const int below = shared_side(m, lower, upper, EdgeRole::CourseOut);
        const int above = shared_side(m, upper, lower, EdgeRole::CourseIn);
        if (below == kNone || above == kNone)
          fail(path, "A004",
               "schedule_cuts[" + std::to_string(c) + "]: faces " + std::to_string(lower) +
                   " and " + std::to_string(upper) + " do not share a course edge");
        seam.sides[0].push_back({lower, below});
        seam.sides[1].push_back({upper, above});
      }
      if (seam.sides[0].empty()) continue;
      cut_seams.push_back(std::move(seam));
    }
  } catch (const json::exception& e) {
    fail(path, "A002", std::string("unexpected \"schedule_cuts\" content: ") + e.what());
  }
  return cut_seams;
}

std::vector<Seam> wale_seams(const Model& m) {
  std::vector<Seam> out;
  struct Pair {
    SideRef a, b;
    std::array<std::uint32_t, 2> v;
  };
  std::vector<Pair> pairs;
  for (const auto& [f, g] : m.wale_seams) {
    const int sf = shared_side(m, f, g, EdgeRole::Wale);
    const int sg = shared_side(m, g, f, EdgeRole::Wale);
    if (sf == kNone || sg == kNone) continue;
    pairs.push_back({{f, sf}, {g, sg}, side_vertices(m, {f, sf})});
  }
  UnionFind groups(pairs.size());
  auto pieces_of = [&](const Pair& p) {
    return std::minmax(m.piece_of_face[at(p.a.face)], m.piece_of_face[at(p.b.face)]);
  };
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    for (std::size_t j = i + 1; j < pairs.size(); ++j) {
      const auto& u = pairs[i].v;
      const auto& w = pairs[j].v;
      if ((u[0] == w[0] || u[0] == w[1] || u[1] == w[0] || u[1] == w[1]) &&
          pieces_of(pairs[i]) == pieces_of(pairs[j]))
        groups.unite(static_cast<int>(i), static_cast<int>(j));
    }
  }
  std::map<int, std::vector<std::size_t>> members;
  for (std::size_t i = 0; i < pairs.size(); ++i)
    members[groups.find(static_cast<int>(i))].push_back(i);
  for (const auto& [root, list] : members) {
    // Orient the stretch: walking it one way, the faces whose sides run
    // along the walk are on one side of the seam, the others on the other.
    std::map<std::uint32_t, std::vector<std::size_t>> at_vertex;
    for (std::size_t i : list) {
      for (std::uint32_t v : pairs[i].v) at_vertex[v].push_back(i);
    }
    std::map<std::size_t, bool> flipped;  // pair -> its side a runs against the walk
    std::vector<std::size_t> order;
    std::vector<std::pair<std::size_t, std::array<std::uint32_t, 2>>> stack{
        {list.front(), pairs[list.front()].v}};
    while (!stack.empty()) {
      const auto [i, walk] = stack.back();
      stack.pop_back();
      if (flipped.count(i)) continue;
      flipped[i] = walk != pairs[i].v;
      order.push_back(i);
      for (std::uint32_t v : {walk[0], walk[1]}) {
        for (std::size_t j : at_vertex[v]) {
          if (flipped.count(j)) continue;
          std::array<std::uint32_t, 2> next = pairs[j].v;
          // Continue the walk through v: leave v if we arrived there, enter it otherwise.
          if ((v == walk[1]) != (next[0] == v)) std::swap(next[0], next[1]);
          stack.push_back({j, next});
        }
      }
    }
    Seam seam;
    seam.kind = SeamKind::WaleSeam;
    for (std::size_t i : order) {
      const bool flip = flipped[i];
      seam.sides[flip ? 1 : 0].push_back(pairs[i].a);
      seam.sides[flip ? 0 : 1].push_back(pairs[i].b);
    }
    if (seam.sides[0].empty() || seam.sides[1].empty()) {
      // Every pair ran the same way: split them by face instead.
      seam.sides = {{{}, {}}};
      for (std::size_t i : order) {
        seam.sides[0].push_back(pairs[i].a);
        seam.sides[1].push_back(pairs[i].b);
      }
    }
    out.push_back(std::move(seam));
  }
  return out;
}

namespace {

// A boundary side placed along its cut-arc: `t` is the arc length of its
// midpoint's projection on the arc.
struct Item {
  double t = 0;
  SideRef side;
  int piece = 0;
};

// Per arc, its two sides' items (unsorted).
using ArcItems = std::map<int, std::array<std::vector<Item>, 2>>;

// Every boundary side carrying an arc is placed along the arc (its midpoint
// projected on the arc's polyline in proxy.obj) and put on one of the arc's
// two sides by the way it runs (the disc's boundary runs along one copy of
// a cut and back along the other).
ArcItems place_on_arcs(const Model& m, const std::unordered_map<std::uint64_t, int>& arc_of_key,
                       const std::map<int, ArcLine>& lines) {
  ArcItems arc_items;
  for (std::size_t f = 0; f < m.mesh.faces.size(); ++f) {
    const StitchFace& face = m.mesh.faces[f];
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      const SideRef side{static_cast<int>(f), static_cast<int>(i)};
      const auto it = arc_of_key.find(
          side_key(face.vertices[i], face.vertices[(i + 1) % face.vertices.size()]));
      if (it == arc_of_key.end() || other_side(m, side).face != kNone) continue;
      const auto line = lines.find(it->second);
      if (line == lines.end())
        fail(m.dir / "stitch-mesh.smobj", "A004",
             "face " + std::to_string(f + 1) + " lies on cut-arc " + std::to_string(it->second) +
                 ", which the cut does not have (run wearknit stitch-mesh again)");
      const ArcLine& pl = line->second;
      const auto v = side_vertices(m, side);
      const Eigen::Vector3d mid = side_mid(m, side);
      const Eigen::Vector3d along = m.mesh.positions[v[1]] - m.mesh.positions[v[0]];
      double best = std::numeric_limits<double>::infinity();
      Item item;
      item.side = side;
      item.piece = m.piece_of_face[f];
      double sign = 1;
      for (std::size_t k = 0; k + 1 < pl.points.size(); ++k) {
        const Eigen::Vector3d seg = pl.points[k + 1] - pl.points[k];
        const double len2 = seg.squaredNorm();
        const double u = len2 > 0 ? std::clamp((mid - pl.points[k]).dot(seg) / len2, 0.0, 1.0) : 0;
        const double d = (pl.points[k] + u * seg - mid).squaredNorm();
        if (d < best) {
          best = d;
          item.t = pl.start[k] + u * std::sqrt(len2);
          sign = along.dot(seg);
        }
      }
      if (pl.points.size() < 2) sign = 1;
      arc_items[it->second][sign >= 0 ? 0 : 1].push_back(item);
    }
  }
  return arc_items;
}

// Splits an arc's two sides where either passes from one piece to another;
// each stretch between two splits (of either side) is one seam. Empty when
// the arc cannot be split into two sides.
std::vector<Seam> split_arc(std::array<std::vector<Item>, 2>& items) {
  for (auto& list : items) {
    std::sort(list.begin(), list.end(), [](const Item& a, const Item& b) { return a.t < b.t; });
  }
  if (items[0].empty() || items[1].empty()) {
    // One copy only (both copies on one side of the projection, e.g. a
    // closed arc): split the sides at the middle of their list instead.
    auto& all = items[0].empty() ? items[1] : items[0];
    std::vector<Item> rest(all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2), all.end());
    all.resize(all.size() / 2);
    (items[0].empty() ? items[0] : items[1]) = std::move(rest);
    if (items[0].empty() || items[1].empty()) return {};
  }
  // Breakpoints where either side changes piece.
  std::vector<double> cuts_at;
  for (const auto& list : items) {
    for (std::size_t k = 1; k < list.size(); ++k) {
      if (list[k].piece != list[k - 1].piece) cuts_at.push_back(0.5 * (list[k].t + list[k - 1].t));
    }
  }
  std::sort(cuts_at.begin(), cuts_at.end());
  auto stretch_of = [&](double t) {
    return static_cast<int>(std::upper_bound(cuts_at.begin(), cuts_at.end(), t) - cuts_at.begin());
  };
  std::vector<Seam> parts(cuts_at.size() + 1);
  for (int s = 0; s < 2; ++s) {
    for (const Item& item : items[at(s)])
      parts[at(stretch_of(item.t))].sides[at(s)].push_back(item.side);
  }
  // A stretch with nothing on one side joins the neighbouring stretch.
  std::vector<Seam> merged;
  for (Seam& part : parts) {
    if (!merged.empty() && (part.sides[0].empty() || part.sides[1].empty() ||
                            merged.back().sides[0].empty() || merged.back().sides[1].empty())) {
      for (int s = 0; s < 2; ++s)
        merged.back().sides[at(s)].insert(merged.back().sides[at(s)].end(),
                                          part.sides[at(s)].begin(), part.sides[at(s)].end());
      continue;
    }
    merged.push_back(std::move(part));
  }
  if (!merged.empty() && (merged.back().sides[0].empty() || merged.back().sides[1].empty()) &&
      merged.size() > 1) {
    Seam last = std::move(merged.back());
    merged.pop_back();
    for (int s = 0; s < 2; ++s)
      merged.back().sides[at(s)].insert(merged.back().sides[at(s)].end(), last.sides[at(s)].begin(),
                                        last.sides[at(s)].end());
  }
  return merged;
}

}  // namespace

ArcSeams chain_seams(Model& m, const std::unordered_map<std::uint64_t, int>& arc_of_key,
                     const std::map<int, ArcLine>& lines) {
  ArcItems arc_items = place_on_arcs(m, arc_of_key, lines);
  ArcSeams out;
  for (const SeamChain& chain : m.chains) {
    // The chain's two sides, each side's items placed along the whole
    // chain: an arc walked backwards has its arc length and its sides
    // turned round (the disc's boundary runs along one copy of the chain
    // and back along the other, through every vertex where it passes).
    std::array<std::vector<Item>, 2> items;
    double offset = 0;
    for (std::size_t k = 0; k < chain.arcs.size(); ++k) {
      const int arc = chain.arcs[k];
      const auto line = lines.find(arc);
      const double length =
          line == lines.end() || line->second.start.empty() ? 0 : line->second.start.back();
      const auto found = arc_items.find(arc);
      if (found != arc_items.end()) {
        for (int s = 0; s < 2; ++s) {
          for (Item item : found->second[at(s)]) {
            item.t = offset + (chain.reversed[k] ? length - item.t : item.t);
            items[at(chain.reversed[k] ? 1 - s : s)].push_back(item);
          }
        }
      }
      offset += length;
    }
    std::vector<Seam> merged = split_arc(items);
    std::vector<Seam> parts;
    for (Seam& seam : merged) {
      if (seam.sides[0].empty() || seam.sides[1].empty()) continue;
      const ArcInfo& first = m.arcs[at(chain.arcs.front())];
      seam.kind = SeamKind::CutArc;
      seam.arc = first.id;
      seam.arcs = chain.arcs;
      seam.lace = first.lace;
      seam.labelled = first.labelled;
      seam.part = static_cast<int>(parts.size()) + 1;
      parts.push_back(std::move(seam));
    }
    for (Seam& seam : parts) {
      seam.parts = static_cast<int>(parts.size());
      (seam.lace ? out.lace : out.sew).push_back(std::move(seam));
    }
    for (const int arc : chain.arcs) m.arcs[at(arc)].seams = static_cast<int>(parts.size());
  }
  return out;
}

void number_seams(Model& m, std::vector<Seam> cut_seams, std::vector<Seam> wale, ArcSeams arcs) {
  // Closing order: first what rebuilds the knit sheet (scheduler cuts, wale
  // seams), then the arcs to sew, all before dressing; the laced arcs last,
  // on the wearer (§5). The parts of a seam follow each other and share its
  // number.
  for (auto* list : {&cut_seams, &wale, &arcs.sew}) {
    for (Seam& s : *list) {
      if (!s.lace) m.seams.push_back(std::move(s));
    }
  }
  const std::size_t sewn_parts = m.seams.size();
  for (auto* list : {&cut_seams, &wale, &arcs.lace}) {
    for (Seam& s : *list) {
      if (s.lace) m.seams.push_back(std::move(s));
    }
  }
  int number = 0;
  for (std::size_t i = 0; i < m.seams.size(); ++i) {
    Seam& seam = m.seams[i];
    if (seam.part == 1) ++number;
    seam.number = number;
    if (i + 1 == sewn_parts) m.sewn = number;
    for (int s = 0; s < 2; ++s) {
      const auto& list = seam.sides[at(s)];
      seam.label_at[at(s)] = list[list.size() / 2];
      seam.piece[at(s)] = m.piece_of_face[at(seam.label_at[at(s)].face)];
      double length = 0;
      for (const SideRef& side : list) {
        m.seam_of_side[side] = static_cast<int>(i);
        const auto v = side_vertices(m, side);
        length += (m.mesh.positions[v[1]] - m.mesh.positions[v[0]]).norm();
      }
      seam.stretch_mm[at(s)] = length;
    }
  }
  m.numbered = number;
}

}  // namespace planner::assembly
