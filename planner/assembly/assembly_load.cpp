// assembly::load (assembly_model.hpp): reading the plan folder, one step per
// file, then the seams (assembly_seams.hpp).

#include <cstddef>
#include <cstdint>
#include <exception>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "planner/assembly/assembly_model.hpp"
#include "planner/assembly/assembly_seams.hpp"
#include "planner/common/index.hpp"
#include "planner/schedule/piece_layout.hpp"
#include "planner/schedule/schedule.hpp"
#include "planner/stitch_mesh/stitch_mesh.hpp"
#include "planner/wearability/wearability_io.hpp"

namespace planner::assembly {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json read_json_file(const fs::path& path) {
  std::ifstream in(path);
  if (!in) fail(path, "A001", "cannot open file (a plan folder needs it for the assembly guide)");
  json value = json::parse(in, nullptr, false);
  if (value.is_discarded()) fail(path, "A002", "not valid JSON");
  if (!value.is_object()) fail(path, "A002", "not a JSON object");
  return value;
}

// The stitch mesh as the scheduler read it, and the cut-arc of every
// boundary side (the `# arc` lines), read with the scheduler's reader, as a
// map from side key to arc id. Fills m.mesh and m.sides_by_key.
std::unordered_map<std::uint64_t, int> read_stitch_mesh(Model& m, const fs::path& smobj_path) {
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
  return arc_of_key;
}

// The options report.json recorded for the scheduler (the ones that change
// the schedule), and the number of pieces it made.
ScheduleParams read_schedule_params(const json& report, const fs::path& report_path,
                                    std::size_t* pieces) {
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
  *pieces = sched["pieces"].size();
  return params;
}

// The pieces laid flat: as the scheduler wrote them
// (pieces/piece-N.layout.json), else from the schedule rebuilt from the
// seed, number of trials and options it recorded (its result depends on
// nothing else, docs/scheduling.md §7.3) and checked against what it
// wrote. Returns whether they were read from the files.
bool read_layouts(Model& m, const json& report, const PlanFiles& files) {
  const fs::path& dir = m.dir;
  const fs::path& report_path = files.report;
  const fs::path& smobj_path = files.smobj;
  std::size_t pieces = 0;
  const ScheduleParams params = read_schedule_params(report, report_path, &pieces);
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
  return from_files;
}

// The piece of every stitch-mesh face and its index in the piece's layout;
// every face must be in exactly one piece.
void index_faces(Model& m, const PlanFiles& files) {
  const fs::path& dir = m.dir;
  m.piece_of_face.assign(m.mesh.faces.size(), kNone);
  m.layout_index.assign(m.mesh.faces.size(), kNone);
  for (std::size_t p = 0; p < m.layouts.size(); ++p) {
    for (std::size_t i = 0; i < m.layouts[p].faces.size(); ++i) {
      const int face = m.layouts[p].faces[i].face;
      if (at(face) >= m.mesh.faces.size() || m.piece_of_face[at(face)] != kNone)
        fail(dir / "pieces" / ("piece-" + std::to_string(p + 1) + ".layout.json"), "A004",
             "face " + std::to_string(face) +
                 (at(face) >= m.mesh.faces.size() ? " is not a face of " : " is twice in ") +
                 (at(face) >= m.mesh.faces.size() ? files.smobj.filename().string()
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
}

// cuts.json's arcs (ids, labels, lengths) into m.arcs, and where each runs
// through proxy.obj, by id.
std::map<int, ArcLine> read_arcs(Model& m, const json& cuts, const PlanFiles& files) {
  const fs::path& cuts_path = files.cuts;
  const fs::path& proxy_path = files.proxy;
  if (!cuts.contains("arcs") || !cuts["arcs"].is_array())
    fail(cuts_path, "A002", "no \"arcs\" list (write it with wearknit cut)");
  knitout::DiagnosticSink proxy_sink;
  const auto proxy = read_stage_mesh(proxy_path.string(), proxy_sink);
  if (!proxy) fail(proxy_path, "A003", "unreadable: " + first_error(proxy_sink));
  std::map<int, ArcLine> lines;
  std::map<int, std::size_t> arc_slot;
  for (std::size_t i = 0; i < cuts["arcs"].size(); ++i) {
    const json& a = cuts["arcs"][i];
    ArcInfo info;
    ArcLine line;
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
  return lines;
}

}  // namespace

void load(Model& m, const fs::path& dir) {
  m.dir = dir;
  if (!fs::is_directory(dir)) fail(dir, "A001", "not a folder");
  const PlanFiles files(dir);
  const json cuts = read_json_file(files.cuts);
  const json report = read_json_file(files.report);
  const auto arc_of_key = read_stitch_mesh(m, files.smobj);
  const bool from_files = read_layouts(m, report, files);
  index_faces(m, files);
  const std::map<int, ArcLine> lines = read_arcs(m, cuts, files);
  // Scheduler cuts: must be the ones the rebuilt schedule makes.
  std::vector<Seam> cut_seams = schedule_cut_seams(m, cuts, files.cuts, !from_files);
  std::vector<Seam> wale = wale_seams(m);
  ArcSeams arcs = arc_seams(m, arc_of_key, lines, files);
  number_seams(m, std::move(cut_seams), std::move(wale), std::move(arcs));
}

}  // namespace planner::assembly
