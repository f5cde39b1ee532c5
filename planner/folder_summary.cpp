// The folder's summary files, report.json and cuts.json, made from the stage
// files (planner/pipeline.hpp, write_folder_summary; docs/plan.md).
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "planner/common/index.hpp"
#include "planner/common/json_file.hpp"
#include "planner/cut/seam_chains.hpp"
#include "planner/pipeline.hpp"

namespace planner {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The stage files a summary is made of; each absent when the stage has not
// written it (or it is not a JSON object).
struct StageFiles {
  std::optional<json> cut, wearability, stitch_mesh, schedule, assembly, plan;
};

StageFiles read_stage_files(const fs::path& base) {
  auto read = [&](const char* name) { return read_json_object_if_any((base / name).string()); };
  return {read("cut.json"),      read("wearability.json"), read("stitch-mesh.json"),
          read("schedule.json"), read("assembly.json"),    read("plan.json")};
}

std::string id_of(const std::optional<json>& file, const char* key) {
  if (!file) return {};
  const json value = file->value(key, json());
  return value.is_string() ? value.get<std::string>() : std::string();
}

// Two ids that are both known and differ. An absent id or one of all zeros
// is unknown (a folder made by hand).
bool differ(const std::string& a, const std::string& b) {
  const std::string unknown(16, '0');
  return !a.empty() && !b.empty() && a != unknown && b != unknown && a != b;
}

// Stage files made from another cut or stitch mesh than the one in the
// folder: each a sentence saying what to run again.
std::vector<std::string> stale_files(const StageFiles& f) {
  std::vector<std::string> stale;
  const std::string cut = id_of(f.cut, "cut_id");
  if (differ(id_of(f.wearability, "cut_id"), cut))
    stale.push_back("wearability.json belongs to another cut: run wearknit wearability again");
  if (differ(id_of(f.stitch_mesh, "cut_id"), cut))
    stale.push_back("the stitch mesh belongs to another cut: run wearknit stitch-mesh again");
  if (differ(id_of(f.schedule, "stitch_mesh_id"), id_of(f.stitch_mesh, "stitch_mesh_id")))
    stale.push_back("the pieces belong to another stitch mesh: run wearknit schedule again");
  return stale;
}

json report_of(const StageFiles& f, const std::vector<std::string>& stale) {
  json report = f.cut ? f.cut->value("report", json::object()) : json::object();
  if (f.wearability) {
    const json summary = f.wearability->value("summary", json::object());
    report["wearability"] = {{"wearable", summary.value("wearable", false)},
                             {"recut", summary.value("recut", false)},
                             {"cut_seed", summary.value("cut_seed", json())},
                             {"cut_attempts", summary.value("cut_attempts", json::array())}};
    if (summary.contains("final_check")) {
      json check = summary["final_check"];
      check.erase("rounds");
      check["rounds"] = summary["final_check"].value("rounds", json::array()).size();
      report["wearability"]["final_check"] = check;
    }
  }
  if (f.stitch_mesh) report["stitch_mesh"] = f.stitch_mesh->value("report", json::object());
  if (f.schedule) report["schedule"] = f.schedule->value("report", json::object());
  if (f.assembly) report["assembly"] = f.assembly->value("summary", json::object());
  if (f.plan) report["plan"] = f.plan->value("plan", json::object());
  if (!stale.empty()) report["stale"] = stale;
  return report;
}

// The seams the cut-arcs make (planner/cut/seam_chains.hpp): each arc's
// `seam`, and `seams`, each with its arcs in order (and whether each is
// walked backwards), its label and its length. Arcs without a label count
// as sewn, as the assembly guide treats them; the label stays null.
void add_seams(json& cuts) {
  json& arcs = cuts["arcs"];
  std::vector<ArcEnds> ends;
  for (std::size_t a = 0; a < arcs.size(); ++a) {
    const json edges = arcs[a].value("edges", json::array());
    // An arc without edges joins nothing: ends no other arc has.
    const int none = -1 - 2 * static_cast<int>(a);
    ArcEnds e{none, none - 1, 0};
    if (!edges.empty() && edges.front().size() == 2 && edges.back().size() == 2) {
      e.first = edges.front()[0].get<int>();
      e.last = edges.back()[1].get<int>();
    }
    e.label = arcs[a].value("label", json()) == "lace" ? 1 : 0;
    ends.push_back(e);
  }
  const std::vector<SeamChain> chains = chain_arcs(ends);
  json seams = json::array();
  for (std::size_t s = 0; s < chains.size(); ++s) {
    const SeamChain& chain = chains[s];
    double length = 0;
    bool labelled = true;
    for (const int a : chain.arcs) {
      json& arc = arcs[at(a)];
      arc["seam"] = s;
      length += arc.value("length_mm", 0.0);
      labelled = labelled && arc.value("label", json()).is_string();
    }
    seams.push_back({{"id", s},
                     {"arcs", chain.arcs},
                     {"reversed", chain.reversed},
                     {"label", labelled ? json(chain.label == 1 ? "lace" : "sew") : json()},
                     {"closed", chain.closed},
                     {"length_mm", std::round(length * 100) / 100}});
  }
  cuts["seams"] = std::move(seams);
}

// The cut-arcs with their labels (when wearability.json belongs to this
// cut) and seams, and the scheduler's cuts.
json cuts_of(const StageFiles& f, bool labels_current) {
  json cuts = json::object();
  if (f.cut) {
    cuts = {{"format", "wearknit-cuts 1"},
            {"vertices", f.cut->value("vertices", json())},
            {"cut_edges", f.cut->value("cut_edges", json())},
            {"cut_length_mm", f.cut->value("cut_length_mm", json())},
            {"arcs", f.cut->value("arcs", json::array())}};
    const json labels =
        labels_current ? f.wearability->value("arcs", json::array()) : json::array();
    json& arcs = cuts["arcs"];
    for (std::size_t a = 0; a < arcs.size(); ++a) {
      arcs[a]["label"] = nullptr;
      if (a >= labels.size() || !labels[a].is_object()) continue;
      arcs[a]["label"] = labels[a].value("label", json());
      if (labels[a].contains("wearability")) arcs[a]["wearability"] = labels[a]["wearability"];
    }
    if (labels_current) {
      // The stage's figures without its time: cuts.json is the same on every run.
      cuts["wearability"] = f.wearability->value("summary", json::object());
      cuts["wearability"].erase("seconds");
      if (cuts["wearability"].contains("final_check"))
        cuts["wearability"]["final_check"].erase("seconds");
    }
    add_seams(cuts);
  }
  if (f.schedule) cuts["schedule_cuts"] = f.schedule->value("schedule_cuts", json::array());
  return cuts;
}

}  // namespace

std::string write_folder_summary(const std::string& dir) {
  const fs::path base(dir);
  const StageFiles files = read_stage_files(base);
  const std::vector<std::string> stale = stale_files(files);
  const bool labels_current =
      files.wearability && !differ(id_of(files.wearability, "cut_id"), id_of(files.cut, "cut_id"));
  std::string failure = write_json_file((base / "report.json").string(), report_of(files, stale));
  const json cuts = cuts_of(files, labels_current);
  if (failure.empty() && !cuts.empty())
    failure = write_json_file((base / "cuts.json").string(), cuts);
  return failure;
}

}  // namespace planner
