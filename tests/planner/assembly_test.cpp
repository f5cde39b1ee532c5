// The assembly guide (planner/assembly/assembly.hpp, `wearknit assembly`) on plan
// folders made here by the real stages: cut, wearability, stitch-mesh,
// schedule.
#include "planner/assembly/assembly.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_support.hpp"

namespace wearknit::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kScale = 25;  // 3torus-quad is 3 units across: a 75 mm cover

// cut (and wearability when `wearer` is given), stitch-mesh, schedule.
fs::path make_plan(const fs::path& mesh, const std::string& name, const fs::path* wearer) {
  const fs::path dir = make_temp_dir(name);
  auto step = [&](const std::string& args) {
    const auto r = run_wearknit(args);
    EXPECT_EQ(r.exit_code, 0) << args << '\n' << r.err;
    return r.exit_code == 0;
  };
  const std::string d = "'" + dir.string() + "'";
  if (!step("cut '" + mesh.string() + "' --scale " + std::to_string(kScale) +
            " -q --no-pictures -o " + d))
    return {};
  if (wearer) {
    // A short budget: the stage labels every arc, sew when the garment still
    // comes off with the arc closed, and every arc lace (exit 1, W020) when
    // even the open garment does not come off within the budget.
    const auto r = run_wearknit("wearability " + d + " --wearer '" + wearer->string() +
                                "' --trials 1 --max-steps 600 --resolution 24 --seed 2 "
                                "--threads 2 -q");
    const bool labelled =
        r.exit_code == 0 || (r.exit_code == 1 && r.err.find("[W020]") != std::string::npos);
    EXPECT_TRUE(labelled) << r.err;
    if (!labelled) return {};
  }
  if (!step("stitch-mesh " + d + " -q --no-picture")) return {};
  if (!step("schedule " + d + " --trials 20 -q")) return {};
  return dir;
}

// Every <tag> closed by its </tag> in order (self-closing ones aside): the
// SVG is well-formed as far as elements go. (Scanned by hand: std::regex
// recurses per character and overflows the stack on long path data.)
bool tags_balance(const std::string& svg, std::string* why) {
  std::vector<std::string> open;
  for (std::size_t at = svg.find('<'); at != std::string::npos; at = svg.find('<', at + 1)) {
    const std::size_t end = svg.find('>', at);
    if (end == std::string::npos) {
      *why = "unterminated tag";
      return false;
    }
    const std::string tag = svg.substr(at + 1, end - at - 1);
    if (tag.empty() || tag[0] == '?' || tag[0] == '!') continue;
    const bool closing = tag[0] == '/';
    const std::size_t name_end = tag.find_first_of(" \t\n/", closing ? 1 : 0);
    const std::string name =
        tag.substr(closing ? 1 : 0, name_end == std::string::npos ? std::string::npos
                                                                  : name_end - (closing ? 1 : 0));
    if (closing) {
      if (open.empty() || open.back() != name) {
        *why = "unexpected </" + name + ">";
        return false;
      }
      open.pop_back();
    } else if (tag.back() != '/') {
      open.push_back(name);
    }
  }
  if (!open.empty()) *why = "<" + open.back() + "> not closed";
  return open.empty();
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Page objects of a PDF: `/Type /Page` not followed by `s` (that is /Pages).
int pdf_pages(const std::string& pdf) {
  int n = 0;
  for (std::size_t at = pdf.find("/Type"); at != std::string::npos;
       at = pdf.find("/Type", at + 1)) {
    std::size_t k = at + 5;
    while (k < pdf.size() && (pdf[k] == ' ' || pdf[k] == '\n' || pdf[k] == '\r')) ++k;
    if (pdf.compare(k, 5, "/Page") == 0 && (k + 5 >= pdf.size() || pdf[k + 5] != 's')) ++n;
  }
  return n;
}

// The seam names on the pieces: <text class="seam-label sew|lace" ...>N</text>
// or, for part P of seam N, N.P.
std::vector<std::pair<std::string, std::string>> seam_labels(const std::string& svg) {
  std::vector<std::pair<std::string, std::string>> found;
  const std::string open = "<text class=\"seam-label ";
  for (std::size_t at = svg.find(open); at != std::string::npos; at = svg.find(open, at + 1)) {
    const std::size_t style_end = svg.find('"', at + open.size());
    const std::size_t text_start = svg.find('>', at) + 1;
    const std::size_t text_end = svg.find("</text>", text_start);
    found.emplace_back(svg.substr(at + open.size(), style_end - at - open.size()),
                       svg.substr(text_start, text_end - text_start));
  }
  return found;
}

// The lines of the closing order: <text class="order" ...>LINE</text>.
std::vector<std::string> order_lines(const std::string& svg) {
  std::vector<std::string> lines;
  const std::string open = "<text class=\"order\"";
  for (std::size_t at = svg.find(open); at != std::string::npos; at = svg.find(open, at + 1)) {
    const std::size_t text_start = svg.find('>', at) + 1;
    lines.push_back(svg.substr(text_start, svg.find("</text>", text_start) - text_start));
  }
  return lines;
}

// The cut-arcs a line of the closing order names ("cut-arc 3" or
// "cut-arcs 3+5+7"), in order.
std::vector<int> arcs_of_line(const std::string& line) {
  std::vector<int> arcs;
  std::size_t at = line.find("cut-arc");
  if (at == std::string::npos) return arcs;
  at = line.find(' ', at) + 1;
  while (at < line.size() && std::isdigit(static_cast<unsigned char>(line[at]))) {
    std::size_t end = at;
    while (end < line.size() && std::isdigit(static_cast<unsigned char>(line[end]))) ++end;
    arcs.push_back(std::stoi(line.substr(at, end - at)));
    at = end < line.size() && line[end] == '+' ? end + 1 : line.size();
  }
  return arcs;
}

// The end vertices of every arc of cuts.json.
std::vector<std::array<int, 2>> arc_ends(const json& cuts) {
  std::vector<std::array<int, 2>> ends;
  for (const json& arc : cuts.at("arcs")) {
    const json& edges = arc.at("edges");
    ends.push_back({edges.front().at(0).get<int>(), edges.back().at(1).get<int>()});
  }
  return ends;
}

// Where two arcs meet end to end at a vertex no other arc ends at.
struct Joints {
  int same_label = 0;
  int two_labels = 0;
  std::array<int, 2> first_same{{-1, -1}};  // the arcs of the first same-label joint
};

// Checks the chaining of cuts.json's arcs against the closing order `lines`
// of the guide: every arc in exactly one seam; two arcs of one label that
// meet end to end where no other arc ends are one seam, arcs of two labels
// never are (cuts.json's `seam` and the seam number of the guide's line
// naming them); fewer seams than arcs where there is such a joint;
// `seams` consistent with the arcs.
Joints expect_chained_by_label(const json& cuts, const std::vector<std::string>& lines) {
  std::map<int, std::set<int>> seam_lines_of_arc;  // arc -> the seam numbers naming it
  for (const std::string& line : lines) {
    for (const int arc : arcs_of_line(line)) {
      // "cut-arcs N+M (...): nothing to join" stands for a seam of its own.
      seam_lines_of_arc[arc].insert(std::isdigit(static_cast<unsigned char>(line[0]))
                                        ? std::stoi(line)
                                        : -arcs_of_line(line).front() - 1);
    }
  }
  const json& arcs = cuts.at("arcs");
  for (const json& arc : arcs) {
    const int id = arc.at("id").get<int>();
    EXPECT_EQ(seam_lines_of_arc[id].size(), 1u) << "cut-arc " << id << " is not in one seam";
  }
  const auto ends = arc_ends(cuts);
  std::map<int, std::vector<int>> arcs_at;  // vertex -> arcs ending there (twice for a loop)
  for (std::size_t a = 0; a < ends.size(); ++a) {
    for (const int v : ends[a]) arcs_at[v].push_back(static_cast<int>(a));
  }
  Joints joints;
  for (const auto& [vertex, at_vertex] : arcs_at) {
    if (at_vertex.size() != 2 || at_vertex[0] == at_vertex[1]) continue;
    const json& a = arcs[static_cast<std::size_t>(at_vertex[0])];
    const json& b = arcs[static_cast<std::size_t>(at_vertex[1])];
    const bool same_label = a.at("label") == b.at("label");
    EXPECT_EQ(a.at("seam") == b.at("seam"), same_label) << "vertex " << vertex;
    EXPECT_EQ(seam_lines_of_arc[at_vertex[0]] == seam_lines_of_arc[at_vertex[1]], same_label)
        << "arcs " << at_vertex[0] << " and " << at_vertex[1] << " meet at vertex " << vertex;
    if (same_label) {
      if (joints.same_label++ == 0) joints.first_same = {at_vertex[0], at_vertex[1]};
    } else {
      ++joints.two_labels;
    }
  }
  const json& chains = cuts.at("seams");
  if (joints.same_label > 0) {
    EXPECT_LT(chains.size(), arcs.size());
  }
  std::size_t chained = 0;
  for (std::size_t c = 0; c < chains.size(); ++c) {
    double length = 0;
    for (const json& a : chains[c].at("arcs")) {
      EXPECT_EQ(arcs.at(a.get<std::size_t>()).at("seam"), c);
      EXPECT_EQ(arcs.at(a.get<std::size_t>()).at("label"), chains[c].at("label"));
      length += arcs.at(a.get<std::size_t>()).at("length_mm").get<double>();
      ++chained;
    }
    EXPECT_NEAR(chains[c].at("length_mm").get<double>(), length, 0.01);
  }
  EXPECT_EQ(chained, arcs.size());
  return joints;
}

TEST(AssemblyTest, GuideOfARealPlanFolderShowsEveryPieceAndSeam) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const fs::path mesh = shared / "meshes" / "3torus-quad.obj";
  // The garment worn over itself: the wearability verb and the guide read
  // the wearer at the scale the cut recorded for the garment.
  const fs::path wearer = mesh;
  const fs::path dir = make_plan(mesh, "assembly-plan", &wearer);
  ASSERT_FALSE(dir.empty());

  const auto r = run_wearknit("assembly '" + dir.string() + "' --wearer '" + wearer.string() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json cuts = json::parse(read_file(dir / "cuts.json"));
  const json report = json::parse(read_file(dir / "report.json"));
  const std::size_t pieces = report.at("schedule").at("pieces").size();

  // Both files, and the same number of pages in each.
  const std::string pdf = read_file(dir / "assembly.pdf");
  ASSERT_EQ(pdf.rfind("%PDF-", 0), 0u);
  EXPECT_NE(pdf.find("%%EOF"), std::string::npos);
  const std::string svg = read_file(dir / "assembly.svg");
  ASSERT_EQ(svg.rfind("<?xml", 0), 0u);
  std::string why;
  EXPECT_TRUE(tags_balance(svg, &why)) << why;
  const int pages = count(svg, "<g class=\"page\"");
  EXPECT_GE(pages, 1);  // the closing order and the pieces share pages where they fit
  EXPECT_EQ(pdf_pages(pdf), pages);
  EXPECT_NE(r.out.find(", " + std::to_string(pages) + (pages == 1 ? " page;" : " pages;")),
            std::string::npos)
      << r.out;
  const std::string png = read_file(dir / "assembly-3d.png");
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));

  // One caption per piece of report.json.
  EXPECT_EQ(count(svg, "class=\"piece-caption\""), static_cast<int>(pieces));

  // Every seam (or part) name exactly twice on the pieces; numbers 1..n,
  // sew numbered before lace; one line per name in the closing order.
  std::map<std::string, std::pair<std::string, int>> seen;
  std::set<int> numbers;
  for (const auto& [style, name] : seam_labels(svg)) {
    auto& entry = seen[name];
    if (entry.second > 0) {
      EXPECT_EQ(entry.first, style) << "seam " << name;
    }
    entry.first = style;
    ++entry.second;
    numbers.insert(std::stoi(name));
  }
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(*numbers.begin(), 1);
  EXPECT_EQ(*numbers.rbegin(), static_cast<int>(numbers.size()));
  int last_sew = 0;
  int first_lace = static_cast<int>(numbers.size()) + 1;
  const std::vector<std::string> lines = order_lines(svg);
  for (const auto& [name, entry] : seen) {
    EXPECT_EQ(entry.second, 2) << "seam " << name << " is labelled " << entry.second << " times";
    if (entry.first == "sew") last_sew = std::max(last_sew, std::stoi(name));
    if (entry.first == "lace") first_lace = std::min(first_lace, std::stoi(name));
    const std::string head = name + "  " + entry.first + "  piece ";
    EXPECT_EQ(std::count_if(lines.begin(), lines.end(),
                            [&](const std::string& l) { return l.rfind(head, 0) == 0; }),
              1)
        << "seam " << name << " is not once in the closing order";
  }
  EXPECT_LT(last_sew, first_lace);
  // Both ends of both stretches of every seam or part are marked (and the
  // two ends drawn in the legend).
  EXPECT_EQ(count(svg, "class=\"seam-end\""), 2 + 4 * static_cast<int>(seen.size()));

  // Stitch sides along each stretch, and how to ease them when they differ.
  for (const std::string& line : lines) {
    const std::size_t at = line.find(" stitch sides");
    if (at == std::string::npos) continue;
    const std::size_t comma = line.rfind(", ", at);
    int a = 0, b = 0;
    ASSERT_EQ(std::sscanf(line.c_str() + comma + 2, "%d / %d", &a, &b), 2) << line;
    EXPECT_GT(a, 0) << line;
    EXPECT_GT(b, 0) << line;
    EXPECT_EQ(line.find(": ease evenly") != std::string::npos, a != b) << line;
  }

  // Every arc of cuts.json is listed once; the arcs are chained into seams.
  const Joints joints = expect_chained_by_label(cuts, lines);
  EXPECT_GT(joints.same_label, 0);  // a cut whose arcs chain: fewer seams than arcs
  std::set<std::string> labels;
  for (const json& arc : cuts.at("arcs")) labels.insert(arc.at("label").get<std::string>());
  for (const std::string& l : labels) {
    EXPECT_GT(count(svg, "class=\"seam-" + l + "\""), 0) << l;
    EXPECT_GT(count(svg, "class=\"seam-label " + l + "\""), 0) << l;
  }
  for (std::size_t c = 0; c < cuts.value("schedule_cuts", json::array()).size(); ++c)
    EXPECT_NE(svg.find("scheduling cut " + std::to_string(c + 1) + " "), std::string::npos);
  EXPECT_EQ(count(svg, "class=\"legend-sew\""), 1);
  EXPECT_EQ(count(svg, "class=\"legend-lace\""), 1);

  // The guide reads the stage files, not the folder's summaries: without
  // report.json and cuts.json it draws the same pages.
  fs::remove(dir / "report.json");
  fs::remove(dir / "cuts.json");
  const auto again = run_wearknit("assembly '" + dir.string() + "' -q");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(read_file(dir / "assembly.svg"), svg);

  // The library call gives the same figures, without a wearer.
  planner::AssemblySummary summary;
  EXPECT_EQ(planner::write_assembly_guide(dir, "", &summary), "");
  EXPECT_EQ(summary.pieces, static_cast<int>(pieces));
  EXPECT_EQ(summary.seams, static_cast<int>(numbers.size()));
  EXPECT_EQ(summary.parts, static_cast<int>(seen.size()));
  EXPECT_EQ(summary.sewn, last_sew);
  EXPECT_EQ(summary.laced, summary.seams - last_sew);
  EXPECT_GT(summary.sewn_mm + summary.laced_mm, 0);
  // No more pages than pieces: the closing order and the pieces share pages.
  EXPECT_LE(summary.pdf_pages, std::max(summary.pieces, 1));
  // assembly.json (and so report.json's `assembly`) carries the same figures.
  const json guide = json::parse(read_file(dir / "assembly.json")).at("summary");
  EXPECT_EQ(guide.at("seams"), summary.seams);
  EXPECT_NEAR(guide.at("sewn_mm").get<double>(), summary.sewn_mm, 0.05);
  EXPECT_NEAR(guide.at("laced_mm").get<double>(), summary.laced_mm, 0.05);

  // Two arcs that made one seam, given two labels, make two seams.
  const fs::path wear = dir / "wearability.json";
  json relabelled = json::parse(read_file(wear));
  json& arc = relabelled.at("arcs").at(static_cast<std::size_t>(joints.first_same[0]));
  arc["label"] = arc.at("label") == "sew" ? "lace" : "sew";
  write_file(wear, relabelled.dump());
  const auto split = run_wearknit("assembly '" + dir.string() + "' -q");
  ASSERT_EQ(split.exit_code, 0) << split.err;
  const json split_cuts = json::parse(read_file(dir / "cuts.json"));
  const auto& split_arcs = split_cuts.at("arcs");
  EXPECT_NE(split_arcs.at(static_cast<std::size_t>(joints.first_same[0])).at("seam"),
            split_arcs.at(static_cast<std::size_t>(joints.first_same[1])).at("seam"));
  const Joints after =
      expect_chained_by_label(split_cuts, order_lines(read_file(dir / "assembly.svg")));
  EXPECT_EQ(after.two_labels, joints.two_labels + 1);
  EXPECT_EQ(split_cuts.at("seams").size(), cuts.at("seams").size() + 1);
  EXPECT_EQ(summary.arcs, static_cast<int>(cuts.at("arcs").size()));
  EXPECT_EQ(summary.pdf_pages, pages);
  fs::remove_all(dir);
}

// The files of the guide and anything else the guide could leave behind.
std::vector<std::string> guide_files(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.find("assembly") != std::string::npos || name.find(".tmp") != std::string::npos)
      found.push_back(name);
  }
  return found;
}

TEST(AssemblyTest, MissingOrCorruptFilesGiveAClearErrorAndWriteNothing) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const fs::path dir = make_plan(shared / "meshes" / "3torus-quad.obj", "assembly-bad", nullptr);
  ASSERT_FALSE(dir.empty());
  const std::string d = "'" + dir.string() + "'";

  // Without wearability the arcs carry no label: the guide says so and treats them as sewn.
  auto r = run_wearknit("assembly " + d + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_NE(read_file(dir / "assembly.svg").find("(no wearability label)"), std::string::npos);
  for (const char* name : {"assembly.svg", "assembly.pdf", "assembly-3d.png", "assembly.json"})
    fs::remove(dir / name);

  // A stage's file missing: the verb that makes it.
  const fs::path schedule = dir / "schedule.json";
  const std::string schedule_text = read_file(schedule);
  fs::remove(schedule);
  r = run_wearknit("assembly " + d);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, schedule.string() + ": error: [A001] missing (run wearknit schedule first)\n");
  EXPECT_TRUE(guide_files(dir).empty());
  write_file(schedule, schedule_text);

  // A stage's file that its reader refuses: the reader's diagnostic.
  const fs::path cut = dir / "cut.json";
  const std::string cut_text = read_file(cut);
  write_file(cut, cut_text.substr(0, cut_text.size() / 2));
  r = run_wearknit("assembly " + d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(
      r.err.rfind(cut.string() + ": error: [A002] cannot be read (run wearknit cut again): ", 0),
      0u)
      << r.err;
  EXPECT_NE(r.err.find("[P021]"), std::string::npos) << r.err;
  EXPECT_TRUE(guide_files(dir).empty());
  write_file(cut, cut_text);

  // Pieces made from another stitch mesh.
  json other = json::parse(schedule_text);
  other["stitch_mesh_id"] = "0123456789abcdef";
  write_file(schedule, other.dump());
  r = run_wearknit("assembly " + d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, schedule.string() +
                       ": error: [A004] the pieces belong to another stitch mesh (run wearknit "
                       "schedule again)\n");
  EXPECT_TRUE(guide_files(dir).empty());
  write_file(schedule, schedule_text);

  // A piece layout written by the scheduler that cannot be read.
  const fs::path layout = dir / "pieces" / "piece-1.layout.json";
  const std::string layout_text = read_file(layout);
  write_file(layout, "[1, 2");
  r = run_wearknit("assembly " + d);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(
      r.err.rfind(
          schedule.string() + ": error: [A002] cannot be read (run wearknit schedule again): ", 0),
      0u)
      << r.err;
  EXPECT_NE(r.err.find(layout.string()), std::string::npos) << r.err;
  EXPECT_TRUE(guide_files(dir).empty());

  // Put back, it works again.
  write_file(layout, layout_text);
  r = run_wearknit("assembly " + d + " -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(guide_files(dir).size(), 4u);  // the guide's three files and assembly.json

  // A page as a picture, and its usage errors.
  const fs::path page = dir / "page-1.png";
  r = run_wearknit("assembly " + d + " -q --page-png '1:" + page.string() + "'");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_file(page).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  r = run_wearknit("assembly " + d + " -q --page-png 0:x.png");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "wearknit assembly: --page-png takes N:OUT.png with a page number N >= 1\n");
  r = run_wearknit("assembly " + d + " -q --page-png '99:" + page.string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(page.string() + ": error: [A006] the guide has pages 1 to "),
            std::string::npos)
      << r.err;

  r = run_wearknit("assembly '" + (dir / "nowhere").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, (dir / "nowhere").string() + ": error: [A001] not a folder\n");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wearknit::test
