#include "planner/mesh/mesh_scan.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "planner/mesh/kind_reporter.hpp"

namespace planner {

namespace {

// The file's lines, numbered from 1, without their line ends.
class Lines {
 public:
  explicit Lines(std::string_view bytes) : bytes_(bytes) {}
  // The next line, or nullopt at the end of the file.
  std::optional<std::string_view> next() {
    if (pos_ >= bytes_.size()) return std::nullopt;
    const std::size_t end = std::min(bytes_.find('\n', pos_), bytes_.size());
    std::string_view line = bytes_.substr(pos_, end - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end + 1;
    ++number_;
    return line;
  }
  std::uint32_t number() const { return number_; }
  std::size_t offset() const { return std::min(pos_, bytes_.size()); }

 private:
  std::string_view bytes_;
  std::size_t pos_ = 0;
  std::uint32_t number_ = 0;
};

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

// Whitespace-separated words of a line, up to a `#` comment (OBJ, OFF,
// STL; PLY has no such comments: `comments` false).
std::vector<std::string_view> words(std::string_view line, bool comments = true) {
  const std::size_t hash = comments ? line.find('#') : std::string_view::npos;
  if (hash != std::string_view::npos) line = line.substr(0, hash);
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// A number as strtod reads it; nan and inf are numbers here (the caller
// says they are not finite), as is a value too large for a double.
std::optional<double> number(std::string_view word) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (end != word.data() + word.size()) return std::nullopt;
  if (ec == std::errc::result_out_of_range) return std::numeric_limits<double>::infinity();
  if (ec != std::errc()) return std::nullopt;
  return value;
}

std::optional<std::int64_t> integer(std::string_view word) {
  if (!word.empty() && word.front() == '+') word.remove_prefix(1);
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (ec != std::errc() || end != word.data() + word.size()) return std::nullopt;
  return value;
}

std::string quoted(std::string_view text) {
  constexpr std::size_t kShown = 60;
  std::string out(text.substr(0, kShown));
  for (char& c : out) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  }
  return "`" + out + (text.size() > kShown ? "...`" : "`");
}

std::string plural(std::int64_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// The five kinds of fault, each capped.
struct Faults {
  Faults(knitout::DiagnosticSink& sink, const std::string& source)
      : coordinate(sink, source, "P003", "bad coordinates"),
        malformed(sink, source, "P004", "malformed lines"),
        corner(sink, source, "P005", "face corners naming no vertex"),
        size(sink, source, "P006", "size faults"),
        short_face(sink, source, "P010", "faces of fewer than 3 corners") {}
  KindReporter coordinate;
  KindReporter malformed;
  KindReporter corner;
  KindReporter size;
  KindReporter short_face;
};

// P006: a header whose counts (`claim`, e.g. "5 vertices and 2 faces")
// need more than the `left` bytes after it.
void claims_too_much(Faults& faults, const std::string& claim, std::uint64_t left,
                     std::uint32_t line) {
  faults.size.report("the header claims " + claim + ", more than the " + std::to_string(left) +
                         " bytes after it can hold; the header is wrong or the file is cut short",
                     line);
}

// P006: the file ends after `read` of the elements its header claims.
void ends_early(Faults& faults, std::int64_t read, const std::string& claimed,
                std::uint32_t line = 0) {
  faults.size.report(
      "the file ends after " + std::to_string(read) + " of the " + claimed + " its header claims",
      line);
}

// P005: OFF face `name`'s corner `v` is not one of its `nv` vertices.
void off_corner_missing(Faults& faults, const std::string& name, std::int64_t v, std::int64_t nv,
                        std::uint32_t line = 0) {
  faults.corner.report(name + " refers to vertex " + std::to_string(v) +
                           " (OFF numbers vertices from 0); the file has " +
                           plural(nv, "vertex", "vertices"),
                       line);
}

// Three coordinates from words[first ..]: P004 when there are not three
// numbers, P003 when one is not finite. `what` names the vertex.
std::optional<Vec3> check_point(const std::vector<std::string_view>& w, std::size_t first,
                                const std::string& what, std::uint32_t line, Faults& faults) {
  if (w.size() < first + 3) {
    faults.malformed.report(what + " has " + std::to_string(w.size() - std::min(w.size(), first)) +
                                " coordinates; a vertex needs three numbers",
                            line);
    return std::nullopt;
  }
  Vec3 p;
  for (std::size_t i = first; i < first + 3; ++i) {
    const std::optional<double> x = number(w[i]);
    if (!x) {
      faults.malformed.report(what + ": " + quoted(w[i]) + " is not a number", line);
      return std::nullopt;
    }
    if (!std::isfinite(*x)) {
      faults.coordinate.report(
          what + " has a coordinate that is not a finite number (" + quoted(w[i]) + ")", line);
      return std::nullopt;
    }
    p[static_cast<Eigen::Index>(i - first)] = *x;
  }
  return p;
}

// OBJ: v lines (three numbers), f lines (corners `i`, `i/t`, `i//n`,
// `i/t/n`; 1-based, negative counts back from the last vertex so far).
void scan_obj(std::string_view bytes, Faults& faults) {
  std::int64_t total = 0;  // v lines in the whole file (corners may point forward)
  {
    Lines lines(bytes);
    while (auto line = lines.next()) {
      const std::vector<std::string_view> w = words(*line);
      if (!w.empty() && w[0] == "v") ++total;
    }
  }
  Lines lines(bytes);
  std::int64_t vertices = 0;
  std::int64_t faces = 0;
  while (auto line = lines.next()) {
    const std::vector<std::string_view> w = words(*line);
    if (w.empty()) continue;
    const std::uint32_t n = lines.number();
    if (w[0] == "v") {
      ++vertices;
      check_point(w, 1, "vertex " + std::to_string(vertices), n, faults);
    } else if (w[0] == "f") {
      ++faces;
      const std::string name = "face " + std::to_string(faces);
      if (w.size() < 4) {
        faults.short_face.report(
            name + " has " + plural(static_cast<std::int64_t>(w.size()) - 1, "corner", "corners") +
                "; a face needs at least 3",
            n);
      }
      for (std::size_t i = 1; i < w.size(); ++i) {
        const std::string_view index = w[i].substr(0, w[i].find('/'));
        const std::optional<std::int64_t> k = integer(index);
        if (!k) {
          faults.malformed.report(name + ": corner " + quoted(w[i]) + " is not a vertex number", n);
          break;
        }
        if (*k == 0) {
          faults.corner.report(name + " has a corner 0; OBJ numbers vertices from 1", n);
          break;
        }
        const std::int64_t resolved = *k > 0 ? *k : vertices + *k + 1;
        if (resolved < 1 || resolved > total) {
          faults.corner.report(name + " refers to vertex " + std::to_string(*k) +
                                   (*k < 0 ? " (" + std::to_string(resolved) + ")" : "") +
                                   "; the file has " + plural(total, "vertex", "vertices"),
                               n);
          break;
        }
      }
    }
  }
}

// Binary OFF after its `OFF BINARY` line (big-endian, 32-bit): the counts
// (vertices, faces, edges), each vertex as three floats, each face as a
// corner count, the corners, a colour count and that many floats.
void read_binary_off(std::string_view bytes, std::size_t at, std::uint32_t line, Faults& faults,
                     PolygonMesh& soup) {
  auto word = [&](std::size_t offset) {
    std::uint32_t x = 0;
    std::memcpy(&x, bytes.data() + offset, 4);
    return __builtin_bswap32(x);
  };
  if (bytes.size() < at + 12) {
    faults.size.report("the binary OFF file ends before its counts", line);
    return;
  }
  const std::uint32_t nv = word(at);
  const std::uint32_t nf = word(at + 4);
  at += 12;
  const std::uint64_t left = bytes.size() - at;
  if (std::uint64_t{nv} * 12 + std::uint64_t{nf} * 20 > left) {
    claims_too_much(faults,
                    plural(nv, "vertex", "vertices") + " and " + plural(nf, "face", "faces"), left,
                    line);
    return;
  }
  soup.positions.reserve(nv);
  for (std::uint32_t v = 0; v < nv; ++v, at += 12) {
    Vec3 p;
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t bits = word(at + 4 * static_cast<std::size_t>(i));
      float x = 0;
      std::memcpy(&x, &bits, 4);
      p[i] = x;
    }
    if (!p.allFinite()) {
      faults.coordinate.report("vertex " + std::to_string(v + 1) +
                               " has a coordinate that is not a finite number");
    }
    soup.positions.push_back(p);
  }
  soup.faces.reserve(nf);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::string name = "face " + std::to_string(f + 1);
    if (bytes.size() < at + 4) {
      ends_early(faults, f, plural(nf, "face", "faces"));
      return;
    }
    const std::uint32_t k = word(at);
    at += 4;
    if (std::uint64_t{k} * 4 + 4 > bytes.size() - at) {
      faults.size.report(name + " claims " + std::to_string(k) +
                         " corners, more than the file holds after it");
      return;
    }
    if (k < 3) {
      faults.short_face.report(name + " has " + plural(k, "corner", "corners") +
                               "; a face needs at least 3");
    }
    std::vector<int>& face = soup.faces.emplace_back();
    const std::size_t corners = at;
    at += 4 * std::size_t{k};
    for (std::uint32_t i = 0; i < k; ++i) {
      const auto v = static_cast<std::int32_t>(word(corners + 4 * std::size_t{i}));
      if (v < 0 || static_cast<std::uint32_t>(v) >= nv) {
        off_corner_missing(faults, name, v, nv);
        break;
      }
      face.push_back(v);
    }
    const std::uint32_t colours = word(at);
    at += 4;
    if (std::uint64_t{colours} * 4 > bytes.size() - at) {
      faults.size.report(name + " claims " + std::to_string(colours) +
                         " colour values, more than the file holds after it");
      return;
    }
    at += 4 * std::size_t{colours};
  }
}

// OFF: [ST][C][N][4][n]OFF, the counts (vertices, faces, edges), then one
// vertex per line and one face per line (`k i1 .. ik [colour]`, 0-based),
// `#` comments anywhere; or plain binary OFF. The soup goes to `soup`.
// Returns whether the file was read here (false only where a fault stopped
// the reading).
bool scan_off(std::string_view bytes, Faults& faults, PolygonMesh& soup) {
  Lines lines(bytes);
  std::vector<std::string_view> head;
  std::uint32_t head_line = 0;
  std::optional<std::string_view> line;
  // The keyword and the three counts, over as many lines as they take.
  while (head.size() < 4 && (line = lines.next())) {
    for (std::string_view w : words(*line)) {
      if (head.size() < 4) head.push_back(w);
      if (head.size() == 1) {
        if (w.size() < 3 || w.substr(w.size() - 3) != "OFF") {
          faults.malformed.report("the file does not start with OFF (" + quoted(w) + ")",
                                  lines.number());
          return false;
        }
        if (w.find('4') != std::string_view::npos || w.find('n') != std::string_view::npos) {
          faults.malformed.report(quoted(w) +
                                      " is OFF of more than three dimensions, not a surface in "
                                      "space; convert it to 3D OFF, OBJ, PLY or STL",
                                  lines.number());
          return false;
        }
      } else if (head.size() == 2 && w == "BINARY") {
        if (head[0] != "OFF") {
          faults.malformed.report("binary " + quoted(head[0]) +
                                      " (with colours, normals or texture coordinates) is not "
                                      "read; convert it to ASCII OFF, OBJ, PLY or STL",
                                  lines.number());
          return false;
        }
        read_binary_off(bytes, lines.offset(), lines.number(), faults, soup);
        return true;
      }
      head_line = lines.number();
    }
  }
  if (head.size() < 4) {
    faults.malformed.report("the header ends before its three counts (vertices, faces, edges)",
                            lines.number());
    return false;
  }
  std::array<std::int64_t, 3> counts{};
  for (int i = 0; i < 3; ++i) {
    const std::optional<std::int64_t> c = integer(head[static_cast<std::size_t>(i) + 1]);
    if (!c || *c < 0) {
      faults.malformed.report("the header's counts are not three whole numbers (" +
                                  quoted(head[static_cast<std::size_t>(i) + 1]) + ")",
                              head_line);
      return false;
    }
    counts[static_cast<std::size_t>(i)] = *c;
  }
  const std::int64_t nv = counts[0];
  const std::int64_t nf = counts[1];
  // The least an element can take: "0 0 0\n" and "3 0 1 2\n".
  const std::size_t left = bytes.size() - lines.offset();
  constexpr std::int64_t kMost = std::numeric_limits<std::int64_t>::max() / 16;
  if (nv > kMost || nf > kMost ||
      static_cast<std::uint64_t>(nv * 6 + nf * 8) > static_cast<std::uint64_t>(left)) {
    claims_too_much(faults,
                    plural(nv, "vertex", "vertices") + " and " + plural(nf, "face", "faces"), left,
                    head_line);
    return false;
  }
  soup.positions.reserve(static_cast<std::size_t>(nv));
  soup.faces.reserve(static_cast<std::size_t>(nf));
  std::int64_t vertices = 0;
  while (vertices < nv && (line = lines.next())) {
    const std::vector<std::string_view> w = words(*line);
    if (w.empty()) continue;
    ++vertices;
    soup.positions.push_back(
        check_point(w, 0, "vertex " + std::to_string(vertices), lines.number(), faults)
            .value_or(Vec3::Zero()));
  }
  if (vertices < nv) {
    ends_early(faults, vertices, plural(nv, "vertex", "vertices"), lines.number());
    return false;
  }
  std::int64_t faces = 0;
  while (faces < nf && (line = lines.next())) {
    const std::vector<std::string_view> w = words(*line);
    if (w.empty()) continue;
    ++faces;
    const std::uint32_t n = lines.number();
    const std::string name = "face " + std::to_string(faces);
    const std::optional<std::int64_t> k = integer(w[0]);
    if (!k || *k < 0 || static_cast<std::size_t>(*k) + 1 > w.size()) {
      faults.malformed.report(name + ": " + quoted(*line) +
                                  " is not a corner count followed by that many vertex numbers",
                              n);
      continue;
    }
    if (*k < 3) {
      faults.short_face.report(
          name + " has " + plural(*k, "corner", "corners") + "; a face needs at least 3", n);
    }
    std::vector<int>& face = soup.faces.emplace_back();
    for (std::int64_t i = 1; i <= *k; ++i) {
      const std::optional<std::int64_t> v = integer(w[static_cast<std::size_t>(i)]);
      if (!v) {
        faults.malformed.report(
            name + ": corner " + quoted(w[static_cast<std::size_t>(i)]) + " is not a vertex number",
            n);
        break;
      }
      if (*v < 0 || *v >= nv) {
        off_corner_missing(faults, name, *v, nv, n);
        break;
      }
      face.push_back(static_cast<int>(*v));
    }
  }
  if (faces < nf) ends_early(faults, faces, plural(nf, "face", "faces"), lines.number());
  return true;
}

// Bytes of a PLY scalar type, 0 for an unknown one.
std::size_t ply_type_size(std::string_view type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

// PLY: the header line by line (OpenMesh's reader loops for ever on a
// header line it does not know or a header without end_header), then the
// element counts against the bytes after it (each element at least its
// fixed-size properties, a face at least 3 corners; in ASCII at least two
// characters per value). The body is left to OpenMesh; check_mesh names
// bad corners there.
void scan_ply(std::string_view bytes, Faults& faults) {
  Lines lines(bytes);
  bool binary = false;
  bool format = false;
  struct Element {
    std::string_view name;
    std::int64_t count = 0;
    std::uint32_t line = 0;
    std::uint64_t least = 0;  // bytes per element, at least
  };
  std::vector<Element> elements;
  bool ended = false;
  auto bad = [&](const std::string& what) {
    faults.malformed.report("PLY header: " + what, lines.number());
  };
  while (auto line = lines.next()) {
    const std::vector<std::string_view> w = words(*line, false);
    if (lines.number() == 1) {
      if (w.size() != 1 || w[0] != "ply") {
        bad("the file does not start with a line `ply`");
        return;
      }
      continue;
    }
    if (w.empty()) continue;
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "end_header") {
      ended = true;
      break;
    }
    if (w[0] == "format") {
      if (w.size() != 3 || w[2] != "1.0" ||
          (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian")) {
        bad(quoted(*line) + " is not `format ascii|binary_little_endian|binary_big_endian 1.0`");
        return;
      }
      binary = w[1] != "ascii";
      format = true;
    } else if (w[0] == "element") {
      const std::optional<std::int64_t> c = w.size() == 3 ? integer(w[2]) : std::nullopt;
      if (!c || *c < 0) {
        bad(quoted(*line) + " is not `element NAME COUNT` with a whole number");
        return;
      }
      elements.push_back({w[1], *c, lines.number(), 0});
    } else if (w[0] == "property" && !elements.empty()) {
      Element& e = elements.back();
      if (w.size() == 5 && w[1] == "list" && ply_type_size(w[2]) > 0 && ply_type_size(w[3]) > 0) {
        const std::uint64_t corners = e.name == "face" ? 3 : 0;
        e.least += binary ? ply_type_size(w[2]) + corners * ply_type_size(w[3]) : 2 + 2 * corners;
      } else if (w.size() == 3 && ply_type_size(w[1]) > 0) {
        e.least += binary ? ply_type_size(w[1]) : 2;
      } else {
        bad(quoted(*line) +
            " is not `property TYPE NAME` or `property list TYPE TYPE NAME` "
            "with known types");
        return;
      }
    } else {
      bad(quoted(*line) +
          " is not a header line (format, element, property, comment, "
          "end_header)");
      return;
    }
  }
  if (!ended || !format) {
    faults.malformed.report(
        std::string("PLY header: ") + (ended ? "no `format` line" : "no `end_header` line"),
        ended ? 1 : lines.number());
    return;
  }
  const std::uint64_t left = bytes.size() - lines.offset();
  std::uint64_t need = 0;
  for (const Element& e : elements) {
    const std::uint64_t least = std::max<std::uint64_t>(1, e.least);
    if (static_cast<std::uint64_t>(e.count) > left / least || need + e.count * least > left) {
      claims_too_much(faults, std::to_string(e.count) + " " + std::string(e.name) + " elements",
                      left, e.line);
      return;
    }
    need += e.count * least;
  }
}

// STL: binary (80 bytes, a count, 50 bytes per triangle) or ASCII
// (`vertex x y z` lines).
void scan_stl(std::string_view bytes, Faults& faults) {
  const bool solid = bytes.substr(0, 5) == "solid";
  std::uint32_t count = 0;
  if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, 4);
  const bool binary_size = bytes.size() >= 84 && 84 + std::uint64_t{count} * 50 == bytes.size();
  if (solid && !binary_size) {
    Lines lines(bytes);
    std::int64_t vertices = 0;
    while (auto line = lines.next()) {
      const std::vector<std::string_view> w = words(*line);
      if (w.empty() || w[0] != "vertex") continue;
      ++vertices;
      check_point(w, 1, "vertex " + std::to_string(vertices) + " of the facets", lines.number(),
                  faults);
    }
    return;
  }
  if (bytes.size() < 84) {
    faults.size.report("a binary STL file has at least 84 bytes; this one has " +
                       std::to_string(bytes.size()));
    return;
  }
  if (84 + std::uint64_t{count} * 50 > bytes.size()) {
    faults.size.report("the header claims " + plural(count, "triangle", "triangles") + " (" +
                       std::to_string(84 + std::uint64_t{count} * 50) +
                       " bytes) but the file has " + std::to_string(bytes.size()) + " bytes");
    return;
  }
  for (std::uint32_t t = 0; t < count; ++t) {
    std::array<float, 9> corners{};
    std::memcpy(corners.data(), bytes.data() + 84 + std::size_t{t} * 50 + 12, sizeof(corners));
    if (!std::all_of(corners.begin(), corners.end(), [](float x) { return std::isfinite(x); })) {
      faults.coordinate.report("triangle " + std::to_string(t + 1) +
                               " has a coordinate that is not a finite number");
    }
  }
}

}  // namespace

ScanResult scan_mesh_bytes(std::string_view bytes, std::string_view ext, const std::string& source,
                           knitout::DiagnosticSink& sink) {
  const std::size_t errors_before = sink.error_count();
  PolygonMesh soup;
  bool read_here = false;
  {
    Faults faults(sink, source);
    if (ext == "obj") scan_obj(bytes, faults);
    if (ext == "off" && scan_off(bytes, faults, soup)) read_here = true;
    if (ext == "ply") scan_ply(bytes, faults);
    if (ext == "stl") scan_stl(bytes, faults);
  }
  ScanResult result;
  result.ok = sink.error_count() == errors_before;
  if (result.ok && read_here) result.soup = std::move(soup);
  return result;
}

}  // namespace planner
