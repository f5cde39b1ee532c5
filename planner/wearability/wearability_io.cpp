#include "planner/wearability/wearability_io.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <ostream>
#include <sstream>

#include "planner/common/hash.hpp"
#include "planner/common/json_file.hpp"
#include "planner/mesh/mesh_io.hpp"

namespace planner {

std::optional<PolygonMesh> read_stage_mesh(const std::string& path, knitout::DiagnosticSink& sink) {
  if (!std::filesystem::is_regular_file(path)) {
    sink.error(path, 0, 0, "W004", "cannot open file");
    return std::nullopt;
  }
  auto mesh = read_polygon_soup(path, sink);
  if (mesh && mesh->faces.empty()) {
    sink.error(path, 0, 0, "W003", "mesh has no faces");
    return std::nullopt;
  }
  return mesh;
}

std::string size_disagreement(const PolygonMesh& garment, const PolygonMesh& wearer) {
  const double g = bounding_box_size(garment).norm();
  const double w = bounding_box_size(wearer).norm();
  if (!(g > 0) || !(w > 0)) return {};
  const double ratio = std::max(g / w, w / g);
  if (ratio <= 1.25) return {};
  std::ostringstream text;
  text << std::fixed << std::setprecision(1) << "the garment (bounding box diagonal " << g
       << " mm) and the wearer (" << w << " mm) differ in size by a factor of "
       << std::setprecision(2) << ratio
       << "; if the wearer is in other units or at another scale than the garment, give "
          "--wearer-units and --wearer-scale (a garment that covers only part of its wearer "
          "can differ this much)";
  return text.str();
}

std::optional<CoverMesh> read_cover_mesh(const PolygonMesh& cut_mesh, const nlohmann::json& cuts,
                                         const std::string& cuts_source,
                                         knitout::DiagnosticSink& sink) {
  CoverMesh mesh;
  mesh.positions = cut_mesh.positions;
  mesh.faces = cut_mesh.faces;
  Eigen::AlignedBox3d box;
  for (const Vec3& v : mesh.positions) box.extend(v);
  // Both sides of a split cut sit at the same point; 1e-9 of the size
  // merges them and nothing else.
  const std::vector<int> weld =
      weld_vertices(mesh.positions, mesh.faces, 1e-9 * std::max(box.diagonal().norm(), 1e-300));
  const std::size_t errors_before = sink.error_count();
  if (!cuts.is_object() || !cuts.contains("arcs") || !cuts["arcs"].is_array()) {
    sink.error(cuts_source, 0, 0, "W010", "expected an object with an array \"arcs\"");
    return std::nullopt;
  }
  auto vertex = [&](const nlohmann::json& value, const std::string& where) -> int {
    if (!value.is_number_integer() || value.get<long long>() < 0 ||
        value.get<long long>() >= static_cast<long long>(weld.size())) {
      sink.error(cuts_source, 0, 0, "W010",
                 where + ": vertex index " + value.dump() + " is not in 0.." +
                     std::to_string(weld.size() - 1));
      return -1;
    }
    return weld[value.get<std::size_t>()];
  };
  const auto& arcs = cuts["arcs"];
  for (std::size_t a = 0; a < arcs.size(); ++a) {
    const auto& entry = arcs[a];
    const std::string where = "arc " + std::to_string(a);
    CoverArc arc;
    if (entry.is_object() && entry.contains("id")) arc.name = entry["id"].dump();
    if (entry.is_object() && entry.contains("edges") && entry["edges"].is_array()) {
      for (const auto& edge : entry["edges"]) {
        if (!edge.is_array() || edge.size() != 2) {
          sink.error(cuts_source, 0, 0, "W010", where + ": an edge is not a pair " + edge.dump());
          continue;
        }
        const int u = vertex(edge[0], where), v = vertex(edge[1], where);
        if (u >= 0 && v >= 0) arc.edges.push_back({u, v});
      }
    } else if (entry.is_object() && entry.contains("vertices") && entry["vertices"].is_array()) {
      std::vector<int> path;
      for (const auto& v : entry["vertices"]) path.push_back(vertex(v, where));
      for (std::size_t i = 0; i + 1 < path.size(); ++i) {
        if (path[i] >= 0 && path[i + 1] >= 0) arc.edges.push_back({path[i], path[i + 1]});
      }
    } else {
      sink.error(cuts_source, 0, 0, "W010", where + ": needs \"edges\" or \"vertices\"");
      continue;
    }
    mesh.arcs.push_back(std::move(arc));
  }
  if (sink.error_count() > errors_before) return std::nullopt;
  for (const std::string& problem : validate(mesh)) {
    sink.error(cuts_source, 0, 0, "W011", problem);
  }
  if (sink.error_count() > errors_before) return std::nullopt;
  return mesh;
}

std::optional<CoverMesh> read_garment(const std::string& dir, int min_vertices,
                                      knitout::DiagnosticSink& sink) {
  const std::string mesh_path = (std::filesystem::path(dir) / "cut-mesh.obj").string();
  const std::string cuts_path = (std::filesystem::path(dir) / "cut.json").string();
  const std::size_t errors_before = sink.error_count();
  const auto cut_mesh = read_stage_mesh(mesh_path, sink);
  const auto cuts = read_json_object(cuts_path, sink, "W004", "W010");
  if (!cut_mesh || !cuts || sink.error_count() != errors_before) return std::nullopt;
  auto cover = read_cover_mesh(*cut_mesh, *cuts, cuts_path, sink);
  if (!cover) return std::nullopt;
  return refined_for_cloth(std::move(*cover), min_vertices);
}

nlohmann::json trials_json(const std::vector<TrialOutcome>& trials) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& t : trials) {
    list.push_back({{"seed", t.seed},
                    {"success", t.success},
                    {"steps", t.steps},
                    {"stalled", t.stalled},
                    {"min_distance", t.min_distance}});
    if (!t.success && t.caught > 0) {
      list.back()["caught_vertices"] = t.caught;
      list.back()["caught_at_mm"] = {t.caught_at.x(), t.caught_at.y(), t.caught_at.z()};
      list.back()["caught_radius_mm"] = t.caught_radius;
    }
  }
  return list;
}

namespace {

using nlohmann::json;

json attempts_json(const std::vector<CutAttempt>& attempts) {
  json list = json::array();
  for (const auto& a : attempts) {
    json entry = {{"attempt", a.attempt},
                  {"cut_seed", a.cut_seed ? json(*a.cut_seed) : json(nullptr)},
                  {"arcs", a.arcs},
                  {"wearable", a.wearable},
                  {"initial_trials", trials_json(a.trials)}};
    if (!a.failure.empty()) entry["failure"] = a.failure;
    if (a.linked) entry["linked_with_wearer"] = true;
    if (a.cloth_vertices > 0) entry["cloth_vertices"] = a.cloth_vertices;
    // The coarse cloth that did not come off with every cut open.
    if (a.coarse_cloth_vertices > 0) entry["coarse_cloth_vertices"] = a.coarse_cloth_vertices;
    list.push_back(entry);
  }
  return list;
}

json check_json(const FinalCheck& check) {
  json rounds = json::array();
  for (const auto& r : check.rounds) {
    rounds.push_back({{"seed", r.seed},
                      {"passed", r.test.wearable},
                      {"trials", trials_json(r.test.trials)},
                      {"laced", r.reopened}});
    if (!r.sewn_again.empty()) rounds.back()["sewn_again"] = r.sewn_again;
  }
  return {{"ran", check.ran},          {"passed", check.passed},
          {"trials", check.trials},    {"cloth_vertices", check.cloth_vertices},
          {"laced", check.reopened()}, {"rounds", rounds},
          {"seconds", check.seconds}};
}

json summary_json(const Wearability& result) {
  const LacingStudy& study = result.study;
  const WearabilityParams& params = result.params.test;
  const int chosen = chosen_run(study);
  json summary = {
      {"wearable", chosen >= 0},
      {"runs", study.runs.size()},
      {"wearable_runs", study.wearable_runs},
      {"chosen_run", chosen},
      {"trials_per_test", params.trials},
      {"group_testing", params.group_testing},
      {"linking_test", params.linking},
      {"arc_order", to_string(params.order)},
      {"seed", params.seed},
      {"max_steps", params.cloth.max_steps},
      {"switch_steps", params.cloth.switch_steps},
      // The elimination's cloth: the garment's vertices, and the cloth's
      // after coarsening (equal when it was simulated as it is).
      {"garment_vertices", result.cover.positions.size()},
      {"cloth_vertices", result.cloth.positions.size()},
  };
  if (!study.runs.empty()) {
    summary["initial_trials"] = trials_json(study.runs[chosen >= 0 ? chosen : 0].initial.trials);
  }
  if (chosen >= 0) {
    const EliminationResult& run = study.runs[static_cast<std::size_t>(chosen)];
    int sewn = 0;
    for (const auto& arc : run.arcs) sewn += arc.label == Label::Sew;
    summary["sewn"] = sewn;
    summary["tests"] = run.tests + 1;
    // Tests of a run cut short, read from its journal instead of simulated.
    summary["tests_replayed"] = run.replayed;
    // Passed without a simulation: an earlier run passed a subset of its
    // open arcs (WearabilityParams::reuse_passes).
    summary["tests_inferred"] = run.inferred;
    // Failed without a simulation: a garment curve links the wearer
    // (WearabilityParams::linking).
    summary["tests_linked"] = run.linked;
    summary["laced"] = static_cast<int>(run.arcs.size()) - sewn;
  }
  summary["final_check"] = check_json(result.check);
  summary["recut"] = result.recut.has_value();
  const auto seed = result.cut_seed();
  summary["cut_seed"] = seed ? json(*seed) : json(nullptr);
  summary["cut_attempts"] = attempts_json(result.attempts);
  summary["seconds"] = result.seconds;
  return summary;
}

}  // namespace

json wearability_json(const Wearability& result, std::uint64_t labelled_cut_id) {
  const LacingStudy& study = result.study;
  const int chosen = chosen_run(study);
  const EliminationResult* run =
      chosen >= 0 ? &study.runs[static_cast<std::size_t>(chosen)] : nullptr;
  json arcs = json::array();
  for (std::size_t a = 0; a < result.cover.arcs.size(); ++a) {
    json entry = {{"id", a}};
    if (run == nullptr) {
      entry["label"] = "lace";
      arcs.push_back(entry);
      continue;
    }
    const ArcResult& arc = run->arcs[a];
    entry["label"] = to_string(arc.label);
    json detail = {{"position", arc.position},
                   {"wearable_when_sewn", arc.test.wearable},
                   {"tested_with", arc.test.group - 1},
                   {"trials", trials_json(arc.test.trials)}};
    // How far its sides parted as the garment came off with every cut open
    // (ArcOrder::Opening).
    if (a < run->initial.openings.size()) detail["opening_mm"] = run->initial.openings[a];
    if (arc.reopened) detail["laced_by_final_check"] = true;
    if (arc.test.inferred) detail["inferred_from_earlier_run"] = true;
    if (arc.test.linked) detail["linked_with_wearer"] = true;
    if (study.runs.size() > 1) detail["lace_probability"] = study.lace_probability[a];
    entry["wearability"] = detail;
    arcs.push_back(entry);
  }
  return {{"format", "wearknit-wearability 1"},
          {"cut_id", hex64(labelled_cut_id)},
          {"summary", summary_json(result)},
          {"arcs", arcs}};
}

}  // namespace planner
