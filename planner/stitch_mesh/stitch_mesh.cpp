#include "planner/stitch_mesh/stitch_mesh.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <iomanip>
#include <map>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace planner {
namespace {

std::string_view role_name(EdgeRole role) {
  switch (role) {
    case EdgeRole::CourseIn:
      return "course-in";
    case EdgeRole::CourseOut:
      return "course-out";
    case EdgeRole::Wale:
      return "wale";
  }
  return "?";
}

bool roles_match(EdgeRole a, EdgeRole b) {
  if (a == EdgeRole::Wale) return b == EdgeRole::Wale;
  if (a == EdgeRole::CourseIn) return b == EdgeRole::CourseOut;
  return b == EdgeRole::CourseIn;
}

// Roles read cyclically from `start`.
std::vector<EdgeRole> rotated(const std::vector<EdgeRole>& roles, std::size_t start) {
  std::vector<EdgeRole> out;
  out.reserve(roles.size());
  for (std::size_t i = 0; i < roles.size(); ++i) out.push_back(roles[(start + i) % roles.size()]);
  return out;
}

using R = EdgeRole;
const std::vector<R> kKnit{R::CourseIn, R::Wale, R::CourseOut, R::Wale};
const std::vector<R> kIncrease{R::CourseIn, R::Wale, R::CourseOut, R::CourseOut, R::Wale};
const std::vector<R> kDecrease{R::CourseIn, R::CourseIn, R::Wale, R::CourseOut, R::Wale};
const std::vector<R> kShortRowLeft{R::CourseIn, R::Wale, R::CourseOut};   // ends on its left
const std::vector<R> kShortRowRight{R::CourseIn, R::CourseOut, R::Wale};  // ends on its right

}  // namespace

std::string_view face_type_name(FaceType type) {
  switch (type) {
    case FaceType::Knit:
      return "knit";
    case FaceType::Increase:
      return "increase";
    case FaceType::Decrease:
      return "decrease";
    case FaceType::ShortRow:
      return "short-row";
  }
  return "?";
}

std::optional<FaceType> classify_roles(const std::vector<EdgeRole>& roles, std::size_t* first) {
  for (std::size_t start = 0; start < roles.size(); ++start) {
    const std::vector<EdgeRole> r = rotated(roles, start);
    std::optional<FaceType> type;
    if (r == kKnit) type = FaceType::Knit;
    if (r == kIncrease) type = FaceType::Increase;
    if (r == kDecrease) type = FaceType::Decrease;
    if (r == kShortRowLeft || r == kShortRowRight) type = FaceType::ShortRow;
    if (type) {
      if (first != nullptr) *first = start;
      return type;
    }
  }
  return std::nullopt;
}

std::vector<std::string> check(const StitchMesh& mesh) {
  std::vector<std::string> problems;
  auto say = [&](const std::string& text) { problems.push_back(text); };
  // Directed side (a, b) -> (face, side).
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<std::size_t, std::size_t>> sides;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const StitchFace& face = mesh.faces[f];
    const std::string where = "face " + std::to_string(f);
    if (face.roles.size() != face.vertices.size() || face.arcs.size() != face.vertices.size()) {
      say(where + ": " + std::to_string(face.vertices.size()) + " vertices, " +
          std::to_string(face.roles.size()) + " roles, " + std::to_string(face.arcs.size()) +
          " arcs");
      continue;
    }
    bool in_range = true;
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      if (face.vertices[i] >= mesh.positions.size()) {
        say(where + " corner " + std::to_string(i) + ": vertex " +
            std::to_string(face.vertices[i]) + " out of range (" +
            std::to_string(mesh.positions.size()) + " vertices)");
        in_range = false;
      }
    }
    if (!in_range) continue;
    std::vector<std::uint32_t> sorted = face.vertices;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
      say(where + ": a vertex appears twice");
    }
    const std::optional<FaceType> type = classify_roles(face.roles);
    if (!type) {
      std::string text = where + ": roles";
      for (EdgeRole role : face.roles) text += " " + std::string(role_name(role));
      say(text + " make no valid face (§6.3)");
    } else if (*type != face.type) {
      say(where + ": type " + std::string(face_type_name(face.type)) + " but its roles make " +
          std::string(face_type_name(*type)));
    }
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const auto key = std::make_pair(face.vertices[i], face.vertices[(i + 1) % n]);
      auto [it, inserted] = sides.emplace(key, std::make_pair(f, i));
      if (!inserted) {
        say(where + " side " + std::to_string(i) + ": runs from vertex " +
            std::to_string(key.first) + " to " + std::to_string(key.second) + " like face " +
            std::to_string(it->second.first) + " side " + std::to_string(it->second.second) +
            " (not one oriented surface)");
      }
    }
  }
  for (const auto& [key, at] : sides) {
    auto twin = sides.find({key.second, key.first});
    if (twin == sides.end() || key.first > key.second) continue;
    const StitchFace& a = mesh.faces[at.first];
    const StitchFace& b = mesh.faces[twin->second.first];
    const EdgeRole ra = a.roles[at.second];
    const EdgeRole rb = b.roles[twin->second.second];
    if (!roles_match(ra, rb)) {
      say("face " + std::to_string(at.first) + " side " + std::to_string(at.second) + ": " +
          std::string(role_name(ra)) + " meets face " + std::to_string(twin->second.first) +
          " side " + std::to_string(twin->second.second) + " as " + std::string(role_name(rb)));
    }
  }
  return problems;
}

namespace {

std::string library_edges(const std::vector<EdgeRole>& roles) {
  std::string text;
  for (EdgeRole role : roles) {
    if (!text.empty()) text += ' ';
    text += role == EdgeRole::CourseIn ? "-l1" : role == EdgeRole::CourseOut ? "+l1" : "y1";
  }
  return text;
}

}  // namespace

void write_smobj(std::ostream& out, const StitchMesh& mesh) {
  const std::vector<std::string> problems = check(mesh);
  if (!problems.empty()) {
    throw std::logic_error("write_smobj: invalid stitch mesh: " + problems.front());
  }
  std::ostringstream text;
  text << std::setprecision(17);
  text << "# stitch mesh (wearknit, paper §6): one face per stitch, lengths in mm\n"
       << "# wearknit course_mm " << mesh.course_mm << " wale_mm " << mesh.wale_mm << "\n"
       << "# library: name, then edge types counter-clockwise from the bottom left:\n"
       << "#   -l1 loop edge in (course, from the row below), +l1 loop edge out (course,\n"
       << "#   to the row above), y1 yarn edge (wale, direction set by the knitting order)\n";
  // Each face is written starting at its bottom-left course-in side, so the
  // library entry names the edge types in the order the face lists them.
  std::map<std::string, std::size_t> library;
  std::vector<std::string> library_lines;
  std::vector<std::size_t> face_library(mesh.faces.size());
  std::vector<std::size_t> face_start(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const StitchFace& face = mesh.faces[f];
    std::size_t start = 0;
    classify_roles(face.roles, &start);
    const std::string entry =
        std::string(face_type_name(face.type)) + " " + library_edges(rotated(face.roles, start));
    auto [it, inserted] = library.emplace(entry, library_lines.size() + 1);
    if (inserted) library_lines.push_back(entry);
    face_library[f] = it->second;
    face_start[f] = start;
  }
  for (const std::string& line : library_lines) text << "L " << line << "\n";
  for (const Eigen::Vector3d& p : mesh.positions) {
    text << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  }
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const StitchFace& face = mesh.faces[f];
    text << "f";
    for (std::size_t i = 0; i < face.vertices.size(); ++i) {
      text << " " << face.vertices[(face_start[f] + i) % face.vertices.size()] + 1;
    }
    text << "\n";
  }
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) text << "T " << face_library[f] << "\n";
  // Connections: every interior side once; on an oriented mesh the second
  // side is reversed.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<std::size_t, std::size_t>> sides;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const StitchFace& face = mesh.faces[f];
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t written = (i + n - face_start[f]) % n;
      sides[{face.vertices[i], face.vertices[(i + 1) % n]}] = {f, written};
    }
  }
  for (const auto& [key, at] : sides) {
    if (key.first > key.second) continue;
    auto twin = sides.find({key.second, key.first});
    if (twin == sides.end()) continue;
    text << "e " << at.first + 1 << "/" << at.second + 1 << " " << twin->second.first + 1 << "/-"
         << twin->second.second + 1 << "\n";
  }
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const StitchFace& face = mesh.faces[f];
    const std::size_t n = face.vertices.size();
    for (std::size_t i = 0; i < n; ++i) {
      if (face.arcs[i] == kNoArc) continue;
      text << "# arc " << f + 1 << "/" << (i + n - face_start[f]) % n + 1 << " " << face.arcs[i]
           << "\n";
    }
  }
  out << text.str();
}

namespace {

struct LibraryEntry {
  FaceType type = FaceType::Knit;
  std::vector<EdgeRole> roles;
};

}  // namespace

std::optional<StitchMesh> parse_smobj(std::istream& in, const std::string& source,
                                      knitout::DiagnosticSink& sink) {
  StitchMesh mesh;
  std::vector<LibraryEntry> library;
  std::vector<std::size_t> types;
  std::vector<std::uint32_t> type_lines;
  std::vector<std::uint32_t> face_lines;
  std::vector<std::pair<std::uint32_t, std::array<std::int64_t, 3>>> arc_lines;
  std::string line;
  std::uint32_t number = 0;
  auto bad = [&](std::string_view code, std::string message) {
    sink.error(source, number, 0, code, std::move(message));
  };
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string word;
    if (!(words >> word)) continue;
    if (word == "#") {
      std::string what;
      words >> what;
      if (what == "wearknit") {
        std::string key;
        double value = 0;
        while (words >> key >> value) {
          if (key == "course_mm") mesh.course_mm = value;
          if (key == "wale_mm") mesh.wale_mm = value;
        }
      } else if (what == "arc") {
        std::string at;
        std::int64_t arc = 0;
        std::int64_t f = 0;
        std::int64_t e = 0;
        char slash = 0;
        std::istringstream at_words;
        if (!(words >> at >> arc) || (at_words.str(at), !(at_words >> f >> slash >> e)) ||
            slash != '/' || f < 1 || e < 1 || arc < 0) {
          bad("P081", "malformed arc line, expected `# arc FACE/SIDE ARC`");
          continue;
        }
        arc_lines.push_back({number, {f - 1, e - 1, arc}});
      }
      continue;
    }
    if (word[0] == '#') continue;
    if (word == "L") {
      LibraryEntry entry;
      std::string name;
      words >> name;
      if (name == "knit") {
        entry.type = FaceType::Knit;
      } else if (name == "increase") {
        entry.type = FaceType::Increase;
      } else if (name == "decrease") {
        entry.type = FaceType::Decrease;
      } else if (name == "short-row") {
        entry.type = FaceType::ShortRow;
      } else {
        bad("P082", "unknown face type `" + name + "` (knit, increase, decrease, short-row)");
        entry.type = FaceType::Knit;
      }
      std::string edge;
      bool ok = true;
      while (words >> edge) {
        if (edge[0] == '#') break;
        if (edge.size() >= 2 && edge[0] == '-' && edge[1] == 'l') {
          entry.roles.push_back(EdgeRole::CourseIn);
        } else if (edge.size() >= 2 && edge[0] == '+' && edge[1] == 'l') {
          entry.roles.push_back(EdgeRole::CourseOut);
        } else if (edge[0] == 'y' || (edge.size() >= 2 && edge[1] == 'y')) {
          entry.roles.push_back(EdgeRole::Wale);
        } else {
          bad("P082", "edge type `" + edge + "` is not -lN, +lN or yN");
          ok = false;
        }
      }
      if (ok && !classify_roles(entry.roles)) {
        bad("P082", "library face `" + name + "` has edges that make no valid stitch face");
      }
      library.push_back(std::move(entry));
    } else if (word == "v") {
      Eigen::Vector3d p;
      if (!(words >> p.x() >> p.y() >> p.z())) {
        bad("P081", "vertex needs three numbers");
        p.setZero();
      }
      mesh.positions.push_back(p);
    } else if (word == "f") {
      StitchFace face;
      std::string index;
      while (words >> index) {
        long value = 0;
        try {
          value = std::stol(index.substr(0, index.find('/')));
        } catch (const std::exception&) {
          value = 0;
        }
        if (value < 1) {
          bad("P081", "face corner `" + index + "` is not a 1-based vertex index");
          continue;
        }
        face.vertices.push_back(static_cast<std::uint32_t>(value - 1));
      }
      mesh.faces.push_back(std::move(face));
      face_lines.push_back(number);
    } else if (word == "T") {
      long value = 0;
      if (!(words >> value) || value < 1) {
        bad("P081", "face type needs a 1-based library index");
        value = 0;
      }
      types.push_back(static_cast<std::size_t>(value));
      type_lines.push_back(number);
    }
    // `e` lines repeat what shared vertices already say; other commands of
    // the format (N, U, c, vt, tex) carry nothing a stitch mesh needs.
  }
  if (sink.has_errors()) return std::nullopt;
  number = 0;
  if (types.size() != mesh.faces.size()) {
    bad("P083", std::to_string(mesh.faces.size()) + " faces but " + std::to_string(types.size()) +
                    " T lines");
    return std::nullopt;
  }
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    StitchFace& face = mesh.faces[f];
    number = type_lines[f];
    if (types[f] < 1 || types[f] > library.size()) {
      bad("P083", "face " + std::to_string(f + 1) + " has library index " +
                      std::to_string(types[f]) + " (" + std::to_string(library.size()) +
                      " entries)");
      continue;
    }
    const LibraryEntry& entry = library[types[f] - 1];
    if (entry.roles.size() != face.vertices.size()) {
      number = face_lines[f];
      bad("P083", "face " + std::to_string(f + 1) + " has " + std::to_string(face.vertices.size()) +
                      " corners but its type has " + std::to_string(entry.roles.size()) + " edges");
      continue;
    }
    face.type = entry.type;
    face.roles = entry.roles;
    face.arcs.assign(face.vertices.size(), kNoArc);
  }
  if (sink.has_errors()) return std::nullopt;
  for (const auto& [at_line, arc] : arc_lines) {
    number = at_line;
    const auto f = static_cast<std::size_t>(arc[0]);
    const auto e = static_cast<std::size_t>(arc[1]);
    if (f >= mesh.faces.size() || e >= mesh.faces[f].arcs.size()) {
      bad("P081", "arc names face " + std::to_string(f + 1) + " side " + std::to_string(e + 1) +
                      ", which does not exist");
      continue;
    }
    mesh.faces[f].arcs[e] = static_cast<std::int32_t>(arc[2]);
  }
  if (sink.has_errors()) return std::nullopt;
  number = 0;
  for (const std::string& problem : check(mesh)) bad("P084", problem);
  if (sink.has_errors()) return std::nullopt;
  return mesh;
}

}  // namespace planner
