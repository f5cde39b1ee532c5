#include "planner/schedule/piece_layout.hpp"

#include <algorithm>
#include <climits>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "knitout/output_file.hpp"
#include "planner/common/index.hpp"

namespace planner {

namespace {}  // namespace

std::vector<PieceLayout> piece_layouts(const Schedule& s) {
  std::vector<int> piece_of_row(s.rows.size(), kNone);
  for (std::size_t p = 0; p < s.pieces.size(); ++p) {
    for (int r : s.pieces[p].rows) piece_of_row.at(at(r)) = static_cast<int>(p);
  }
  std::vector<PieceLayout> layouts(s.pieces.size());
  std::vector<int> level(s.rows.size(), kNone);
  for (std::size_t p = 0; p < s.pieces.size(); ++p) {
    // Rows are knit after the rows whose loops they take, so one pass in
    // knitting order gives every row the longest path below it: a row sits
    // on the highest row it is knit onto (§7.1's row graph, within the piece).
    auto below = [&](int e) -> int {
      const CourseEdge& edge = s.edges.at(at(e));
      if (edge.cut || edge.lower == kNone) return kNone;
      const int row = s.face_row.at(at(edge.lower));
      if (piece_of_row.at(at(row)) != static_cast<int>(p)) return kNone;
      return row;
    };
    for (int r : s.pieces[p].rows) {
      int l = 0;
      for (int f : s.rows.at(at(r)).faces) {
        for (int e : s.faces.at(at(f)).in) {
          const int row = below(e);
          if (row != kNone && level[at(row)] != kNone) l = std::max(l, level[at(row)] + 1);
        }
      }
      level[at(r)] = l;
    }
    int lo = INT_MAX;
    int hi = INT_MIN;
    PieceLayout& layout = layouts[p];
    for (int r : s.pieces[p].rows) {
      for (int f : s.rows[at(r)].faces) {
        const FaceLinks& links = s.faces.at(at(f));
        FaceLayout face;
        face.face = f;
        face.level = level[at(r)];
        for (int e : links.in) {
          const int row = below(e);
          face.in_needles.push_back(s.edges[at(e)].needle);
          face.in_levels.push_back(row == kNone ? face.level : level[at(row)] + 1);
        }
        for (int e : links.out) face.out_needles.push_back(s.edges[at(e)].needle);
        if (face.in_needles.empty() || face.out_needles.empty())
          throw std::logic_error("piece_layouts: face " + std::to_string(f) +
                                 " has no course edge in or out");
        for (const auto* list : {&face.in_needles, &face.out_needles}) {
          for (int n : *list) {
            lo = std::min(lo, n);
            hi = std::max(hi, n);
          }
        }
        layout.levels = std::max(layout.levels, face.level + 1);
        layout.faces.push_back(std::move(face));
      }
    }
    if (layout.faces.empty()) continue;
    for (FaceLayout& face : layout.faces) {
      for (int& n : face.in_needles) n = n - lo + 1;
      for (int& n : face.out_needles) n = n - lo + 1;
    }
    layout.needles = hi - lo + 1;
  }
  return layouts;
}

std::string write_piece_layouts(const std::string& pieces_dir, const Schedule& schedule) {
  const std::vector<PieceLayout> layouts = piece_layouts(schedule);
  for (std::size_t p = 0; p < layouts.size(); ++p) {
    nlohmann::json faces = nlohmann::json::array();
    for (const FaceLayout& f : layouts[p].faces)
      faces.push_back({f.face, f.level, f.in_needles, f.in_levels, f.out_needles});
    const nlohmann::json doc = {{"format", "wearknit-piece-layout 1"},
                                {"piece", p + 1},
                                {"needles", layouts[p].needles},
                                {"rows", layouts[p].levels},
                                {"faces", faces}};
    const std::string path =
        (std::filesystem::path(pieces_dir) / ("piece-" + std::to_string(p + 1) + ".layout.json"))
            .string();
    const std::string failure =
        knitout::write_file_atomically(path, [&](std::ostream& out) { out << doc.dump() << '\n'; });
    if (!failure.empty()) return failure;
  }
  return "";
}

std::optional<PieceLayout> read_piece_layout(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open file";
    return std::nullopt;
  }
  const nlohmann::json doc = nlohmann::json::parse(in, nullptr, false);
  if (doc.is_discarded() || !doc.is_object() ||
      doc.value("format", std::string()) != "wearknit-piece-layout 1") {
    *error = path + ": not a piece layout (wearknit-piece-layout 1)";
    return std::nullopt;
  }
  PieceLayout layout;
  try {
    layout.needles = doc.at("needles").get<int>();
    layout.levels = doc.at("rows").get<int>();
    for (const nlohmann::json& f : doc.at("faces")) {
      FaceLayout face;
      face.face = f.at(0).get<int>();
      face.level = f.at(1).get<int>();
      face.in_needles = f.at(2).get<std::vector<int>>();
      face.in_levels = f.at(3).get<std::vector<int>>();
      face.out_needles = f.at(4).get<std::vector<int>>();
      if (face.face < 0 || face.in_needles.empty() || face.out_needles.empty() ||
          face.in_levels.size() != face.in_needles.size())
        throw std::runtime_error("face entry " + f.dump() +
                                 " is not [face, level, [needles], [levels], [needles]]");
      layout.faces.push_back(std::move(face));
    }
  } catch (const std::exception& e) {
    *error = path + ": unexpected content: " + e.what();
    return std::nullopt;
  }
  return layout;
}

FaceSideRoles face_side_roles(const StitchFace& face) {
  FaceSideRoles sides;
  const int n = static_cast<int>(face.roles.size());
  if (n == 0) return sides;
  auto role = [&](int i) { return face.roles[at(((i % n) + n) % n)]; };
  auto run = [&](EdgeRole r) {
    std::vector<int> found;
    for (int i = 0; i < n; ++i) {
      if (role(i) == r && role(i - 1) != r) {
        for (int j = i; role(j) == r && static_cast<int>(found.size()) < n; ++j)
          found.push_back(j % n);
        break;
      }
    }
    if (found.empty() && role(0) == r) {
      for (int i = 0; i < n; ++i) found.push_back(i);
    }
    return found;
  };
  sides.in = run(EdgeRole::CourseIn);
  sides.out = run(EdgeRole::CourseOut);
  // Counter-clockwise seen from the front the top is walked right to left.
  std::reverse(sides.out.begin(), sides.out.end());
  for (int i = 0; i < n; ++i) {
    if (role(i) != EdgeRole::Wale) continue;
    int j = i + 1;
    while (role(j) == EdgeRole::Wale && j < i + n) ++j;
    // In, then the right side, then out; out, then the left side, then in.
    (role(j) == EdgeRole::CourseOut ? sides.right_wale : sides.left_wale) = i;
  }
  return sides;
}

std::array<std::array<double, 2>, 4> face_corners(const FaceLayout& at) {
  const double top = at.level + 1;
  return {{{at.in_needles.front() - 0.5, static_cast<double>(at.in_levels.front())},
           {at.in_needles.back() + 0.5, static_cast<double>(at.in_levels.back())},
           {at.out_needles.back() + 0.5, top},
           {at.out_needles.front() - 0.5, top}}};
}

std::array<std::array<double, 2>, 2> side_in_layout(const StitchFace& face, const FaceLayout& at,
                                                    int side) {
  const FaceSideRoles sides = face_side_roles(face);
  const auto corners = face_corners(at);
  for (std::size_t j = 0; j < sides.in.size() && j < at.in_needles.size(); ++j) {
    if (sides.in[j] != side) continue;
    const double y = at.in_levels[j];
    return {{{at.in_needles[j] - 0.5, y}, {at.in_needles[j] + 0.5, y}}};
  }
  for (std::size_t k = 0; k < sides.out.size() && k < at.out_needles.size(); ++k) {
    if (sides.out[k] != side) continue;
    const double y = at.level + 1;
    return {{{at.out_needles[k] + 0.5, y}, {at.out_needles[k] - 0.5, y}}};
  }
  if (side == sides.right_wale) return {{corners[1], corners[2]}};
  if (side == sides.left_wale) return {{corners[3], corners[0]}};
  throw std::logic_error("side_in_layout: face " + std::to_string(at.face) + " has no side " +
                         std::to_string(side));
}

}  // namespace planner
