// wearknit demo: the main job on a built-in input, needing no data file.
//
// It builds an egg-like ellipsoid in code as the wearer and a cover for it
// — the same shape about half a stitch height further out, the way the paper
// covers its objects (§8) — runs the whole plan on them (cut, wearability
// beside stitch mesh and schedule, assembly guide), checks the result
// independently (every piece's knitout through the needle-bed VM, its DAT
// present, every cut-arc labelled) and says what to open.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <tuple>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/plan_display.hpp"
#include "apps/wearknit/stage_options.hpp"
#include "knitout/output_file.hpp"
#include "knitout/parser.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/mesh/shapes.hpp"
#include "planner/viewer/plan_page.hpp"
#include "simulators/bed/validate.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;
namespace fs = std::filesystem;

int run_demo(const std::vector<std::string>& args, Context& context) {
  planner::PlanInputs inputs;
  std::string out_dir;
  std::uint64_t seed = 1;
  std::string pattern;
  po::options_description options("options");
  options.add_options()("output,o",
                        po::value<std::string>(&out_dir)->default_value("wearknit-demo"),
                        "folder to write into")(
      "seed", po::value<std::uint64_t>(&seed)->default_value(1), "seed of every stage")(
      "pattern", po::value<std::string>(&pattern)->default_value("plain"),
      "stitch pattern: plain or seed")("quiet,q", "no progress display");
  po::positional_options_description positional;
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("demo"), options, positional, values, context)) {
    return *code;
  }
  if (pattern != "plain" && pattern != "seed") {
    context.err << "wearknit demo: --pattern takes plain or seed, not '" << pattern << "'\n";
    return kExitUsage;
  }
  const fs::path dir(out_dir);
  std::error_code ec;
  fs::create_directories(dir / "input", ec);
  if (ec) {
    context.err << "wearknit demo: cannot create " << (dir / "input").string() << ": "
                << ec.message() << '\n';
    return kExitUsage;
  }
  // An egg-like ellipsoid 50 x 50 x 90 mm; the cover about 1.5 mm out from
  // it (half the default wale height, 2.9 mm). About 4,500 stitches.
  inputs.wearer = (dir / "input" / "wearer.obj").string();
  inputs.garment = (dir / "input" / "garment.obj").string();
  for (const auto& [path, shape, header] :
       {std::tuple{inputs.wearer, planner::quad_ellipsoid(25, 1.8, 6),
                   "wearknit demo: the wearer, an ellipsoid, in mm"},
        std::tuple{inputs.garment, planner::quad_ellipsoid(26.5, 1.75, 6),
                   "wearknit demo: the garment, the ellipsoid 1.5 mm further out, in mm"}}) {
    const planner::PolygonMesh& mesh = shape;
    const char* const title = header;
    const std::string failure = knitout::write_file_atomically(
        path, [&mesh, title](std::ostream& out) { planner::write_obj(out, mesh, title); });
    if (!failure.empty()) {
      context.err << "wearknit demo: " << failure << '\n';
      return kExitUsage;
    }
  }
  planner::PlanParams params;
  params.cut.cut.seed = seed;
  params.wearability.test.seed = seed;
  params.schedule.schedule.seed = seed;
  if (pattern == "seed") params.schedule.emit.pattern = planner::StitchPattern::Seed;
  PlanRunOptions run;
  run.quiet = values.count("quiet") != 0;
  // The page to open comes first: it is where the demo's results are shown.
  const std::string page_path = (dir / "index.html").string();
  context.out << "open: " << page_path << '\n';
  context.out << "wearknit demo: an ellipsoid and its cover, built in code (" << inputs.garment
              << ", " << inputs.wearer << ")\n";
  const int code = run_plan_and_report(inputs, params, out_dir, run, context);
  // The page shows whatever the plan wrote, also when a stage failed.
  planner::viewer::PlanPageSummary page;
  const std::string page_failure = planner::viewer::write_plan_page(dir, &page);
  if (!page_failure.empty()) context.err << "wearknit demo: " << page_failure << '\n';
  if (code != kExitOk || !page_failure.empty()) {
    context.err << "wearknit demo FAILED\n";
    return code != kExitOk ? code : kExitUsage;
  }

  // Independent checks of what the plan wrote.
  std::ifstream report_in(dir / "report.json"), cuts_in(dir / "cuts.json");
  const nlohmann::json report = nlohmann::json::parse(report_in, nullptr, false);
  const nlohmann::json cuts = nlohmann::json::parse(cuts_in, nullptr, false);
  std::vector<std::string> problems;
  std::size_t pieces = 0, labelled = 0, arcs = 0;
  if (report.is_discarded() || cuts.is_discarded())
    problems.push_back("report.json or cuts.json is not JSON");
  if (problems.empty()) {
    for (const auto& arc : cuts.value("arcs", nlohmann::json::array())) {
      ++arcs;
      const auto label = arc.value("label", nlohmann::json());
      labelled += label == "sew" || label == "lace";
    }
    if (labelled != arcs) problems.push_back("a cut-arc has no sew/lace label");
    for (const auto& piece : report["schedule"].value("pieces", nlohmann::json::array())) {
      ++pieces;
      const fs::path knitout_path = dir / piece.value("knitout", std::string());
      knitout::DiagnosticSink sink;
      const knitout::Program program = knitout::parse_file(knitout_path.string(), sink);
      bed::validate(program, bed::default_profile(), sink, knitout_path.string());
      if (sink.has_errors()) {
        problems.push_back(knitout_path.string() + ": the needle-bed VM finds errors");
        knitout::print_text(context.err, sink.diagnostics());
      }
      const fs::path dat = dir / piece.value("dat", std::string());
      if (!fs::is_regular_file(dat) || fs::file_size(dat) == 0)
        problems.push_back(dat.string() + ": missing");
    }
    if (pieces == 0) problems.push_back("no pieces");
    if (!fs::is_regular_file(dir / "assembly.svg")) problems.push_back("no assembly guide");
    if (page.seams == 0 || page.pieces == 0)
      problems.push_back(page_path + ": the page shows no seams or no pieces");
  }
  for (const std::string& p : problems) context.err << "wearknit demo: " << p << '\n';
  if (!problems.empty()) {
    context.err << "wearknit demo FAILED\n";
    return kExitInvalid;
  }
  context.out << "checked: " << pieces << " piece" << (pieces == 1 ? "" : "s")
              << " valid on the needle-bed VM (" << bed::default_profile().name
              << "), each with its DAT; " << arcs
              << " cut-arcs, each labelled sew or lace; the assembly guide; the page ("
              << (page.bytes + 1023) / 1024 << " KB)\n"
              << "open:\n";
  const std::pair<const char*, const char*> to_open[] = {
      {"index.html",
       "everything below in a browser: the garment in 3D with its seams, the pieces, the figures"},
      {"assembly.pdf", "how to put the pieces together: seams numbered, sew and lace"},
      {"assembly-3d.png", "the garment on its wearer, seams coloured sew and lace"},
      {"cuts-3d.png", "where the cover is cut"},
      {"wearability.png", "which cuts are sewn (green) and laced (red)"},
      {"stitch-mesh.png", "the stitch mesh"},
      {"pieces/piece-1.svg", "the first piece on the needle bed (also pieces/*.k, *.dat)"},
      {"report.json", "every stage's figures and timings"}};
  for (const auto& [name, what] : to_open) {
    if (fs::exists(dir / name))
      context.out << "  " << (dir / name).string() << "  " << what << '\n';
  }
  return kExitOk;
}

}  // namespace wearknit::cli
