// The remesher's steps in order (remesh_internal.hpp says where each lives),
// and the checks its result must pass.
#include "planner/proxy/remesh.hpp"

#include <string>

#include "knitout/diagnostic.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/soup.hpp"
#include "planner/proxy/remesh_internal.hpp"

namespace planner {

namespace {

// Whether `mesh` passes the input checks; if not, stats.failure is `what`
// and the first problem.
bool is_clean_surface(const PolygonMesh& mesh, const std::string& what, RemeshStats& stats) {
  knitout::DiagnosticSink sink;
  if (check_mesh(mesh, "remesh", sink)) return true;
  stats.failure = what + ": " + sink.diagnostics().front().message;
  return false;
}

}  // namespace

std::optional<PolygonMesh> field_aligned_remesh(const PolygonMesh& input,
                                                const RemeshParams& params, RemeshStats& stats) {
  const double s = params.edge_mm;
  // Samples about half a lattice step apart, so every lattice cell holds some.
  const HalfedgeMesh samples(sample_surface(input, params.sample_ratio * s));
  stats.samples = samples.num_vertices();
  remesh_detail::LatticeFields fields = remesh_detail::solve_fields(
      samples, s, params.orientation_iterations, params.position_iterations);
  PolygonMesh mesh = remesh_detail::extract_lattice(samples, std::move(fields), params);
  drop_unused_vertices(mesh);
  remesh_detail::split_pinched_vertices(mesh);
  stats.folds_removed += remesh_detail::weld_folds(mesh, params.fold_ratio);
  remesh_detail::keep_largest_component(mesh);
  if (!is_clean_surface(mesh, "extracted mesh is not a clean surface", stats)) return std::nullopt;
  const HalfedgeMesh source(input);
  if (HalfedgeMesh(mesh).count_boundary_loops() > source.count_boundary_loops()) {
    stats.holes_filled = remesh_detail::fill_holes(mesh, source.count_boundary_loops(), 16);
    if (stats.holes_filled > 0) {
      remesh_detail::split_pinched_vertices(mesh);
      // A fold along a hole's rim has both short corners on the boundary
      // until the hole is closed.
      stats.folds_removed += remesh_detail::weld_folds(mesh, params.fold_ratio);
      if (!is_clean_surface(mesh, "extracted mesh with its holes closed is not a clean surface",
                            stats)) {
        return std::nullopt;
      }
    }
  }
  const HalfedgeMesh result(mesh);
  if (result.euler_characteristic() != source.euler_characteristic() ||
      result.count_boundary_loops() != source.count_boundary_loops()) {
    stats.failure = "extracted mesh has Euler characteristic " +
                    std::to_string(result.euler_characteristic()) + " and " +
                    std::to_string(result.count_boundary_loops()) + " boundary loops, the input " +
                    std::to_string(source.euler_characteristic()) + " and " +
                    std::to_string(source.count_boundary_loops());
    return std::nullopt;
  }
  return mesh;
}

}  // namespace planner
