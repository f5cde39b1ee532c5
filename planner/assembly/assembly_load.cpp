// assembly::load (assembly_model.hpp): the stage files of the plan folder
// through the stages' readers, then the seams (assembly_seams.hpp).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "planner/assembly/assembly_model.hpp"
#include "planner/assembly/assembly_seams.hpp"
#include "planner/common/index.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/pipeline.hpp"

namespace planner::assembly {

namespace {

namespace fs = std::filesystem;

// A stage's output as its reader gives it: A001 when one of `files` (the
// stage's files in `dir`) is missing, A002 with the reader's diagnostic when
// they cannot be read. `verb` is what makes them.
template <typename T>
T need(std::optional<T> value, const knitout::DiagnosticSink& sink, const fs::path& dir,
       std::initializer_list<const char*> files, const std::string& verb) {
  for (const char* name : files) {
    if (!fs::exists(dir / name))
      fail(dir / name, "A001", "missing (run wearknit " + verb + " first)");
  }
  if (!value || sink.has_errors())
    fail(dir / *files.begin(), "A002",
         "cannot be read (run wearknit " + verb + " again): " + first_error(sink));
  return std::move(*value);
}

// Two ids that are both known and differ (0: a folder made by hand).
bool differ(std::uint64_t a, std::uint64_t b) {
  return a != 0 && b != 0 && a != b;
}

// The cut-arcs (ids, lengths) into m.arcs with their labels when the folder
// has wearability.json, and where each runs through the proxy, by id; the
// arcs chained into seams into m.chains.
std::map<int, ArcLine> arcs_of(Model& m, const Cut& cut,
                               const std::optional<WearabilityRecord>& labels) {
  std::map<int, ArcLine> lines;
  for (std::size_t i = 0; i < cut.mesh.arcs.size(); ++i) {
    const CutArc& arc = cut.mesh.arcs[i];
    ArcInfo info;
    info.id = static_cast<int>(i);
    info.length_mm = arc.length_mm;
    if (labels) {
      info.lace = labels->labels[i] == Label::Lace;
      info.labelled = true;
    }
    ArcLine line;
    double s = 0;
    for (const int v : arc.vertices) {
      line.points.push_back(cut.mesh.proxy.position(v));
      if (line.points.size() > 1)
        s += (line.points.back() - line.points[line.points.size() - 2]).norm();
      line.start.push_back(s);
    }
    lines[info.id] = std::move(line);
    m.arcs.push_back(info);
  }
  // The arcs chained into seams; arcs without a label count as sewn, the
  // label the guide gives them.
  std::vector<ArcEnds> ends;
  for (std::size_t i = 0; i < cut.mesh.arcs.size(); ++i) {
    const std::vector<int>& v = cut.mesh.arcs[i].vertices;
    const int none = -1 - 2 * static_cast<int>(i);  // ends no other arc has
    ends.push_back(
        {v.empty() ? none : v.front(), v.empty() ? none - 1 : v.back(), m.arcs[i].lace ? 1 : 0});
  }
  m.chains = chain_arcs(ends);
  const std::vector<int> seam = seam_of_arc(m.chains, m.arcs.size());
  for (std::size_t i = 0; i < m.arcs.size(); ++i) m.arcs[i].seam = seam[i];
  return lines;
}

// The stitch mesh as the scheduler read it, and the cut-arc of every
// boundary side (the `# arc` lines) as a map from side key to arc id. Fills
// m.mesh and m.sides_by_key.
std::unordered_map<std::uint64_t, int> take_stitch_mesh(Model& m, StitchMesh mesh) {
  m.mesh = std::move(mesh);
  // Without a `# wearknit` stitch-size line, the paper's swatch (§8.1:
  // 40 x 40 stitches measure 42 x 115 mm).
  if (!(m.mesh.course_mm > 0)) m.mesh.course_mm = 1.05;
  if (!(m.mesh.wale_mm > 0)) m.mesh.wale_mm = 2.875;
  std::unordered_map<std::uint64_t, int> arc_of_key;
  for (std::size_t f = 0; f < m.mesh.faces.size(); ++f) {
    const StitchFace& face = m.mesh.faces[f];
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      const std::uint64_t key =
          side_key(face.vertices[i], face.vertices[(i + 1) % face.vertices.size()]);
      if (i < face.arcs.size() && face.arcs[i] != kNoArc) arc_of_key[key] = face.arcs[i];
      m.sides_by_key[key].push_back({static_cast<int>(f), static_cast<int>(i)});
    }
  }
  return arc_of_key;
}

// The piece of every stitch-mesh face and its index in the piece's layout;
// every face must be in exactly one piece.
void index_faces(Model& m) {
  const fs::path& dir = m.dir;
  m.piece_of_face.assign(m.mesh.faces.size(), kNone);
  m.layout_index.assign(m.mesh.faces.size(), kNone);
  for (std::size_t p = 0; p < m.layouts.size(); ++p) {
    for (std::size_t i = 0; i < m.layouts[p].faces.size(); ++i) {
      const int face = m.layouts[p].faces[i].face;
      if (at(face) >= m.mesh.faces.size() || m.piece_of_face[at(face)] != kNone)
        fail(dir / "pieces" / ("piece-" + std::to_string(p + 1) + ".layout.json"), "A004",
             "face " + std::to_string(face) +
                 (at(face) >= m.mesh.faces.size() ? " is not a face of stitch-mesh.smobj"
                                                  : " is twice in the pieces") +
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

}  // namespace

void load(Model& m, const fs::path& dir) {
  m.dir = dir;
  if (!fs::is_directory(dir)) fail(dir, "A001", "not a folder");
  const std::string folder = dir.string();
  // Every stage's output through its own reader (planner/pipeline.hpp); the
  // folder's summaries (report.json, cuts.json) are not read.
  knitout::DiagnosticSink sink;
  const Cut cut = need(read_cut(folder, sink), sink, dir,
                       {"cut.json", "labels.json", "proxy.obj", "cut-mesh.obj"}, "cut");
  m.garment_mm_per_unit = mm_per_unit(cut.report.units).value_or(1.0) * cut.report.scale;
  std::optional<WearabilityRecord> labels;
  if (fs::exists(dir / "wearability.json")) {
    labels = need(read_wearability(folder, sink), sink, dir, {"wearability.json"}, "wearability");
    if (differ(labels->cut_id, cut.id) || labels->labels.size() != cut.mesh.arcs.size())
      fail(dir / "wearability.json", "A004",
           "the labels belong to another cut (run wearknit wearability again)");
  }
  StitchMeshFile stitches =
      need(read_stitch_mesh(folder, sink), sink, dir, {"stitch-mesh.smobj"}, "stitch-mesh");
  if (differ(stitches.cut_id, cut.id))
    fail(dir / "stitch-mesh.smobj", "A004",
         "belongs to another cut (run wearknit stitch-mesh again)");
  ScheduleRecord schedule =
      need(read_schedule(folder, sink), sink, dir, {"schedule.json"}, "schedule");
  if (differ(schedule.stitch_mesh_id, stitches.id))
    fail(dir / "schedule.json", "A004",
         "the pieces belong to another stitch mesh (run wearknit schedule again)");

  const auto arc_of_key = take_stitch_mesh(m, std::move(stitches.mesh));
  m.layouts = std::move(schedule.layouts);
  m.wale_seams = std::move(schedule.wale_seams);
  index_faces(m);
  const std::map<int, ArcLine> lines = arcs_of(m, cut, labels);
  std::vector<Seam> cut_seams =
      schedule_cut_seams(m, schedule.schedule_cuts, dir / "schedule.json");
  std::vector<Seam> wale = wale_seams(m);
  ArcSeams arcs = chain_seams(m, arc_of_key, lines);
  number_seams(m, std::move(cut_seams), std::move(wale), std::move(arcs));
}

}  // namespace planner::assembly
