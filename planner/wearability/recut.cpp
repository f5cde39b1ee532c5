#include "planner/wearability/recut.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>
#include <fstream>

#include "knitout/output_file.hpp"
#include "planner/cut/cut.hpp"
#include "planner/cut/cut_io.hpp"
#include "planner/cut/cut_pictures.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/wearability/wearability_io.hpp"

namespace planner {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::optional<json> read_json_file(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  try {
    return json::parse(in);
  } catch (const json::exception&) {
    return std::nullopt;
  }
}

// The cut seed report.json records, if any.
std::optional<std::uint64_t> reported_seed(const fs::path& dir) {
  const auto report = read_json_file(dir / "report.json");
  if (!report || !report->is_object() || !report->contains("params")) return std::nullopt;
  const json& params = (*report)["params"];
  if (!params.is_object() || !params.contains("seed") || !params["seed"].is_number_unsigned()) {
    return std::nullopt;
  }
  return params["seed"].get<std::uint64_t>();
}

// The larger side of a PNG image from its IHDR chunk (0 when the file is not
// a PNG): the pictures are drawn again at the size `wearknit cut
// --picture-px` gave them (the 2x2 views: twice the panel; the layout: its
// size_px, which is its larger side).
int png_extent(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::array<unsigned char, 24> header{};
  if (!in.read(reinterpret_cast<char*>(header.data()), header.size())) return 0;
  if (header[1] != 'P' || header[2] != 'N' || header[3] != 'G') return 0;
  auto word = [&](int at) {
    return static_cast<int>((static_cast<std::uint32_t>(header[at]) << 24) |
                            (static_cast<std::uint32_t>(header[at + 1]) << 16) |
                            (static_cast<std::uint32_t>(header[at + 2]) << 8) | header[at + 3]);
  };
  return std::max(word(16), word(20));
}

// The CutReport that report.json describes (what write_cut_result wrote),
// so a re-cut keeps what it said about the input and the proxy.
CutReport report_from_json(const json& r) {
  CutReport report;
  const json input = r.value("input", json::object());
  report.input = input.value("file", std::string());
  report.units = input.value("units", std::string("mm"));
  report.scale = input.value("scale", 1.0);
  const auto size = input.value("size_mm", std::vector<double>{0, 0, 0});
  if (size.size() == 3) report.input_size_mm = Vec3(size[0], size[1], size[2]);
  report.input_vertices = input.value("vertices", 0);
  report.input_faces = input.value("faces", 0);
  const json proxy = r.value("proxy", json::object());
  report.remeshed = proxy.value("remeshed", false);
  report.proxy_method = proxy.value("method", std::string("input"));
  report.remesh_failure = proxy.value("remesh_failure", std::string());
  report.proxy_edge_mm = proxy.value("edge_mm", 0.0);
  report.polygons_split = proxy.value("polygons_split", 0);
  report.triangles_paired = proxy.value("triangles_paired", 0);
  report.samples = proxy.value("samples", 0);
  report.holes_filled = proxy.value("holes_filled", 0);
  report.folds_removed = proxy.value("folds_removed", 0);
  report.remesh_attempts = proxy.value("remesh_attempts", 0);
  const json params = r.value("params", json::object());
  report.params.seed = params.value("seed", report.params.seed);
  report.params.cs = params.value("cs", report.params.cs);
  report.params.co = params.value("co", report.params.co);
  report.params.vanishing.fewest_irregular = params.value("vanishing", "acute") == "regular";
  report.params.vanishing.slack_deg = params.value("vanishing_slack_deg", 0.0);
  const json time = r.value("time_s", json::object());
  report.load_seconds = time.value("load", 0.0);
  report.proxy_seconds = time.value("proxy", 0.0);
  return report;
}

// SplitMix64 finaliser (the same mixing as the elimination's seeds).
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

}  // namespace

std::optional<CutFolder> read_cut_folder(const std::string& dir, knitout::DiagnosticSink& sink,
                                         int min_vertices) {
  const std::string mesh_path = (fs::path(dir) / "cut-mesh.obj").string();
  const std::string cuts_path = (fs::path(dir) / "cuts.json").string();
  const std::size_t errors_before = sink.error_count();
  const auto cut_mesh = read_stage_mesh(mesh_path, sink);
  json cuts;
  {
    std::ifstream in(cuts_path);
    if (!in) {
      sink.error(cuts_path, 0, 0, "W004", "cannot open file");
    } else {
      try {
        cuts = json::parse(in);
      } catch (const json::parse_error& e) {
        sink.error(cuts_path, 0, 0, "W010", std::string("not JSON: ") + e.what());
      }
    }
  }
  if (!cut_mesh || sink.error_count() != errors_before) return std::nullopt;
  auto cover = read_cover_mesh(*cut_mesh, cuts, cuts_path, sink);
  if (!cover) return std::nullopt;
  return CutFolder{refined_for_cloth(std::move(*cover), min_vertices), std::move(cuts)};
}

std::uint64_t recut_seed(std::uint64_t wearability_seed, int attempt) {
  // "CUT" tags the stream, apart from the runs' and trials' seeds.
  return mix(mix(wearability_seed ^ 0x435554ULL) + static_cast<std::uint64_t>(attempt));
}

std::string recut_folder(const std::string& dir, std::uint64_t seed) {
  const fs::path base(dir);
  if (!fs::is_regular_file(base / "proxy.obj") || !fs::is_regular_file(base / "report.json")) {
    return dir + " has no proxy.obj and report.json (not a folder written by wearknit cut)";
  }
  const auto report_json = read_json_file(base / "report.json");
  if (!report_json || !report_json->is_object()) {
    return (base / "report.json").string() + " is not a JSON object";
  }
  CutReport report;
  try {
    report = report_from_json(*report_json);
  } catch (const json::exception& e) {
    return (base / "report.json").string() + ": unexpected content: " + e.what();
  }
  knitout::DiagnosticSink sink;
  const std::string proxy_path = (base / "proxy.obj").string();
  auto proxy = read_polygon_soup(proxy_path, sink);
  if (!proxy || !check_mesh(*proxy, proxy_path, sink)) {
    return sink.diagnostics().empty() ? proxy_path + ": cannot be read"
                                      : knitout::format(sink.diagnostics().front());
  }
  report.params.seed = seed;
  CutMesh cut;
  const auto start = std::chrono::steady_clock::now();
  try {
    cut = cut_surface(HalfedgeMesh(std::move(*proxy)), report.params);
  } catch (const std::exception& e) {
    return proxy_path + ": cutting with seed " + std::to_string(seed) + " failed: " + e.what();
  }
  report.cut_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto problems = verify_cut(cut);
  if (!problems.empty()) {
    // A broken invariant of the cutter: say so, do not write the cut.
    return "internal error: the cut with seed " + std::to_string(seed) +
           " violates its guarantees: " + problems.front();
  }
  // The pictures are drawn again only if `wearknit cut` drew them.
  const int cuts_width = png_extent(base / "cuts-3d.png");
  const int layout_width = png_extent(base / "layout-2d.png");
  std::string failure = write_cut_result(dir, cut, report);
  if (failure.empty() && cuts_width > 0) {
    failure = draw_cuts_3d(cut, (base / "cuts-3d.png").string(), std::max(cuts_width / 2, 50));
  }
  if (failure.empty() && layout_width > 0) {
    failure = draw_layout_2d(cut, (base / "layout-2d.png").string(), layout_width);
  }
  return failure;
}

CutFolderStudy study_cut_folder(const std::string& dir, CutFolder folder,
                                const cloth::SignedDistanceField& wearer,
                                const WearabilityParams& params, int runs, const RecutParams& recut,
                                knitout::DiagnosticSink& sink, const ProgressCallback& progress,
                                const std::function<void(const CutAttempt&)>& on_attempt) {
  CutFolderStudy result;
  result.folder = std::move(folder);
  std::optional<std::uint64_t> seed = reported_seed(dir);
  for (int attempt = 0;; ++attempt) {
    result.study = study_lacing(result.folder.cover, wearer, params, runs, progress);
    CutAttempt tried;
    tried.attempt = attempt;
    tried.cut_seed = seed;
    tried.arcs = static_cast<int>(result.folder.cover.arcs.size());
    tried.wearable = result.wearable();
    if (!result.study.runs.empty()) tried.trials = result.study.runs.front().initial.trials;
    result.attempts.push_back(tried);
    if (on_attempt) on_attempt(tried);
    if (tried.wearable || attempt >= recut.limit) break;

    // §5: the garment with every cut open is not wearable: cut again.
    CutAttempt next;
    next.attempt = attempt + 1;
    next.cut_seed = recut_seed(params.seed, attempt + 1);
    next.failure = recut_folder(dir, *next.cut_seed);
    if (next.failure.empty()) {
      auto reread = read_cut_folder(dir, sink, recut.min_vertices);
      if (reread) {
        result.folder = std::move(*reread);
        seed = next.cut_seed;
        continue;
      }
      next.failure = "the re-cut folder cannot be read back";
    }
    result.attempts.push_back(next);
    if (on_attempt) on_attempt(next);
    break;
  }
  return result;
}

bool CutFolderStudy::recut() const {
  for (std::size_t i = 1; i < attempts.size(); ++i) {
    if (attempts[i].failure.empty()) return true;
  }
  return false;
}

std::optional<std::uint64_t> CutFolderStudy::cut_seed() const {
  for (auto it = attempts.rbegin(); it != attempts.rend(); ++it) {
    if (it->failure.empty()) return it->cut_seed;
  }
  return std::nullopt;
}

json attempts_json(const std::vector<CutAttempt>& attempts) {
  json list = json::array();
  for (const auto& a : attempts) {
    json entry = {{"attempt", a.attempt},
                  {"cut_seed", a.cut_seed ? json(*a.cut_seed) : json(nullptr)},
                  {"arcs", a.arcs},
                  {"wearable", a.wearable},
                  {"initial_trials", trials_json(a.trials)}};
    if (!a.failure.empty()) entry["failure"] = a.failure;
    list.push_back(entry);
  }
  return list;
}

void annotate_cut_folder(CutFolderStudy& result, const WearabilityParams& params) {
  annotate_cuts(result.folder.cuts, result.study, params);
  json& summary = result.folder.cuts["wearability"];
  summary["recut"] = result.recut();
  const auto seed = result.cut_seed();
  summary["cut_seed"] = seed ? json(*seed) : json(nullptr);
  summary["cut_attempts"] = attempts_json(result.attempts);
}

std::string record_attempts(const std::string& dir, const CutFolderStudy& result) {
  const fs::path path = fs::path(dir) / "report.json";
  if (!fs::is_regular_file(path)) return {};
  auto report = read_json_file(path);
  if (!report || !report->is_object()) return path.string() + ": not a JSON object";
  const auto seed = result.cut_seed();
  (*report)["wearability"] = {{"wearable", result.wearable()},
                              {"recut", result.recut()},
                              {"cut_seed", seed ? json(*seed) : json(nullptr)},
                              {"cut_attempts", attempts_json(result.attempts)}};
  return knitout::write_file_atomically(path.string(),
                                        [&](std::ostream& out) { out << report->dump(1) << '\n'; });
}

}  // namespace planner
