#include "planner/cut/cut_stage.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "planner/common/index.hpp"
#include "planner/mesh/girth.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/surface_distance.hpp"
#include "planner/pipeline.hpp"

namespace planner {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Cuts `proxy` with `params` (and the given vanishing corners, when there
// are any) and checks the cut's guarantees.
CutMesh checked_cut(HalfedgeMesh proxy, const CutParams& params,
                    const std::vector<int>& vanishing_corner) {
  CutMesh cut =
      cut_surface(std::move(proxy), params, vanishing_corner.empty() ? nullptr : &vanishing_corner);
  const std::vector<std::string> problems = verify_cut(cut);
  if (!problems.empty()) {
    std::string message =
        "the cut with seed " + std::to_string(params.seed) + " violates its guarantees:";
    for (const std::string& p : problems) message += "\n  " + p;
    throw std::logic_error(message);
  }
  return cut;
}

// The smoothest cross field of `garment` at `edge_mm`, into the report.
void report_field(const PolygonMesh& garment, double edge_mm, CutReport& report) {
  const auto start = std::chrono::steady_clock::now();
  CrossFieldParams field_params;
  field_params.edge_mm = edge_mm;
  const CrossField field = smoothest_cross_field(garment, field_params);
  report.field.edge_mm = field_params.edge_mm;
  report.field.faces = static_cast<int>(field.surface.faces.size());
  report.field.euler_characteristic = field.euler_characteristic;
  report.field.boundary_loops = field.boundary_loops;
  report.field.singularities = field_singularities(field);
  report.field.iterations = field.iterations;
  report.field_seconds += seconds_since(start);
}

// --proxy field with a quad-dominant input: the input is kept when it is
// clean against the field's f singularities, at most min(clean_ratio * f,
// clean_bound_ratio * f + clean_bound_extra) singular vertices with the
// cut's vanishing rule, no more than clean_pairs_ratio of them in adjacent
// +1/-1 pairs. Returns the verdict; `clean` says which, and `vanishing_corner`
// holds the corners of the labels judged, for the cut to reuse.
std::string judge_input(const PolygonMesh& input, const CutStageParams& params, int f, bool& clean,
                        std::vector<int>& vanishing_corner) {
  const HalfedgeMesh q(input);
  FieldLabels labels = label_field(q, params.cut.vanishing);
  const int singular = static_cast<int>(labels.singular_vertices.size());
  const int pairs = adjacent_opposite_pairs(q, labels);
  const ProxyParams& p = params.proxy;
  const double bound = std::min(p.clean_ratio * f, p.clean_bound_ratio * f + p.clean_bound_extra);
  clean = singular <= bound && pairs <= p.clean_pairs_ratio * singular;
  std::ostringstream text;
  text << std::setprecision(3) << (clean ? "kept" : "remeshed") << ": the input has " << singular
       << " singular vertices (" << pairs << " in adjacent +1/-1 pairs) against the field's " << f
       << "; clean is at most " << bound << " with at most " << 100 * p.clean_pairs_ratio
       << "% in pairs";
  vanishing_corner = std::move(labels.vanishing_corner);
  return text.str();
}

void take_proxy(const ProxyResult& proxy, CutReport& report) {
  report.remeshed = proxy.remeshed;
  report.proxy_edge_mm = proxy.edge_mm;
  report.polygons_split = proxy.polygons_split;
  report.triangles_paired = proxy.triangles_paired;
  report.samples = proxy.samples;
  report.holes_filled = proxy.holes_filled;
  report.folds_removed = proxy.folds_removed;
  report.remesh_attempts = proxy.remesh_attempts;
  report.edge_candidates = proxy.edge_candidates;
  report.proxy_method = proxy.method;
  report.remesh_failure = proxy.remesh_failure;
  report.valence_flips = proxy.valence_flips;
  report.field_misfit = proxy.field_misfit;
}

}  // namespace

Cut cut_garment(const PolygonMesh& garment, const CutStageParams& params) {
  Cut result;
  CutReport& report = result.report;
  report.params = params.cut;
  report.input_size_mm = bounding_box_size(garment);
  report.input_vertices = static_cast<int>(garment.positions.size());
  report.input_faces = static_cast<int>(garment.faces.size());

  auto start = std::chrono::steady_clock::now();
  ProxyResult proxy = make_proxy(garment, params.proxy);
  report.proxy_seconds = seconds_since(start);

  // The field at the proxy's scale: detail far below an edge of Q, which
  // Q cannot follow, makes no singularity there either.
  report_field(garment, proxy.edge_mm, report);
  if (params.proxy.method == ProxyMethod::Field && proxy.method == "input") {
    start = std::chrono::steady_clock::now();
    bool clean = false;
    std::vector<int> judged;
    report.input_verdict =
        judge_input(proxy.mesh, params, report.field.singularities.count, clean, judged);
    if (clean) {
      proxy.vanishing_corner = std::move(judged);  // the cut's own rule gave them
    } else {
      proxy = make_field_proxy(garment, params.proxy);
    }
    report.proxy_seconds += seconds_since(start);
    if (!clean) {  // the yardstick at the new proxy's scale
      report.field_seconds = 0.0;
      report_field(garment, proxy.edge_mm, report);
    }
  }
  const SurfaceDistance off = distance_to_surface(proxy.mesh, garment);
  report.surface_distance_max_mm = off.max_mm;
  report.surface_distance_mean_mm = off.mean_mm;
  const std::vector<int> vanishing_corner = std::move(proxy.vanishing_corner);
  HalfedgeMesh q(std::move(proxy.mesh));
  take_proxy(proxy, report);

  start = std::chrono::steady_clock::now();
  result.girth_mm = girth_at(garment, measure_girth(garment), q.polygons().positions);
  result.surface = garment;
  report.girth_seconds = seconds_since(start);

  start = std::chrono::steady_clock::now();
  result.mesh = checked_cut(std::move(q), params.cut, vanishing_corner);
  report.cut_seconds = seconds_since(start);
  return result;
}

Cut recut(const Cut& cut, std::uint64_t seed) {
  Cut result;
  result.report = cut.report;
  result.report.params.seed = seed;
  result.girth_mm = cut.girth_mm;  // the same Q
  const auto start = std::chrono::steady_clock::now();
  // The field-guided proxy's corners come from its field, not from a rule.
  const std::vector<int> none;
  const std::vector<int>& corners =
      cut.report.proxy_method == "field" ? cut.mesh.labels.vanishing_corner : none;
  result.mesh = checked_cut(HalfedgeMesh(cut.mesh.proxy.polygons()), result.report.params, corners);
  result.report.cut_seconds = seconds_since(start);
  return result;
}

FieldSingularities proxy_singularities(const CutMesh& cut) {
  FieldSingularities s;
  for (const int v : cut.labels.irregular_vertices) {
    const int index = 4 - cut.labels.corner_count[at(v)];
    ++s.count;
    s.index_sum += index;
    ++s.by_index[index];
  }
  return s;
}

namespace {

// "+1: 8, -1: 2": the count of each index, the most frequent first.
std::string by_index_text(const FieldSingularities& s) {
  std::vector<std::pair<int, int>> counts;
  for (const auto& [index, count] : s.by_index) counts.emplace_back(-count, index);
  std::sort(counts.begin(), counts.end());
  std::string text;
  for (const auto& [negative_count, index] : counts) {
    if (!text.empty()) text += ", ";
    text += (index > 0 ? "+" : "") + std::to_string(index) + ": " + std::to_string(-negative_count);
  }
  return text.empty() ? "none" : text;
}

}  // namespace

std::string describe(const Cut& cut) {
  const CutReport& r = cut.report;
  const CutSummary s = summarize(cut.mesh);
  std::ostringstream text;
  text << std::fixed << std::setprecision(1) << r.input << ": " << r.input_size_mm.x() << " x "
       << r.input_size_mm.y() << " x " << r.input_size_mm.z() << " mm; proxy "
       << cut.mesh.proxy.num_faces() << " faces"
       << (r.remeshed ? " (remeshed: " + r.proxy_method + ")" : std::string(" (input as is)"))
       << "\n";
  const FieldReport& f = r.field;
  const FieldSingularities q = proxy_singularities(cut.mesh);
  if (f.faces == 0) {
    text << "field: not computed";
  } else {
    text << "field: " << f.singularities.count << " singularities ("
         << by_index_text(f.singularities) << "; index sum " << f.singularities.index_sum
         << ", Euler characteristic " << f.euler_characteristic << ") at " << f.edge_mm << " mm";
  }
  text << "; Q: " << q.count << " irregular vertices (" << by_index_text(q) << "), "
       << cut.mesh.labels.singular_vertices.size() << " singular, "
       << adjacent_opposite_pairs(cut.mesh.proxy, cut.mesh.labels) << " adjacent +1/-1 pairs\n"
       << (r.input_verdict.empty() ? std::string() : "proxy " + r.input_verdict + "\n")
       << "cut: " << s.irregular_vertices << " irregular vertices, " << s.cut_edges
       << " cut edges in " << s.arcs << " arcs, " << s.cut_length_mm << " mm, "
       << s.overlapping_faces << " overlapping faces, " << std::setprecision(3)
       << r.proxy_seconds + r.field_seconds + r.girth_seconds + r.cut_seconds << " s\n";
  // The narrowest part of the garment, for the fine features the
  // stitch-mesh stage judges at its gauge (docs/stitch-mesh.md).
  int narrowest = -1;
  for (std::size_t v = 0; v < cut.girth_mm.size(); ++v) {
    if (narrowest < 0 || cut.girth_mm[v] < cut.girth_mm[at(narrowest)])
      narrowest = static_cast<int>(v);
  }
  if (narrowest >= 0 && std::isfinite(cut.girth_mm[at(narrowest)])) {
    const Vec3& p = cut.mesh.proxy.position(narrowest);
    text << std::setprecision(1) << "girth: narrowest " << cut.girth_mm[at(narrowest)]
         << " mm round, at (" << p.x() << ", " << p.y() << ", " << p.z() << ") mm\n";
  }
  return text.str();
}

}  // namespace planner
