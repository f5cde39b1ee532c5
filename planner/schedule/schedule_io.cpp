// The schedule stage's files: pieces/piece-N.{k,dat,svg,layout.json} and
// schedule.json (planner/pipeline.hpp).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <ostream>

#include "knitout/output_file.hpp"
#include "planner/common/hash.hpp"
#include "planner/common/index.hpp"
#include "planner/common/json_file.hpp"
#include "planner/pipeline.hpp"

namespace planner {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Removes the files of pieces numbered above `count` (piece-N.k, .dat, .svg,
// .layout.json) that an earlier run making more pieces left in `dir`, so the
// folder holds exactly this schedule's pieces and nobody sends a stale one.
// Other files are left alone. Returns an error message, or "".
std::string remove_stale_pieces(const fs::path& dir, std::size_t count) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("piece-", 0) != 0) continue;
    std::size_t end = 6;
    while (end < name.size() && end < 15 && std::isdigit(static_cast<unsigned char>(name[end])))
      ++end;
    const std::string kind = name.substr(end);
    if (end == 6 || (kind != ".k" && kind != ".dat" && kind != ".svg" && kind != ".layout.json"))
      continue;
    if (std::stoul(name.substr(6, end - 6)) > count) stale.push_back(entry.path());
  }
  if (ec) return dir.string() + ": " + ec.message();
  for (const fs::path& path : stale) {
    fs::remove(path, ec);
    if (ec) return path.string() + ": cannot remove a piece of an earlier run: " + ec.message();
  }
  return {};
}

std::string write_piece(const fs::path& pieces, const ScheduledPiece& piece) {
  std::string failure =
      knitout::write_file_atomically((pieces / (piece.name + ".k")).string(),
                                     [&](std::ostream& out) { out << piece.emitted.knitout; });
  if (failure.empty()) {
    failure = knitout::write_file_atomically(
        (pieces / (piece.name + ".dat")).string(), [&](std::ostream& out) {
          out.write(reinterpret_cast<const char*>(piece.dat.data()),
                    static_cast<std::streamsize>(piece.dat.size()));
        });
  }
  if (failure.empty()) failure = write_bed_view(piece, (pieces / (piece.name + ".svg")).string());
  return failure;
}

json piece_json(const ScheduledPiece& piece) {
  const PieceStats& st = piece.emitted.stats;
  return {{"name", piece.name},
          {"knitout", "pieces/" + piece.name + ".k"},
          {"dat", "pieces/" + piece.name + ".dat"},
          {"rows", st.rows},
          {"stitches", piece.stitches},
          {"passes", st.passes},
          {"knit_passes", st.knit_passes},
          {"transfer_passes", st.transfer_passes},
          {"transfers", st.transfers},
          {"racks", st.racks},
          {"width_needles", st.width_needles},
          {"yarn_ins", st.yarn_ins},
          {"lines", st.lines},
          {"bed_view", "pieces/" + piece.name + ".svg"},
          {"vm_warnings", piece.vm_warnings},
          {"estimated_knit_time_s", piece.vm_stats.estimated_time_s},
          {"planner_time_model_s", st.knit_time_s}};
}

// Cuts from scheduling: seams labelled sew (§7.3), the course edges of each
// separated row pair.
json schedule_cuts_json(const Schedule& schedule) {
  json cuts = json::array();
  for (const auto& [lower, upper] : schedule.cut_rows) {
    json edges = json::array();
    for (const CourseEdge& e : schedule.edges) {
      if (!e.cut) continue;
      if (schedule.face_row[at(e.lower)] != lower || schedule.face_row[at(e.upper)] != upper)
        continue;
      edges.push_back({e.lower, e.upper});
    }
    json cut = {{"label", "sew"}, {"lower_row", lower}, {"upper_row", upper}, {"faces", edges}};
    const std::size_t i = cuts.size();
    if (i < schedule.cut_causes.size() && schedule.cut_causes[i].covering != kNone) {
      cut["why"] = {{"covering_row", schedule.cut_causes[i].covering},
                    {"needle", schedule.cut_causes[i].needle},
                    {"text", cut_cause_text(schedule, i)}};
    }
    cuts.push_back(std::move(cut));
  }
  return cuts;
}

json report_json(const ScheduleOutcome& outcome) {
  const Schedule& s = outcome.schedule;
  const ScheduleParams& params = outcome.params.schedule;
  json trials = json::array();
  for (const TrialResult& t : s.trials) trials.push_back(t.cuts);
  json pieces = json::array();
  for (const ScheduledPiece& piece : outcome.pieces) pieces.push_back(piece_json(piece));
  return {{"seed", params.seed},
          {"pattern", stitch_pattern_name(outcome.params.emit.pattern)},
          {"threads", outcome.threads},
          {"trials", s.trials.size()},
          {"cuts_per_trial", trials},
          {"best_trial", s.best_trial},
          {"random_cuts", s.random_cuts},
          {"improve", params.improve},
          {"cuts", s.cuts},
          {"max_shift", params.max_patch_shift},
          {"patches_moved", std::count_if(s.patch_shift.begin(), s.patch_shift.end(),
                                          [](int shift) { return shift != 0; })},
          {"max_aside", params.max_aside},
          {"loops_set_aside", s.aside_moves.size()},
          {"rows", s.rows.size()},
          {"patches", s.patches.size()},
          {"wale_seams", s.wale_seams.size()},
          {"pieces", pieces},
          {"time_s", outcome.seconds}};
}

}  // namespace

std::string write_schedule(const std::string& dir, const ScheduleOutcome& outcome) {
  const fs::path pieces = fs::path(dir) / "pieces";
  std::error_code ec;
  fs::create_directories(pieces, ec);
  if (ec) return pieces.string() + ": " + ec.message();
  for (const ScheduledPiece& piece : outcome.pieces) {
    if (std::string failure = write_piece(pieces, piece); !failure.empty()) return failure;
  }
  // Each piece laid flat, for the assembly guide (piece_layout.hpp).
  if (std::string failure = write_piece_layouts(pieces.string(), outcome.schedule);
      !failure.empty())
    return failure;
  if (std::string failure = remove_stale_pieces(pieces, outcome.pieces.size()); !failure.empty())
    return failure;
  json wale_seams = json::array();
  for (const auto& [f, g] : outcome.schedule.wale_seams) wale_seams.push_back({f, g});
  return write_json_file((fs::path(dir) / "schedule.json").string(),
                         {{"format", "wearknit-schedule 1"},
                          {"stitch_mesh_id", hex64(outcome.stitch_mesh_id)},
                          {"cut_id", hex64(outcome.cut_id)},
                          {"report", report_json(outcome)},
                          {"schedule_cuts", schedule_cuts_json(outcome.schedule)},
                          {"wale_seams", wale_seams}});
}

std::optional<ScheduleRecord> read_schedule(const std::string& dir, knitout::DiagnosticSink& sink) {
  const fs::path base(dir);
  const std::string path = (base / "schedule.json").string();
  auto file = read_json_object(path, sink, "S920", "S920");
  if (!file) return std::nullopt;
  ScheduleRecord record;
  try {
    if (!parse_hex64(file->at("stitch_mesh_id").get<std::string>(), record.stitch_mesh_id))
      throw std::runtime_error("\"stitch_mesh_id\" is not 16 hex digits");
    record.schedule_cuts = file->at("schedule_cuts");
    for (const auto& pair : file->at("wale_seams"))
      record.wale_seams.emplace_back(pair.at(0).get<int>(), pair.at(1).get<int>());
    const std::size_t pieces = file->at("report").at("pieces").size();
    for (std::size_t p = 1; p <= pieces; ++p) {
      const fs::path layout_path =
          base / "pieces" / ("piece-" + std::to_string(p) + ".layout.json");
      std::string error;
      auto layout = read_piece_layout(layout_path.string(), &error);
      if (!layout) {
        sink.error(layout_path.string(), 0, 0, "S920",
                   error.substr(error.find(": ") == std::string::npos ? 0 : error.find(": ") + 2) +
                       " (run wearknit schedule again)");
        return std::nullopt;
      }
      record.layouts.push_back(std::move(*layout));
    }
  } catch (const std::exception& e) {
    sink.error(path, 0, 0, "S920", std::string("unexpected content: ") + e.what());
    return std::nullopt;
  }
  record.file = std::move(*file);
  return record;
}

}  // namespace planner
