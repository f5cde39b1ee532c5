// make_cover_cut: writes a cut folder (cut-mesh.obj + cut.json, the input of
// `wearknit wearability`) for a cover made of a mesh's own surface, cut along
// one path of mesh edges through extreme points of the mesh, split into arcs.
//   make_cover_cut GARMENT.obj OUT_DIR [EDGES_PER_ARC [EXTREMES...]]
// EXTREMES name the waypoints as the vertex farthest along an axis: +x, -y,
// ... (default +x -y +z +y: for the Stanford bunny, tail → belly → chest →
// ear, a long zipper over most of the body). The path is the chain of
// shortest edge paths between consecutive waypoints, edges repeated by the
// chain dropped; every EDGES_PER_ARC edges (default 8) start a new arc.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>

#include "planner/mesh/mesh_io.hpp"
#include "planner/wearability/wearability_io.hpp"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: make_cover_cut GARMENT.obj OUT_DIR [EDGES_PER_ARC [EXTREMES...]]\n";
    return 2;
  }
  knitout::DiagnosticSink sink;
  const auto mesh = planner::read_stage_mesh(argv[1], sink);
  if (!mesh) {
    knitout::print_text(std::cerr, sink.diagnostics());
    return 1;
  }
  const int per_arc = argc > 3 ? std::max(1, std::atoi(argv[3])) : 8;
  std::vector<std::string> extremes = {"+x", "-y", "+z", "+y"};
  if (argc > 4) extremes.assign(argv + 4, argv + argc);
  planner::CoverMesh cover{*mesh, {}};
  std::vector<int> waypoints;
  for (const std::string& extreme : extremes) {
    if (extreme.size() != 2 || (extreme[0] != '+' && extreme[0] != '-') || extreme[1] < 'x' ||
        extreme[1] > 'z') {
      std::cerr << "make_cover_cut: extreme '" << extreme << "' is not one of +x -x +y -y +z -z\n";
      return 2;
    }
    const int axis = extreme[1] - 'x';
    const double sign = extreme[0] == '+' ? 1 : -1;
    int best = 0;
    for (std::size_t v = 0; v < cover.positions.size(); ++v) {
      if (sign * cover.positions[v][axis] > sign * cover.positions[best][axis])
        best = static_cast<int>(v);
    }
    waypoints.push_back(best);
  }
  std::vector<std::array<int, 2>> edges;
  std::set<std::pair<int, int>> used;
  for (std::size_t w = 0; w + 1 < waypoints.size(); ++w) {
    const auto path = planner::shortest_edge_path(cover, waypoints[w], waypoints[w + 1]);
    for (std::size_t i = 0; i + 1 < path.size(); ++i) {
      const int a = path[i], b = path[i + 1];
      if (used.insert({std::min(a, b), std::max(a, b)}).second) edges.push_back({a, b});
    }
  }
  nlohmann::json cuts = {{"arcs", nlohmann::json::array()}};
  for (std::size_t e = 0; e < edges.size(); e += per_arc) {
    nlohmann::json arc_edges = nlohmann::json::array();
    for (std::size_t k = e; k < std::min(edges.size(), e + per_arc); ++k) {
      arc_edges.push_back({edges[k][0], edges[k][1]});
    }
    cuts["arcs"].push_back({{"id", cuts["arcs"].size()}, {"edges", arc_edges}});
  }
  const std::filesystem::path dir(argv[2]);
  std::filesystem::create_directories(dir);
  std::ofstream obj(dir / "cut-mesh.obj");
  planner::write_obj(obj, cover);
  std::ofstream json(dir / "cut.json");
  json << cuts.dump(1) << '\n';
  if (!obj || !json) {
    std::cerr << "make_cover_cut: cannot write " << dir << '\n';
    return 2;
  }
  std::cout << edges.size() << " cut edges in " << cuts["arcs"].size() << " arcs -> "
            << dir.string() << '\n';
  return 0;
}
