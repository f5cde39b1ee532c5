#include "planner/assembly/assembly.hpp"

#include <cairo-pdf.h>
#include <cairo.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "knitout/output_file.hpp"
#include "planner/common/index.hpp"
#include "planner/common/union_find.hpp"
#include "planner/render/png.hpp"
#include "planner/schedule/piece_layout.hpp"
#include "planner/schedule/schedule.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "planner/wearability/wearability_io.hpp"

namespace planner {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A failure with its message already formatted.
struct Failure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void fail(const fs::path& file, const char* code, const std::string& message) {
  throw Failure(file.string() + ": error: [" + code + "] " + message);
}

// ---------------------------------------------------------------- reading

json read_json_file(const fs::path& path) {
  std::ifstream in(path);
  if (!in) fail(path, "A001", "cannot open file (a plan folder needs it for the assembly guide)");
  json value = json::parse(in, nullptr, false);
  if (value.is_discarded()) fail(path, "A002", "not valid JSON");
  if (!value.is_object()) fail(path, "A002", "not a JSON object");
  return value;
}

std::string first_error(const knitout::DiagnosticSink& sink) {
  for (const knitout::Diagnostic& d : sink.diagnostics()) {
    if (d.severity == knitout::Severity::Error) return knitout::format(d);
  }
  return "unknown problem";
}

std::uint64_t side_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

struct SideRef {
  int face = 0;
  int side = 0;
  bool operator<(const SideRef& o) const { return face != o.face ? face < o.face : side < o.side; }
  bool operator==(const SideRef& o) const { return face == o.face && side == o.side; }
};

enum class SeamKind { ScheduleCut, WaleSeam, CutArc };

struct Seam {
  int number = 0;
  bool lace = false;
  bool labelled = true;  // false: the arc has no wearability label (treated as sew)
  SeamKind kind = SeamKind::CutArc;
  int arc = -1;  // cuts.json arc id (CutArc), or index in schedule_cuts (ScheduleCut)
  int part = 1;
  int parts = 1;
  std::array<std::vector<SideRef>, 2> sides;  // the two stretches that are joined, in order
  std::array<int, 2> piece{{0, 0}};           // the piece each side's number is drawn on
  std::array<SideRef, 2> label_at;            // the side each side's number is drawn on
};

struct ArcInfo {
  int id = 0;
  bool lace = false;
  bool labelled = false;
  double length_mm = 0;
  int seams = 0;  // numbered seams made from it
};

struct Model {
  fs::path dir;
  StitchMesh mesh;
  Schedule schedule;
  std::vector<PieceLayout> layouts;
  std::vector<int> piece_of_face;
  std::vector<int> layout_index;  // face -> index in its piece's layout
  std::unordered_map<std::uint64_t, std::vector<SideRef>> sides_by_key;
  std::vector<Seam> seams;  // in closing order, numbered 1..n
  std::vector<ArcInfo> arcs;
  std::map<SideRef, int> seam_of_side;
  int sewn = 0;
};

SideRef other_side(const Model& m, SideRef s) {
  const StitchFace& face = m.mesh.faces[at(s.face)];
  const std::size_t n = face.vertices.size();
  const auto it =
      m.sides_by_key.find(side_key(face.vertices[at(s.side)], face.vertices[(at(s.side) + 1) % n]));
  if (it != m.sides_by_key.end()) {
    for (const SideRef& o : it->second) {
      if (!(o == s)) return o;
    }
  }
  return {kNone, kNone};
}

std::array<std::uint32_t, 2> side_vertices(const Model& m, SideRef s) {
  const StitchFace& face = m.mesh.faces[at(s.face)];
  return {face.vertices[at(s.side)], face.vertices[(at(s.side) + 1) % face.vertices.size()]};
}

Eigen::Vector3d side_mid(const Model& m, SideRef s) {
  const auto v = side_vertices(m, s);
  return 0.5 * (m.mesh.positions[v[0]] + m.mesh.positions[v[1]]);
}

// The side of `face` shared with `other` (of the given role), or kNone.
int shared_side(const Model& m, int face, int other, EdgeRole role) {
  const StitchFace& f = m.mesh.faces[at(face)];
  for (std::size_t i = 0; i < f.vertices.size(); ++i) {
    if (f.roles[i] != role) continue;
    if (other_side(m, {face, static_cast<int>(i)}).face == other) return static_cast<int>(i);
  }
  return kNone;
}

void load(Model& m, const fs::path& dir) {
  m.dir = dir;
  if (!fs::is_directory(dir)) fail(dir, "A001", "not a folder");
  const fs::path cuts_path = dir / "cuts.json";
  const fs::path report_path = dir / "report.json";
  const fs::path smobj_path = dir / "stitch-mesh.smobj";
  const fs::path proxy_path = dir / "proxy.obj";
  const json cuts = read_json_file(cuts_path);
  const json report = read_json_file(report_path);

  // The stitch mesh as the scheduler read it, and the cut-arc of every
  // boundary side (the `# arc` lines), read with the scheduler's reader.
  {
    std::ifstream probe(smobj_path);
    if (!probe) fail(smobj_path, "A001", "cannot open file (run wearknit stitch-mesh first)");
  }
  std::unordered_map<std::uint64_t, int> arc_of_key;
  {
    std::ifstream in(smobj_path);
    knitout::DiagnosticSink sink;
    auto read = parse_smobj(in, smobj_path.string(), sink);
    if (!read || sink.has_errors()) fail(smobj_path, "A003", "unreadable: " + first_error(sink));
    m.mesh = std::move(*read);
    // Without a `# wearknit` stitch-size line, the paper's swatch (§8.1:
    // 40 x 40 stitches measure 42 x 115 mm).
    if (!(m.mesh.course_mm > 0)) m.mesh.course_mm = 1.05;
    if (!(m.mesh.wale_mm > 0)) m.mesh.wale_mm = 2.875;
    for (const StitchFace& f : m.mesh.faces) {
      for (std::size_t i = 0; i < f.vertices.size() && i < f.arcs.size(); ++i) {
        if (f.arcs[i] != kNoArc)
          arc_of_key[side_key(f.vertices[i], f.vertices[(i + 1) % f.vertices.size()])] = f.arcs[i];
      }
    }
  }
  for (std::size_t f = 0; f < m.mesh.faces.size(); ++f) {
    const StitchFace& face = m.mesh.faces[f];
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      m.sides_by_key[side_key(face.vertices[i], face.vertices[(i + 1) % face.vertices.size()])]
          .push_back({static_cast<int>(f), static_cast<int>(i)});
    }
  }

  // The pieces laid flat: as the scheduler wrote them
  // (pieces/piece-N.layout.json), else from the schedule rebuilt from the
  // seed, number of trials and options it recorded (its result depends on
  // nothing else, docs/scheduling.md §7.3) and checked against what it
  // wrote.
  if (!report.contains("schedule") || !report["schedule"].is_object())
    fail(report_path, "A004", "no \"schedule\" member: run wearknit schedule first");
  const json& sched = report["schedule"];
  ScheduleParams params;
  try {
    params.seed = sched.at("seed").get<std::uint64_t>();
    params.trials = sched.at("trials").get<int>();
    // The options that change the schedule; a report written before
    // held loops could be set aside has no "max_aside".
    params.max_patch_shift = sched.value("max_shift", params.max_patch_shift);
    params.improve = sched.value("improve", params.improve);
    params.max_aside = sched.value("max_aside", 0);
    if (!sched.at("pieces").is_array()) throw std::runtime_error("\"pieces\" is not a list");
  } catch (const std::exception& e) {
    fail(report_path, "A002", std::string("unexpected \"schedule\" content: ") + e.what());
  }
  if (params.trials < 1) fail(report_path, "A002", "\"schedule\".\"trials\" is less than 1");
  const std::size_t pieces = sched["pieces"].size();
  bool from_files = pieces > 0;
  for (std::size_t p = 1; p <= pieces && from_files; ++p)
    from_files = fs::exists(dir / "pieces" / ("piece-" + std::to_string(p) + ".layout.json"));
  try {
    if (from_files) {
      build_rows(m.mesh, m.schedule);  // the wale seams (§7.1); nothing random
      for (std::size_t p = 1; p <= pieces; ++p) {
        const fs::path path = dir / "pieces" / ("piece-" + std::to_string(p) + ".layout.json");
        std::string error;
        auto layout = read_piece_layout(path.string(), &error);
        if (!layout) throw Failure(error.insert(error.find(": ") + 2, "error: [A002] "));
        m.layouts.push_back(std::move(*layout));
      }
    } else {
      m.schedule = schedule(m.mesh, params);
      if (m.schedule.pieces.size() != pieces)
        fail(report_path, "A004",
             "lists " + std::to_string(pieces) + " pieces but the schedule rebuilt from " +
                 smobj_path.filename().string() + " (seed " + std::to_string(params.seed) + ", " +
                 std::to_string(params.trials) + " trials) has " +
                 std::to_string(m.schedule.pieces.size()) +
                 ": the folder's files do not belong together (run wearknit schedule again)");
      m.layouts = piece_layouts(m.schedule);
    }
  } catch (const ScheduleError& e) {
    fail(smobj_path, "A003", std::string("cannot be scheduled: ") + e.what());
  }
  m.piece_of_face.assign(m.mesh.faces.size(), kNone);
  m.layout_index.assign(m.mesh.faces.size(), kNone);
  for (std::size_t p = 0; p < m.layouts.size(); ++p) {
    for (std::size_t i = 0; i < m.layouts[p].faces.size(); ++i) {
      const int face = m.layouts[p].faces[i].face;
      if (at(face) >= m.mesh.faces.size() || m.piece_of_face[at(face)] != kNone)
        fail(dir / "pieces" / ("piece-" + std::to_string(p + 1) + ".layout.json"), "A004",
             "face " + std::to_string(face) +
                 (at(face) >= m.mesh.faces.size() ? " is not a face of " : " is twice in ") +
                 (at(face) >= m.mesh.faces.size() ? smobj_path.filename().string()
                                                  : std::string("the pieces")) +
                 ": the folder's files do not belong together (run wearknit schedule again)");
      m.piece_of_face[at(face)] = static_cast<int>(p);
      m.layout_index[at(face)] = static_cast<int>(i);
    }
  }
  for (std::size_t f = 0; f < m.mesh.faces.size(); ++f) {
    if (m.piece_of_face[f] == kNone)
      fail(dir / "pieces", "A004",
           "stitch-mesh face " + std::to_string(f) +
               " is in no piece: the folder's files do not belong together (run wearknit "
               "schedule again)");
  }

  // cuts.json: arcs (ids, labels) and the scheduler's cuts.
  if (!cuts.contains("arcs") || !cuts["arcs"].is_array())
    fail(cuts_path, "A002", "no \"arcs\" list (write it with wearknit cut)");
  knitout::DiagnosticSink proxy_sink;
  const auto proxy = read_stage_mesh(proxy_path.string(), proxy_sink);
  if (!proxy) fail(proxy_path, "A003", "unreadable: " + first_error(proxy_sink));

  struct Polyline {
    std::vector<Eigen::Vector3d> points;
    std::vector<double> start;  // arc length at each point
  };
  std::map<int, Polyline> lines;
  std::map<int, std::size_t> arc_slot;
  for (std::size_t i = 0; i < cuts["arcs"].size(); ++i) {
    const json& a = cuts["arcs"][i];
    ArcInfo info;
    Polyline line;
    try {
      info.id = a.contains("id") ? a.at("id").get<int>() : static_cast<int>(i);
      if (a.contains("label") && a["label"].is_string()) {
        const std::string label = a["label"].get<std::string>();
        if (label != "sew" && label != "lace")
          fail(cuts_path, "A002",
               "arc " + std::to_string(info.id) + ": label \"" + label + "\" is not sew or lace");
        info.lace = label == "lace";
        info.labelled = true;
      }
      info.length_mm = a.value("length_mm", 0.0);
      std::uint32_t last = 0;
      bool first = true;
      for (const json& e : a.at("edges")) {
        auto u = e.at(0).get<std::int64_t>();
        auto v = e.at(1).get<std::int64_t>();
        for (std::int64_t w : {u, v}) {
          if (w < 0 || static_cast<std::size_t>(w) >= proxy->positions.size())
            fail(cuts_path, "A004",
                 "arc " + std::to_string(info.id) + ": vertex " + std::to_string(w) +
                     " is not a vertex of " + proxy_path.filename().string() + " (" +
                     std::to_string(proxy->positions.size()) + " vertices)");
        }
        if (!first && static_cast<std::uint32_t>(v) == last) std::swap(u, v);
        if (first || static_cast<std::uint32_t>(u) != last)
          line.points.push_back(proxy->positions[static_cast<std::size_t>(u)]);
        line.points.push_back(proxy->positions[static_cast<std::size_t>(v)]);
        last = static_cast<std::uint32_t>(v);
        first = false;
      }
    } catch (const json::exception& e) {
      fail(cuts_path, "A002", "arc " + std::to_string(i) + ": unexpected content: " + e.what());
    }
    if (arc_slot.count(info.id))
      fail(cuts_path, "A002", "arc id " + std::to_string(info.id) + " appears twice");
    double s = 0;
    for (std::size_t k = 0; k < line.points.size(); ++k) {
      if (k > 0) s += (line.points[k] - line.points[k - 1]).norm();
      line.start.push_back(s);
    }
    arc_slot[info.id] = m.arcs.size();
    lines[info.id] = std::move(line);
    m.arcs.push_back(info);
  }

  // Scheduler cuts: must be the ones the rebuilt schedule makes.
  std::set<std::pair<int, int>> rebuilt;
  for (const CourseEdge& e : m.schedule.edges) {
    if (e.cut) rebuilt.insert({e.lower, e.upper});
  }
  std::set<std::pair<int, int>> listed;
  std::vector<Seam> cut_seams;
  if (cuts.contains("schedule_cuts")) {
    try {
      const json& list = cuts.at("schedule_cuts");
      for (std::size_t c = 0; c < list.size(); ++c) {
        Seam seam;
        seam.kind = SeamKind::ScheduleCut;
        seam.arc = static_cast<int>(c);
        seam.lace = list[c].value("label", std::string("sew")) == "lace";
        for (const json& pair : list[c].at("faces")) {
          const int lower = pair.at(0).get<int>();
          const int upper = pair.at(1).get<int>();
          if (lower < 0 || upper < 0 || at(lower) >= m.mesh.faces.size() ||
              at(upper) >= m.mesh.faces.size())
            fail(cuts_path, "A004",
                 "schedule_cuts[" + std::to_string(c) +
                     "]: face out of range (the stitch mesh has " +
                     std::to_string(m.mesh.faces.size()) + " faces)");
          listed.insert({lower, upper});
          const int below = shared_side(m, lower, upper, EdgeRole::CourseOut);
          const int above = shared_side(m, upper, lower, EdgeRole::CourseIn);
          if (below == kNone || above == kNone)
            fail(cuts_path, "A004",
                 "schedule_cuts[" + std::to_string(c) + "]: faces " + std::to_string(lower) +
                     " and " + std::to_string(upper) + " do not share a course edge");
          seam.sides[0].push_back({lower, below});
          seam.sides[1].push_back({upper, above});
        }
        if (seam.sides[0].empty()) continue;
        cut_seams.push_back(std::move(seam));
      }
    } catch (const json::exception& e) {
      fail(cuts_path, "A002", std::string("unexpected \"schedule_cuts\" content: ") + e.what());
    }
  }
  if (!from_files && listed != rebuilt)
    fail(cuts_path, "A004",
         "\"schedule_cuts\" lists " + std::to_string(listed.size()) +
             " cut course edges but the schedule rebuilt from report.json cuts " +
             std::to_string(rebuilt.size()) +
             ": the folder's files do not belong together (run wearknit schedule again)");

  // Wale seams (§7.1): the shared wale sides, grouped into stretches that
  // touch and join the same two pieces.
  std::vector<Seam> wale_seams;
  {
    struct Pair {
      SideRef a, b;
      std::array<std::uint32_t, 2> v;
    };
    std::vector<Pair> pairs;
    for (const auto& [f, g] : m.schedule.wale_seams) {
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
      wale_seams.push_back(std::move(seam));
    }
  }

  // Cut-arcs: every boundary side carrying an arc is placed along the arc
  // (its midpoint projected on the arc's polyline in proxy.obj) and put on
  // one of the arc's two sides by the way it runs (the disc's boundary runs
  // along one copy of a cut and back along the other). Each side is split
  // where it passes from one piece to another; each stretch between two
  // splits (of either side) is one numbered seam.
  struct Item {
    double t = 0;
    SideRef side;
    int piece = 0;
  };
  std::map<int, std::array<std::vector<Item>, 2>> arc_items;
  for (std::size_t f = 0; f < m.mesh.faces.size(); ++f) {
    const StitchFace& face = m.mesh.faces[f];
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      const SideRef side{static_cast<int>(f), static_cast<int>(i)};
      const auto it = arc_of_key.find(
          side_key(face.vertices[i], face.vertices[(i + 1) % face.vertices.size()]));
      if (it == arc_of_key.end() || other_side(m, side).face != kNone) continue;
      const auto line = lines.find(it->second);
      if (line == lines.end())
        fail(smobj_path, "A004",
             "face " + std::to_string(f + 1) + " lies on cut-arc " + std::to_string(it->second) +
                 ", which " + cuts_path.filename().string() + " does not list");
      const Polyline& pl = line->second;
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
  std::vector<Seam> sew_arcs;
  std::vector<Seam> lace_arcs;
  for (ArcInfo& info : m.arcs) {
    auto found = arc_items.find(info.id);
    if (found == arc_items.end()) continue;
    auto& items = found->second;
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
      if (items[0].empty() || items[1].empty()) continue;
    }
    // Breakpoints where either side changes piece.
    std::vector<double> cuts_at;
    for (const auto& list : items) {
      for (std::size_t k = 1; k < list.size(); ++k) {
        if (list[k].piece != list[k - 1].piece)
          cuts_at.push_back(0.5 * (list[k].t + list[k - 1].t));
      }
    }
    std::sort(cuts_at.begin(), cuts_at.end());
    auto stretch_of = [&](double t) {
      return static_cast<int>(std::upper_bound(cuts_at.begin(), cuts_at.end(), t) -
                              cuts_at.begin());
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
        merged.back().sides[at(s)].insert(merged.back().sides[at(s)].end(),
                                          last.sides[at(s)].begin(), last.sides[at(s)].end());
    }
    int part_no = 0;
    for (Seam& seam : merged) {
      if (seam.sides[0].empty() || seam.sides[1].empty()) continue;
      seam.kind = SeamKind::CutArc;
      seam.arc = info.id;
      seam.lace = info.lace;
      seam.labelled = info.labelled;
      seam.part = ++part_no;
      (info.lace ? lace_arcs : sew_arcs).push_back(std::move(seam));
    }
    for (auto* list : {&sew_arcs, &lace_arcs}) {
      for (Seam& s : *list) {
        if (s.kind == SeamKind::CutArc && s.arc == info.id) s.parts = part_no;
      }
    }
    info.seams = part_no;
  }

  // Closing order: first what rebuilds the knit sheet (scheduler cuts, wale
  // seams), then the arcs to sew, all before dressing; the laced arcs last,
  // on the wearer (§5).
  for (auto* list : {&cut_seams, &wale_seams, &sew_arcs}) {
    for (Seam& s : *list) {
      if (!s.lace) m.seams.push_back(std::move(s));
    }
  }
  m.sewn = static_cast<int>(m.seams.size());
  for (auto* list : {&cut_seams, &wale_seams, &lace_arcs}) {
    for (Seam& s : *list) {
      if (s.lace) m.seams.push_back(std::move(s));
    }
  }
  for (std::size_t i = 0; i < m.seams.size(); ++i) {
    Seam& seam = m.seams[i];
    seam.number = static_cast<int>(i) + 1;
    for (int s = 0; s < 2; ++s) {
      const auto& list = seam.sides[at(s)];
      seam.label_at[at(s)] = list[list.size() / 2];
      seam.piece[at(s)] = m.piece_of_face[at(seam.label_at[at(s)].face)];
      for (const SideRef& side : seam.sides[at(s)]) m.seam_of_side[side] = static_cast<int>(i);
    }
  }
}

// ---------------------------------------------------------------- drawing

struct P2 {
  double x = 0;
  double y = 0;
};

struct Rgb {
  double r = 0, g = 0, b = 0;
};

const Rgb kSewColour{0.10, 0.35, 0.80};
const Rgb kLaceColour{0.85, 0.15, 0.15};
const Rgb kEdgeColour{0.15, 0.15, 0.15};
const Rgb kFabric{0.91, 0.89, 0.84};
const Rgb kText{0.1, 0.1, 0.1};
const Rgb kWhite{1, 1, 1};

enum class Anchor { Start, Middle, End };

// The two back ends of the guide's pages: SVG text (numbers stay text, so
// they can be searched) and cairo (PDF).
class Canvas {
 public:
  virtual ~Canvas() = default;
  virtual void next_page() = 0;
  virtual void fill_polygons(const std::vector<std::vector<P2>>& polygons, Rgb fill) = 0;
  virtual void polyline(const std::vector<P2>& points, Rgb colour, double width, bool dashed,
                        const char* cls) = 0;
  virtual void circle(P2 centre, double radius, Rgb fill, Rgb stroke, double width) = 0;
  virtual void text(P2 at, const std::string& s, double size, Rgb colour, Anchor anchor, bool bold,
                    const char* cls) = 0;
};

constexpr double kPageW = 842;  // A4 landscape, points
constexpr double kPageH = 595;
constexpr double kMargin = 30;

std::string hex(Rgb c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", static_cast<int>(std::lround(c.r * 255)),
                static_cast<int>(std::lround(c.g * 255)), static_cast<int>(std::lround(c.b * 255)));
  return buf;
}

std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '&')
      out += "&amp;";
    else if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// Pages are stacked top to bottom in one SVG document, each in a <g
// class="page">.
class SvgCanvas final : public Canvas {
 public:
  explicit SvgCanvas(int pages) : pages_(pages) {
    body_ << std::fixed;
    body_.precision(2);
    open_page();
  }
  void next_page() override {
    body_ << "</g>\n";
    ++page_;
    open_page();
  }
  void fill_polygons(const std::vector<std::vector<P2>>& polygons, Rgb fill) override {
    if (polygons.empty()) return;
    body_ << "<path fill=\"" << hex(fill) << "\" d=\"";
    for (const auto& poly : polygons) {
      for (std::size_t i = 0; i < poly.size(); ++i)
        body_ << (i == 0 ? "M" : "L") << poly[i].x << ' ' << poly[i].y << ' ';
      body_ << "Z ";
    }
    body_ << "\"/>\n";
  }
  void polyline(const std::vector<P2>& points, Rgb colour, double width, bool dashed,
                const char* cls) override {
    if (points.size() < 2) return;
    body_ << "<polyline class=\"" << cls << "\" fill=\"none\" stroke=\"" << hex(colour)
          << "\" stroke-width=\"" << width << "\" stroke-linecap=\"round\"";
    if (dashed) body_ << " stroke-dasharray=\"5 3\"";
    body_ << " points=\"";
    for (const P2& p : points) body_ << p.x << ',' << p.y << ' ';
    body_ << "\"/>\n";
  }
  void circle(P2 c, double radius, Rgb fill, Rgb stroke, double width) override {
    body_ << "<circle cx=\"" << c.x << "\" cy=\"" << c.y << "\" r=\"" << radius << "\" fill=\""
          << hex(fill) << "\" stroke=\"" << hex(stroke) << "\" stroke-width=\"" << width
          << "\"/>\n";
  }
  void text(P2 p, const std::string& s, double size, Rgb colour, Anchor anchor, bool bold,
            const char* cls) override {
    body_ << "<text class=\"" << cls << "\" x=\"" << p.x << "\" y=\"" << p.y
          << "\" font-family=\"sans-serif\" font-size=\"" << size << "\" fill=\"" << hex(colour)
          << '"';
    if (bold) body_ << " font-weight=\"bold\"";
    if (anchor != Anchor::Start)
      body_ << " text-anchor=\"" << (anchor == Anchor::Middle ? "middle" : "end") << '"';
    body_ << '>' << escape(s) << "</text>\n";
  }
  std::string document() const {
    std::ostringstream out;
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kPageW << "pt\" height=\""
        << kPageH * pages_ << "pt\" viewBox=\"0 0 " << kPageW << ' ' << kPageH * pages_ << "\">\n"
        << body_.str() << "</g>\n</svg>\n";
    return out.str();
  }

 private:
  void open_page() {
    body_ << "<g class=\"page\" transform=\"translate(0 " << kPageH * page_ << ")\">\n"
          << "<rect width=\"" << kPageW << "\" height=\"" << kPageH
          << "\" fill=\"#ffffff\" stroke=\"#bbbbbb\"/>\n";
  }
  int pages_ = 1;
  int page_ = 0;
  std::ostringstream body_;
};

class CairoCanvas final : public Canvas {
 public:
  // only_page >= 0: draw that page only (0-based), onto a single-page
  // surface such as a PNG image.
  explicit CairoCanvas(cairo_t* cr, int only_page = -1) : cr_(cr), only_(only_page) {}
  void next_page() override {
    ++page_;
    if (only_ < 0) cairo_show_page(cr_);
  }
  void fill_polygons(const std::vector<std::vector<P2>>& polygons, Rgb fill) override {
    if (skip()) return;
    for (const auto& poly : polygons) {
      for (std::size_t i = 0; i < poly.size(); ++i)
        (i == 0 ? cairo_move_to : cairo_line_to)(cr_, poly[i].x, poly[i].y);
      cairo_close_path(cr_);
    }
    cairo_set_source_rgb(cr_, fill.r, fill.g, fill.b);
    cairo_fill(cr_);
  }
  void polyline(const std::vector<P2>& points, Rgb colour, double width, bool dashed,
                const char*) override {
    if (skip() || points.size() < 2) return;
    for (std::size_t i = 0; i < points.size(); ++i)
      (i == 0 ? cairo_move_to : cairo_line_to)(cr_, points[i].x, points[i].y);
    cairo_set_source_rgb(cr_, colour.r, colour.g, colour.b);
    cairo_set_line_width(cr_, width);
    cairo_set_line_cap(cr_, CAIRO_LINE_CAP_ROUND);
    const double dash[2] = {5, 3};
    cairo_set_dash(cr_, dash, dashed ? 2 : 0, 0);
    cairo_stroke(cr_);
    cairo_set_dash(cr_, dash, 0, 0);
  }
  void circle(P2 c, double radius, Rgb fill, Rgb stroke, double width) override {
    if (skip()) return;
    cairo_new_path(cr_);
    cairo_arc(cr_, c.x, c.y, radius, 0, 2 * M_PI);
    cairo_set_source_rgb(cr_, fill.r, fill.g, fill.b);
    cairo_fill_preserve(cr_);
    cairo_set_source_rgb(cr_, stroke.r, stroke.g, stroke.b);
    cairo_set_line_width(cr_, width);
    cairo_stroke(cr_);
  }
  void text(P2 p, const std::string& s, double size, Rgb colour, Anchor anchor, bool bold,
            const char*) override {
    if (skip()) return;
    cairo_select_font_face(cr_, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                           bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr_, size);
    cairo_text_extents_t ext;
    cairo_text_extents(cr_, s.c_str(), &ext);
    double x = p.x;
    if (anchor == Anchor::Middle) x -= ext.x_advance / 2;
    if (anchor == Anchor::End) x -= ext.x_advance;
    cairo_move_to(cr_, x, p.y);
    cairo_set_source_rgb(cr_, colour.r, colour.g, colour.b);
    cairo_show_text(cr_, s.c_str());
    cairo_new_path(cr_);
  }

 private:
  bool skip() const { return only_ >= 0 && page_ != only_; }
  cairo_t* cr_;
  int only_ = -1;
  int page_ = 0;
};

// Where a piece goes: its page, its top-left corner and scale.
struct Placement {
  int piece = 0;
  int page = 0;
  double x = 0, y = 0;  // top-left of the drawing area on the page
  double scale = 1;     // points per mm
  double w_mm = 0, h_mm = 0;
};

constexpr double kPointsPerMm = 72.0 / 25.4;
constexpr double kCaption = 16;
constexpr double kGap = 18;

struct PageLines {
  std::vector<std::string> lines;
};

std::string seam_line(const Model& m, const Seam& s) {
  std::ostringstream out;
  out << s.number << ". " << (s.lace ? "lace" : "sew") << "  piece " << s.piece[0] + 1
      << " to piece " << s.piece[1] + 1 << "  ";
  switch (s.kind) {
    case SeamKind::ScheduleCut: {
      const int lower = s.label_at[0].face;
      const int upper = s.label_at[1].face;
      out << "scheduling cut " << s.arc + 1 << " (rows "
          << m.layouts[at(m.piece_of_face[at(lower)])].faces[at(m.layout_index[at(lower)])].level +
                 1
          << " / "
          << m.layouts[at(m.piece_of_face[at(upper)])].faces[at(m.layout_index[at(upper)])].level +
                 1
          << ")";
      break;
    }
    case SeamKind::WaleSeam:
      out << "wale seam (rows knit in opposite directions)";
      break;
    case SeamKind::CutArc:
      out << "cut-arc " << s.arc;
      if (s.parts > 1) out << " part " << s.part << " of " << s.parts;
      if (!s.labelled) out << " (no wearability label)";
      break;
  }
  out << ", " << s.sides[0].size() << " / " << s.sides[1].size() << " stitch sides";
  return out.str();
}

std::vector<std::string> order_lines(const Model& m) {
  std::vector<std::string> lines;
  for (const Seam& s : m.seams) {
    if (s.number == m.sewn + 1) lines.push_back("-- put the garment on the wearer, then --");
    lines.push_back(seam_line(m, s));
  }
  for (const ArcInfo& a : m.arcs) {
    if (a.seams == 0) {
      std::ostringstream out;
      out << "cut-arc " << a.id << " (" << (a.lace ? "lace" : "sew")
          << "): no stitch side lies on it (shorter than a stitch); nothing to join";
      lines.push_back(out.str());
    }
  }
  return lines;
}

constexpr double kLine = 11;
constexpr double kTableTop = 200;
constexpr int kColumns = 2;

int lines_per_page(bool first) {
  const double top = first ? kTableTop : kMargin + 30;
  return static_cast<int>((kPageH - kMargin - top) / kLine) * kColumns;
}

// Pieces packed in shelves; returns placements and the number of piece pages.
std::string caption(const Model& m, const Placement& pl) {
  const PieceLayout& layout = m.layouts[at(pl.piece)];
  std::ostringstream out;
  out << "piece " << pl.piece + 1 << ": " << layout.needles << " needles x " << layout.levels
      << " rows, " << layout.faces.size() << " stitches";
  if (std::abs(pl.scale - kPointsPerMm) > 1e-9) {
    out.precision(2);
    out << std::fixed << " (x" << pl.scale / kPointsPerMm << ")";
  } else {
    out << " (true size)";
  }
  return out.str();
}

std::vector<Placement> place_pieces(const Model& m, int first_page, int* pages) {
  std::vector<Placement> out;
  const double area_w = kPageW - 2 * kMargin;
  const double area_h = kPageH - 2 * kMargin - 20;
  double x = kMargin;
  double y = kMargin + 20;
  double shelf = 0;
  int page = first_page;
  bool any = false;
  for (std::size_t p = 0; p < m.layouts.size(); ++p) {
    Placement pl;
    pl.piece = static_cast<int>(p);
    pl.w_mm = std::max(1, m.layouts[p].needles + 1) * m.mesh.course_mm;
    pl.h_mm = std::max(1, m.layouts[p].levels) * m.mesh.wale_mm;
    const double fit = std::min(area_w / pl.w_mm, (area_h - kCaption) / pl.h_mm);
    // Twice the true size when it fits (room for the seam numbers), small
    // pieces enlarged to stay readable, large ones scaled down to the page.
    const double readable = 90.0 / std::max(pl.w_mm, pl.h_mm);
    pl.scale = std::min(fit, std::max(2 * kPointsPerMm, readable));
    // Room for the caption too (about 5 points per character at 9 points).
    const double w = std::max(pl.w_mm * pl.scale, 5.0 * static_cast<double>(caption(m, pl).size()));
    const double h = pl.h_mm * pl.scale + kCaption;
    if (any && x + w > kMargin + area_w) {
      x = kMargin;
      y += shelf + kGap;
      shelf = 0;
    }
    if (any && y + h > kMargin + 20 + area_h) {
      ++page;
      x = kMargin;
      y = kMargin + 20;
      shelf = 0;
    }
    pl.page = page;
    pl.x = x;
    pl.y = y;
    out.push_back(pl);
    x += w + kGap;
    shelf = std::max(shelf, h);
    any = true;
  }
  *pages = any ? page - first_page + 1 : 0;
  return out;
}

// Joins segments that meet end to start into polylines.
std::vector<std::vector<P2>> chain(std::vector<std::array<P2, 2>> segments) {
  std::vector<std::vector<P2>> out;
  auto same = [](P2 a, P2 b) { return std::abs(a.x - b.x) < 1e-6 && std::abs(a.y - b.y) < 1e-6; };
  std::vector<bool> used(segments.size(), false);
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (used[i]) continue;
    used[i] = true;
    std::vector<P2> line{segments[i][0], segments[i][1]};
    for (bool grew = true; grew;) {
      grew = false;
      for (std::size_t j = 0; j < segments.size(); ++j) {
        if (used[j]) continue;
        auto s = segments[j];
        if (same(s[1], line.front()) || same(s[0], line.front())) {
          if (same(s[0], line.front())) std::swap(s[0], s[1]);
          line.insert(line.begin(), s[0]);
        } else if (same(s[0], line.back()) || same(s[1], line.back())) {
          if (same(s[1], line.back())) std::swap(s[0], s[1]);
          line.push_back(s[1]);
        } else {
          continue;
        }
        used[j] = true;
        grew = true;
      }
    }
    out.push_back(std::move(line));
  }
  return out;
}

void draw_legend(Canvas& c, P2 at) {
  c.text({at.x, at.y}, "Legend", 11, kText, Anchor::Start, true, "legend");
  double y = at.y + 16;
  c.polyline({{at.x, y - 3}, {at.x + 40, y - 3}}, kSewColour, 2.2, false, "legend-sew");
  c.text({at.x + 48, y}, "sew: closed with a sewing needle, before dressing", 9, kText,
         Anchor::Start, false, "legend");
  y += 14;
  c.polyline({{at.x, y - 3}, {at.x + 40, y - 3}}, kLaceColour, 2.2, true, "legend-lace");
  c.text({at.x + 48, y}, "lace: laced shut after the garment is on the wearer", 9, kText,
         Anchor::Start, false, "legend");
  y += 14;
  c.polyline({{at.x, y - 3}, {at.x + 40, y - 3}}, kEdgeColour, 0.6, false, "legend-edge");
  c.text({at.x + 48, y}, "edge of the fabric that stays open (not a seam)", 9, kText, Anchor::Start,
         false, "legend");
  y += 16;
  c.circle({at.x + 20, y - 4}, 6, kWhite, kSewColour, 1.2);
  c.text({at.x + 20, y - 1}, "7", 7, kSewColour, Anchor::Middle, true, "legend");
  c.text({at.x + 48, y}, "seam number: the two stretches with the same number are joined", 9, kText,
         Anchor::Start, false, "legend");
  y += 14;
  c.text({at.x, y},
         "Pieces are drawn as they come off the machine: left to right = needles, bottom to top = "
         "rows, in the stitch size of the gauge.",
         9, kText, Anchor::Start, false, "legend");
}

// A seam number on a page: its circle, and the point of the seam it names.
struct Label {
  P2 centre;
  P2 anchor;
  double radius = 0;
  const Seam* seam = nullptr;
};

void draw_pages(Canvas& c, const Model& m, const std::vector<std::string>& lines,
                const std::vector<Placement>& places, int table_pages, int piece_pages,
                const std::string& title) {
  // Cover page(s): title, legend, steps, the closing order.
  c.text({kMargin, kMargin + 14}, title, 16, kText, Anchor::Start, true, "title");
  std::ostringstream summary;
  summary << m.layouts.size() << " piece" << (m.layouts.size() == 1 ? "" : "s") << ", "
          << m.seams.size() << " seam" << (m.seams.size() == 1 ? "" : "s") << ": ";
  if (m.sewn > 0)
    summary << "sew 1" << (m.sewn > 1 ? "-" + std::to_string(m.sewn) : "") << " first";
  else
    summary << "nothing to sew";
  const int laced = static_cast<int>(m.seams.size()) - m.sewn;
  if (laced > 0) {
    summary << ", then put the garment on the wearer and lace " << m.sewn + 1;
    if (laced > 1) summary << "-" << m.seams.size();
  }
  summary << ".";
  c.text({kMargin, kMargin + 34}, summary.str(), 10, kText, Anchor::Start, false, "summary");
  draw_legend(c, {kMargin, kMargin + 60});
  c.text({kMargin, kTableTop - 14}, "Order to close the seams", 11, kText, Anchor::Start, true,
         "order-title");
  std::size_t next = 0;
  for (int page = 0; page < table_pages; ++page) {
    if (page > 0) {
      c.next_page();
      c.text({kMargin, kMargin + 14}, "Order to close the seams (continued)", 11, kText,
             Anchor::Start, true, "order-title");
    }
    const double top = page == 0 ? kTableTop : kMargin + 30;
    const int per_column = lines_per_page(page == 0) / kColumns;
    for (int col = 0; col < kColumns && next < lines.size(); ++col) {
      for (int row = 0; row < per_column && next < lines.size(); ++row, ++next) {
        const std::string& line = lines[next];
        const bool lace = line.find(". lace") != std::string::npos;
        c.text({kMargin + col * (kPageW - 2 * kMargin) / kColumns, top + row * kLine}, line, 8,
               line.rfind("--", 0) == 0 ? kLaceColour : (lace ? kLaceColour : kText), Anchor::Start,
               false, "order");
      }
    }
  }

  // Piece pages.
  for (int page = 0; page < piece_pages; ++page) {
    c.next_page();
    std::vector<Label> placed;  // seam numbers on this page
    c.text({kMargin, kMargin + 10},
           "Pieces (page " + std::to_string(page + 1) + " of " + std::to_string(piece_pages) + ")",
           11, kText, Anchor::Start, true, "page-title");
    for (const Placement& pl : places) {
      if (pl.page != table_pages + page) continue;
      const PieceLayout& layout = m.layouts[at(pl.piece)];
      const double top = pl.y + kCaption;
      const double height = pl.h_mm * pl.scale;
      auto to_page = [&](std::array<double, 2> q) {
        return P2{pl.x + q[0] * m.mesh.course_mm * pl.scale,
                  top + height - q[1] * m.mesh.wale_mm * pl.scale};
      };
      c.text({pl.x, pl.y + 10}, caption(m, pl), 9, kText, Anchor::Start, true, "piece-caption");
      std::vector<std::vector<P2>> polys;
      polys.reserve(layout.faces.size());
      for (const FaceLayout& f : layout.faces) {
        std::vector<P2> poly;
        for (const auto& q : face_corners(f)) poly.push_back(to_page(q));
        polys.push_back(std::move(poly));
      }
      c.fill_polygons(polys, kFabric);
      // Open edges, then the seams over them.
      std::vector<std::array<P2, 2>> edges;
      std::map<std::pair<int, int>, std::vector<std::array<P2, 2>>> seam_segments;
      for (const FaceLayout& f : layout.faces) {
        const StitchFace& face = m.mesh.faces[at(f.face)];
        const FaceSideRoles roles = face_side_roles(face);
        for (std::size_t i = 0; i < face.vertices.size(); ++i) {
          const SideRef side{f.face, static_cast<int>(i)};
          const auto seam = m.seam_of_side.find(side);
          const SideRef other = other_side(m, side);
          const bool open = other.face == kNone || m.piece_of_face[at(other.face)] != pl.piece;
          if (seam == m.seam_of_side.end() && !open) continue;
          const auto seg = side_in_layout(face, f, static_cast<int>(i));
          const std::array<P2, 2> s{to_page(seg[0]), to_page(seg[1])};
          if (seam == m.seam_of_side.end()) {
            edges.push_back(s);
          } else {
            const Seam& sm = m.seams[at(seam->second)];
            const int which =
                std::find(sm.sides[0].begin(), sm.sides[0].end(), side) != sm.sides[0].end() ? 0
                                                                                             : 1;
            seam_segments[{seam->second, which}].push_back(s);
          }
        }
        // The point of a short-row triangle has no side; in the layout it
        // is a gap between the triangle's bottom and top. Close it in the
        // style of the seam on either side of it, so the seam reads as one line.
        const auto corners = face_corners(f);
        auto close = [&](P2 a, P2 b, int in_side, int out_side) {
          for (int side : {in_side, out_side}) {
            const auto seam = m.seam_of_side.find({f.face, side});
            if (seam == m.seam_of_side.end()) continue;
            const Seam& sm = m.seams[at(seam->second)];
            const SideRef ref{f.face, side};
            const int which =
                std::find(sm.sides[0].begin(), sm.sides[0].end(), ref) != sm.sides[0].end() ? 0 : 1;
            seam_segments[{seam->second, which}].push_back({a, b});
            return;
          }
          edges.push_back({a, b});
        };
        if (roles.left_wale == kNone && !roles.in.empty() && !roles.out.empty())
          close(to_page(corners[3]), to_page(corners[0]), roles.in.front(), roles.out.front());
        if (roles.right_wale == kNone && !roles.in.empty() && !roles.out.empty())
          close(to_page(corners[1]), to_page(corners[2]), roles.in.back(), roles.out.back());
      }
      for (const auto& e : edges) c.polyline({e[0], e[1]}, kEdgeColour, 0.6, false, "edge");
      std::vector<Label> labels;
      for (const auto& [key, segs] : seam_segments) {
        const Seam& sm = m.seams[at(key.first)];
        const Rgb colour = sm.lace ? kLaceColour : kSewColour;
        for (const auto& line : chain(segs))
          c.polyline(line, colour, 2.0, sm.lace, sm.lace ? "seam-lace" : "seam-sew");
        // The number sits on the middle side of the stretch, or, where
        // another number is already there, on a side near it or moved off
        // the line (with a leader) until it is clear.
        if (sm.piece[at(key.second)] != pl.piece) continue;
        std::vector<SideRef> here;
        for (const SideRef& side : sm.sides[at(key.second)]) {
          if (m.piece_of_face[at(side.face)] == pl.piece) here.push_back(side);
        }
        const SideRef mid = sm.label_at[at(key.second)];
        const auto middle = std::find(here.begin(), here.end(), mid);
        const std::ptrdiff_t centre = middle == here.end() ? 0 : middle - here.begin();
        std::vector<std::pair<std::ptrdiff_t, SideRef>> by_distance;
        for (std::size_t k = 0; k < here.size(); ++k)
          by_distance.push_back({std::abs(static_cast<std::ptrdiff_t>(k) - centre), here[k]});
        std::stable_sort(by_distance.begin(), by_distance.end(),
                         [](const auto& x, const auto& y) { return x.first < y.first; });
        for (std::size_t k = 0; k < here.size(); ++k) here[k] = by_distance[k].second;
        const std::string number = std::to_string(sm.number);
        const double r = number.size() > 2 ? 8.5 : 6.5;
        Label best;
        bool found = false;
        const std::size_t anchors = std::min<std::size_t>(here.size(), 8);
        for (int push = 0; push < 4 && !found; ++push) {
          for (std::size_t k = 0; k < anchors && !found; ++k) {
            const SideRef side = here[k];
            const FaceLayout& f = m.layouts[at(pl.piece)].faces[at(m.layout_index[at(side.face)])];
            const auto seg = side_in_layout(m.mesh.faces[at(side.face)], f, side.side);
            const P2 a = to_page(seg[0]);
            const P2 b = to_page(seg[1]);
            const P2 on{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
            const double len = std::max(std::hypot(b.x - a.x, b.y - a.y), 1e-9);
            const P2 normal{-(b.y - a.y) / len, (b.x - a.x) / len};
            for (int sign : {1, -1}) {
              const double d = push * 2.2 * r * sign;
              const P2 at_p{on.x + normal.x * d, on.y + normal.y * d};
              const bool clear = std::all_of(placed.begin(), placed.end(), [&](const Label& o) {
                return std::hypot(o.centre.x - at_p.x, o.centre.y - at_p.y) >= o.radius + r + 0.5;
              });
              if (!found && (clear || (push == 0 && k == 0 && sign == 1))) {
                best = {at_p, on, r, &sm};
                found = clear;
              }
              if (push == 0) break;
            }
          }
        }
        placed.push_back(best);
        labels.push_back(best);
      }
      for (const Label& l : labels) {
        const Seam& sm = *l.seam;
        const Rgb colour = sm.lace ? kLaceColour : kSewColour;
        if (std::hypot(l.centre.x - l.anchor.x, l.centre.y - l.anchor.y) > 0.5)
          c.polyline({l.anchor, l.centre}, colour, 0.6, false, "leader");
        c.circle(l.centre, l.radius, kWhite, colour, 1.2);
        c.text({l.centre.x, l.centre.y + 2.6}, std::to_string(sm.number), 7, colour, Anchor::Middle,
               true, sm.lace ? "seam-label lace" : "seam-label sew");
      }
    }
  }
}

// ---------------------------------------------------------------- 3D

std::string draw_3d(const Model& m, const std::optional<PolygonMesh>& wearer,
                    const std::string& png_path) {
  constexpr int kPanel = 450;
  constexpr int kLegend = 36;
  const int width = 2 * kPanel;
  const int height = 2 * kPanel + kLegend;
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
  if (cairo_surface_status(surface) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(surface);
    return png_path + ": error: [A006] cairo could not make the picture";
  }
  cairo_surface_flush(surface);
  unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  std::fill(data, data + static_cast<std::ptrdiff_t>(stride) * height, 255);

  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  auto grow = [&](const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const auto& p : m.mesh.positions) grow(p);
  if (wearer) {
    for (const auto& p : wearer->positions) grow(p);
  }
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  const double radius = std::max(0.5 * (hi - lo).norm(), 1e-9);
  const Eigen::Vector3d light = Eigen::Vector3d(0.3, 0.5, 1.0).normalized();

  const double yaws[4] = {0, 90, 180, 270};
  std::vector<float> depth(static_cast<std::size_t>(kPanel) * kPanel);
  for (int panel = 0; panel < 4; ++panel) {
    const double yaw = yaws[panel] * M_PI / 180;
    const double pitch = 20 * M_PI / 180;
    const Eigen::Matrix3d rot = (Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX()) *
                                 Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()))
                                    .toRotationMatrix();
    const double scale = 0.46 * kPanel / radius;
    const int ox = (panel % 2) * kPanel;
    const int oy = (panel / 2) * kPanel;
    auto project = [&](const Eigen::Vector3d& p) {
      const Eigen::Vector3d q = rot * (p - centre);
      return Eigen::Vector3d(kPanel / 2.0 + q.x() * scale, kPanel / 2.0 - q.y() * scale,
                             q.z() * scale);
    };
    std::fill(depth.begin(), depth.end(), -std::numeric_limits<float>::infinity());
    auto put = [&](int x, int y, double z, Rgb c) {
      if (x < 0 || y < 0 || x >= kPanel || y >= kPanel) return;
      float& d = depth[static_cast<std::size_t>(y) * kPanel + static_cast<std::size_t>(x)];
      if (z < d) return;
      d = static_cast<float>(z);
      unsigned char* px = data + static_cast<std::ptrdiff_t>(oy + y) * stride + (ox + x) * 4;
      px[0] = static_cast<unsigned char>(std::lround(c.b * 255));
      px[1] = static_cast<unsigned char>(std::lround(c.g * 255));
      px[2] = static_cast<unsigned char>(std::lround(c.r * 255));
    };
    auto triangle = [&](const Eigen::Vector3d& a3, const Eigen::Vector3d& b3,
                        const Eigen::Vector3d& c3, Rgb base, double bias) {
      Eigen::Vector3d n = (b3 - a3).cross(c3 - a3);
      if (n.norm() == 0) return;
      n = rot * n.normalized();
      const double shade = 0.35 + 0.65 * std::abs(n.dot(light));
      const Rgb col{base.r * shade, base.g * shade, base.b * shade};
      const Eigen::Vector3d a = project(a3), b = project(b3), c = project(c3);
      const double area = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
      if (std::abs(area) < 1e-12) return;
      const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x(), b.x(), c.x()}))));
      const int x1 =
          std::min(kPanel - 1, static_cast<int>(std::ceil(std::max({a.x(), b.x(), c.x()}))));
      const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y(), b.y(), c.y()}))));
      const int y1 =
          std::min(kPanel - 1, static_cast<int>(std::ceil(std::max({a.y(), b.y(), c.y()}))));
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const double px = x + 0.5, py = y + 0.5;
          const double w0 = ((b.x() - px) * (c.y() - py) - (b.y() - py) * (c.x() - px)) / area;
          const double w1 = ((c.x() - px) * (a.y() - py) - (c.y() - py) * (a.x() - px)) / area;
          const double w2 = 1 - w0 - w1;
          if (w0 < 0 || w1 < 0 || w2 < 0) continue;
          put(x, y, w0 * a.z() + w1 * b.z() + w2 * c.z() + bias, col);
        }
      }
    };
    auto segment = [&](const Eigen::Vector3d& a3, const Eigen::Vector3d& b3, Rgb col,
                       double half_width, double bias) {
      const Eigen::Vector3d a = project(a3), b = project(b3);
      const int steps = std::max(1, static_cast<int>(std::ceil((b - a).head<2>().norm())));
      const int r = static_cast<int>(std::ceil(half_width));
      for (int k = 0; k <= steps; ++k) {
        const Eigen::Vector3d p = a + (b - a) * (static_cast<double>(k) / steps);
        for (int dy = -r; dy <= r; ++dy) {
          for (int dx = -r; dx <= r; ++dx) {
            if (dx * dx + dy * dy > half_width * half_width + 0.25) continue;
            put(static_cast<int>(p.x()) + dx, static_cast<int>(p.y()) + dy, p.z() + bias, col);
          }
        }
      }
    };
    const double unit = scale * radius;  // depth units per radius
    if (wearer) {
      for (const auto& face : wearer->faces) {
        for (std::size_t k = 1; k + 1 < face.size(); ++k)
          triangle(wearer->positions[at(face[0])], wearer->positions[at(face[k])],
                   wearer->positions[at(face[k + 1])], {0.62, 0.68, 0.78}, 0);
      }
    }
    for (const StitchFace& face : m.mesh.faces) {
      for (std::size_t k = 1; k + 1 < face.vertices.size(); ++k)
        triangle(m.mesh.positions[face.vertices[0]], m.mesh.positions[face.vertices[k]],
                 m.mesh.positions[face.vertices[k + 1]], {0.96, 0.86, 0.58}, 0.006 * unit);
    }
    for (const Seam& seam : m.seams) {
      for (const auto& sides : seam.sides) {
        for (const SideRef& s : sides) {
          const auto v = side_vertices(m, s);
          segment(m.mesh.positions[v[0]], m.mesh.positions[v[1]],
                  seam.lace ? kLaceColour : kSewColour, 2.0, 0.02 * unit);
        }
      }
    }
  }
  cairo_surface_mark_dirty(surface);
  cairo_t* cr = cairo_create(surface);
  // Legend strip.
  const double y = 2 * kPanel + kLegend / 2.0;
  auto key = [&](double x, Rgb c, const char* label) {
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_rectangle(cr, x, y - 5, 30, 5);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, kText.r, kText.g, kText.b);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 14);
    cairo_move_to(cr, x + 38, y + 2);
    cairo_show_text(cr, label);
  };
  key(20, kSewColour, "sew");
  key(130, kLaceColour, "lace");
  key(250, {0.96, 0.86, 0.58}, "garment");
  if (wearer) key(390, {0.62, 0.68, 0.78}, "wearer");
  cairo_destroy(cr);
  const std::string failure = render::write_png_file(surface, png_path);
  cairo_surface_destroy(surface);
  return failure.empty() ? "" : "error: [A006] " + failure;
}

}  // namespace

namespace {

struct Guide {
  Model model;
  std::optional<PolygonMesh> wearer;
  std::vector<std::string> lines;
  std::vector<Placement> places;
  int table_pages = 1;
  int piece_pages = 0;
  std::string title;
};

// Reads the folder and lays out the pages; throws Failure.
void prepare(Guide& g, const fs::path& plan_dir, const std::string& wearer_path) {
  load(g.model, plan_dir);
  if (!wearer_path.empty()) {
    knitout::DiagnosticSink sink;
    g.wearer = read_stage_mesh(wearer_path, sink);
    if (!g.wearer) fail(wearer_path, "A005", "the wearer cannot be read: " + first_error(sink));
  }
  g.lines = order_lines(g.model);
  for (std::size_t room = static_cast<std::size_t>(lines_per_page(true)); room < g.lines.size();
       room += static_cast<std::size_t>(lines_per_page(false)))
    ++g.table_pages;
  g.places = place_pieces(g.model, g.table_pages, &g.piece_pages);
  g.title = "Assembly guide: " + fs::absolute(plan_dir).lexically_normal().filename().string();
}

cairo_status_t write_to_stream(void* closure, const unsigned char* bytes, unsigned int length) {
  auto* o = static_cast<std::ostream*>(closure);
  o->write(reinterpret_cast<const char*>(bytes), static_cast<std::streamsize>(length));
  return *o ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

}  // namespace

std::string write_assembly_guide(const fs::path& plan_dir, const std::string& wearer_path,
                                 AssemblySummary* summary) {
  Guide g;
  try {
    prepare(g, plan_dir, wearer_path);
  } catch (const Failure& e) {
    return e.what();
  } catch (const std::logic_error& e) {
    // A broken invariant of the guide's own code: said loudly, never a crash of the caller.
    return plan_dir.string() + ": internal error: " + e.what();
  }
  const Model& m = g.model;
  const int pages = g.table_pages + g.piece_pages;
  SvgCanvas svg(pages);
  draw_pages(svg, m, g.lines, g.places, g.table_pages, g.piece_pages, g.title);
  const std::string svg_text = svg.document();

  const fs::path pdf_path = plan_dir / "assembly.pdf";
  std::string failure = knitout::write_file_atomically(pdf_path.string(), [&](std::ostream& out) {
    cairo_surface_t* surface =
        cairo_pdf_surface_create_for_stream(write_to_stream, &out, kPageW, kPageH);
    cairo_t* cr = cairo_create(surface);
    CairoCanvas pdf(cr);
    draw_pages(pdf, m, g.lines, g.places, g.table_pages, g.piece_pages, g.title);
    cairo_show_page(cr);
    cairo_destroy(cr);
    cairo_surface_finish(surface);
    const cairo_status_t status = cairo_surface_status(surface);
    cairo_surface_destroy(surface);
    if (status != CAIRO_STATUS_SUCCESS)
      throw std::runtime_error(std::string("cairo: ") + cairo_status_to_string(status));
  });
  if (!failure.empty()) return "error: [A006] " + failure;
  failure = knitout::write_file_atomically((plan_dir / "assembly.svg").string(),
                                           [&](std::ostream& out) { out << svg_text; });
  if (!failure.empty()) return "error: [A006] " + failure;
  failure = draw_3d(m, g.wearer, (plan_dir / "assembly-3d.png").string());
  if (!failure.empty()) return failure;

  if (summary) {
    summary->pieces = static_cast<int>(m.layouts.size());
    summary->seams = static_cast<int>(m.seams.size());
    summary->sewn = m.sewn;
    summary->laced = summary->seams - m.sewn;
    summary->arcs = static_cast<int>(m.arcs.size());
    summary->pdf_pages = pages;
  }
  return "";
}

std::string write_assembly_page_png(const fs::path& plan_dir, int page, const std::string& png_path,
                                    double pixels_per_point) {
  Guide g;
  try {
    prepare(g, plan_dir, "");
  } catch (const Failure& e) {
    return e.what();
  }
  const int pages = g.table_pages + g.piece_pages;
  if (page < 1 || page > pages)
    return png_path + ": error: [A006] the guide has pages 1 to " + std::to_string(pages) +
           ", not " + std::to_string(page);
  const int w = static_cast<int>(std::lround(kPageW * pixels_per_point));
  const int h = static_cast<int>(std::lround(kPageH * pixels_per_point));
  cairo_surface_t* surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
  cairo_t* cr = cairo_create(surface);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_scale(cr, pixels_per_point, pixels_per_point);
  CairoCanvas canvas(cr, page - 1);
  draw_pages(canvas, g.model, g.lines, g.places, g.table_pages, g.piece_pages, g.title);
  cairo_destroy(cr);
  const std::string failure = render::write_png_file(surface, png_path);
  cairo_surface_destroy(surface);
  return failure.empty() ? "" : "error: [A006] " + failure;
}

}  // namespace planner
