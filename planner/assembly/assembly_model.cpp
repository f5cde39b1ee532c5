#include "planner/assembly/assembly_model.hpp"

#include <utility>

#include "planner/common/index.hpp"

namespace planner::assembly {

void fail(const std::filesystem::path& file, const char* code, const std::string& message) {
  throw Failure(file.string() + ": error: [" + code + "] " + message);
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

int shared_side(const Model& m, int face, int other, EdgeRole role) {
  const StitchFace& f = m.mesh.faces[at(face)];
  for (std::size_t i = 0; i < f.vertices.size(); ++i) {
    if (f.roles[i] != role) continue;
    if (other_side(m, {face, static_cast<int>(i)}).face == other) return static_cast<int>(i);
  }
  return kNone;
}

}  // namespace planner::assembly
