#include "planner/smobj_read.hpp"

#include <charconv>
#include <fstream>
#include <istream>
#include <sstream>
#include <vector>

namespace planner {
namespace {

bool parse_uint(std::string_view text, std::uint32_t& value) {
  const auto slash = text.find('/');
  if (slash != std::string_view::npos) text = text.substr(0, slash);
  auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && ptr == text.data() + text.size();
}

}  // namespace

StitchMesh read_smobj(std::istream& in, std::string_view source, knitout::DiagnosticSink& sink) {
  StitchMesh mesh;
  std::vector<std::vector<EdgeRole>> library;
  std::vector<std::uint32_t> face_lines;
  std::size_t typed = 0;
  std::string text;
  std::uint32_t line = 0;
  auto error = [&](std::string_view code, std::string message) {
    sink.error(source, line, 0, code, std::move(message));
  };
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    const auto hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    std::istringstream words(text);
    std::string op;
    if (!(words >> op)) continue;
    if (op == "L") {
      std::string name, edge;
      words >> name;
      std::vector<EdgeRole> roles;
      bool ok = !name.empty();
      while (words >> edge) {
        const char sign = edge[0] == '+' || edge[0] == '-' ? edge[0] : 0;
        const char kind = sign != 0 && edge.size() > 1 ? edge[1] : edge[0];
        if (kind == 'l' && sign != 0) {
          roles.push_back(sign == '-' ? EdgeRole::CourseIn : EdgeRole::CourseOut);
        } else if (kind == 'y') {
          roles.push_back(EdgeRole::Wale);
        } else {
          error("S902", "library face '" + name + "': edge type '" + edge +
                            "' is neither a directed loop edge (-l/+l) nor a yarn edge (y)");
          ok = false;
        }
      }
      if (ok && roles.size() < 3) {
        error("S902", "library face '" + name + "' has fewer than three edges");
      }
      library.push_back(std::move(roles));
    } else if (op == "v") {
      Eigen::Vector3d p;
      if (!(words >> p.x() >> p.y() >> p.z())) {
        error("S901", "vertex line needs three numbers");
        continue;
      }
      mesh.positions.push_back(p);
    } else if (op == "f") {
      StitchFace face;
      std::string word;
      while (words >> word) {
        std::uint32_t v = 0;
        if (!parse_uint(word, v) || v == 0) {
          error("S901", "face vertex '" + word + "' is not a 1-based index");
          continue;
        }
        face.vertices.push_back(v - 1);
      }
      mesh.faces.push_back(std::move(face));
      face_lines.push_back(line);
    } else if (op == "T") {
      std::string word;
      while (words >> word) {
        std::uint32_t k = 0;
        if (typed >= mesh.faces.size()) {
          error("S903",
                "type given for face " + std::to_string(typed + 1) + ", which is not defined yet");
          break;
        }
        if (!parse_uint(word, k) || k == 0 || k > library.size()) {
          error("S903", "face type '" + word + "' is not an index into the " +
                            std::to_string(library.size()) + "-entry face library");
          ++typed;
          continue;
        }
        StitchFace& face = mesh.faces[typed];
        face.roles = library[k - 1];
        if (face.roles.size() != face.vertices.size()) {
          error("S903", "face " + std::to_string(typed + 1) + " has " +
                            std::to_string(face.vertices.size()) + " vertices but library face " +
                            std::to_string(k) + " has " + std::to_string(face.roles.size()) +
                            " edges");
        }
        ++typed;
      }
    }
  }
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    StitchFace& face = mesh.faces[f];
    line = face_lines[f];
    for (std::uint32_t v : face.vertices) {
      if (v >= mesh.positions.size()) {
        error("S904", "face " + std::to_string(f + 1) + ": vertex " + std::to_string(v + 1) +
                          " does not exist (" + std::to_string(mesh.positions.size()) +
                          " vertices)");
        break;
      }
    }
    if (f >= typed) {
      error("S905", "face " + std::to_string(f + 1) + " has no type (`T` line)");
      continue;
    }
    face.arcs.assign(face.vertices.size(), kNoArc);
    int ins = 0, outs = 0;
    for (EdgeRole r : face.roles) {
      ins += r == EdgeRole::CourseIn ? 1 : 0;
      outs += r == EdgeRole::CourseOut ? 1 : 0;
    }
    face.type = face.vertices.size() == 3 ? FaceType::ShortRow
                : ins == 2                ? FaceType::Decrease
                : outs == 2               ? FaceType::Increase
                                          : FaceType::Knit;
  }
  return mesh;
}

StitchMesh read_smobj_file(const std::string& path, knitout::DiagnosticSink& sink) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    sink.error(path, 0, 0, "S900", "cannot open the stitch mesh");
    return {};
  }
  return read_smobj(in, path, sink);
}

}  // namespace planner
