// The knit graph and bed view observers.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "knitout/parser.hpp"
#include "simulators/bed/bed_view.hpp"
#include "simulators/bed/knit_graph.hpp"
#include "simulators/bed/machine.hpp"
#include "tests/test_support.hpp"

namespace bed {
namespace {

constexpr const char* kProgram =
    ";!knitout-2\n;;Carriers: 1 2 3\n"
    "in 3\n"             // 3
    "tuck + f1 3\n"      // 4: loop 0
    "tuck + f2 3\n"      // 5: loop 1
    "knit - f2 3\n"      // 6: loop 2 through 1
    "knit - f1 3\n"      // 7: loop 3 through 0
    "split + f1 b1 3\n"  // 8: loop 4 through 3; 3 moves to b1
    "out 3\n"            // 9
    "drop b1\n";         // 10

TEST(KnitGraphTest, RecordsLoopsParentsAndYarnOrder) {
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(kProgram, "t.k", sink);
  KnitGraph graph;
  MachineOptions options;
  options.observer = &graph;
  Machine machine(default_profile(), sink, "t.k", program.carriers, 3, options);
  for (const auto& instruction : program.instructions) machine.step(instruction);
  machine.finish(10);
  ASSERT_EQ(graph.loops().size(), 5u);
  auto parents = [&](LoopId id) {
    const auto& loop = graph.loops()[id];
    return std::vector<LoopId>(graph.parents().begin() + loop.parents_begin,
                               graph.parents().begin() + loop.parents_begin + loop.parents_count);
  };
  EXPECT_EQ(parents(0), std::vector<LoopId>{});
  EXPECT_EQ(parents(2), std::vector<LoopId>{1});
  EXPECT_EQ(parents(3), std::vector<LoopId>{0});
  EXPECT_EQ(parents(4), std::vector<LoopId>{3});
  EXPECT_EQ(graph.loops()[4].kind, LoopKind::Split);
  EXPECT_EQ(graph.loops()[3].dropped_line, 10u);  // moved to b1 by the split, dropped there
  EXPECT_EQ(graph.loops()[4].dropped_line, 0u);   // still on f1
  std::ostringstream json;
  graph.write_json(json, machine);
  const std::string text = json.str();
  EXPECT_NE(text.find("\"carrier_sets\": [[\"3\"]],\n  \"yarns\": [\n    {\"carrier\": \"3\", "
                      "\"loops\": [0, 1, 2, 3, 4]}\n  ]"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("{\"id\": 4, \"kind\": \"split\", \"needle\": \"f1\", \"line\": 8, "
                      "\"carriers\": 0, \"parents\": [3], \"dropped_line\": 0}"),
            std::string::npos)
      << text;
}

TEST(BedViewTest, WritesPngAndSvg) {
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(kProgram, "t.k", sink);
  BedView view;
  MachineOptions options;
  options.observer = &view;
  Machine machine(default_profile(), sink, "t.k", program.carriers, 3, options);
  for (const auto& instruction : program.instructions) machine.step(instruction);
  machine.finish(10);
  EXPECT_GE(view.samples(), 3u);
  const auto dir = wearknit::test::make_temp_dir("bed-view");
  EXPECT_EQ(view.write((dir / "v.png").string(), machine, "t.k"), "");
  EXPECT_EQ(view.write((dir / "v.svg").string(), machine, "t.k"), "");
  const std::string png = wearknit::test::read_file(dir / "v.png");
  const std::string svg = wearknit::test::read_file(dir / "v.svg");
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  // A folder that does not exist: an error, and no file.
  EXPECT_NE(view.write((dir / "missing/v.png").string(), machine, "t.k"), "");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace bed

namespace bed {
namespace {

TEST(KnitGraphTest, PlatedLoopsBelongToEveryCarriersYarn) {
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(
      ";!knitout-2\n;;Carriers: 3 4\nin 3 4\ntuck + f1 3 4\nknit - f1 3 4\n", "t.k", sink);
  KnitGraph graph;
  MachineOptions options;
  options.observer = &graph;
  Machine machine(default_profile(), sink, "t.k", program.carriers, 2, options);
  for (const auto& instruction : program.instructions) machine.step(instruction);
  std::ostringstream json;
  graph.write_json(json, machine);
  EXPECT_NE(json.str().find("\"carrier_sets\": [[\"3\", \"4\"]],\n  \"yarns\": [\n"
                            "    {\"carrier\": \"3\", \"loops\": [0, 1]},\n"
                            "    {\"carrier\": \"4\", \"loops\": [0, 1]}\n  ]"),
            std::string::npos)
      << json.str();
}

}  // namespace
}  // namespace bed

namespace bed {
namespace {

std::uint32_t png_height(const std::string& png) {
  // IHDR: width at bytes 16-19, height at 20-23, big-endian.
  std::uint32_t h = 0;
  for (int i = 20; i < 24; ++i) h = (h << 8) | static_cast<unsigned char>(png[i]);
  return h;
}

TEST(BedViewTest, MergesSweepsOfLongProgramsIntoABoundedPicture) {
  std::string text = ";!knitout-2\n;;Carriers: 3\nin 3\ntuck + f0 3\ntuck + f1 3\n";
  for (int row = 0; row < 3000; ++row) {
    text += row % 2 == 0 ? "knit - f1 3\nknit - f0 3\n" : "knit + f0 3\nknit + f1 3\n";
  }
  text += "out 3\n";
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(text, "t.k", sink);
  BedView view;
  MachineOptions options;
  options.observer = &view;
  Machine machine(default_profile(), sink, "t.k", program.carriers, 1, options);
  for (const auto& instruction : program.instructions) machine.step(instruction);
  machine.finish(0);
  EXPECT_EQ(view.samples(), 3001u);
  const auto dir = wearknit::test::make_temp_dir("bed-view");
  ASSERT_EQ(view.write((dir / "v.png").string(), machine, "t.k"), "");
  const std::string png = wearknit::test::read_file(dir / "v.png");
  // 3001 sweeps, two per pixel row: 1501 rows of 1 px plus margins.
  EXPECT_EQ(png_height(png), 56u + 1501u + 48u);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace bed

namespace bed {
namespace {

TEST(BedViewTest, DrawsAbsurdlyWideProgramsWithinBounds) {
  // On the unlimited generic profile needles may be far apart; the picture
  // keeps to kMaxNeedles needles instead of allocating billions.
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(
      ";!knitout-2\n;;Carriers: 3\nin 3\ntuck + f-200000 3\ntuck + f200000 3\n"
      "knit - f200000 3\nknit - f-200000 3\nout 3\n",
      "t.k", sink);
  BedView view;
  MachineOptions options;
  options.observer = &view;
  Machine machine(*find_profile("generic"), sink, "t.k", program.carriers, 1, options);
  for (const auto& instruction : program.instructions) machine.step(instruction);
  machine.finish(0);
  EXPECT_EQ(machine.stats().bed_span(), 400001);
  const auto dir = wearknit::test::make_temp_dir("bed-view");
  EXPECT_EQ(view.write((dir / "v.png").string(), machine, "t.k"), "");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace bed
