// wearknit assembly: (re)writes the assembly guide of a finished plan folder
// (planner/assembly/assembly.hpp): assembly.svg, assembly.pdf and assembly-3d.png.
#include <cmath>
#include <filesystem>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/stage_options.hpp"
#include "planner/pipeline.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_assembly(const std::vector<std::string>& args, Context& context) {
  std::string dir;
  std::string wearer;
  std::string page_png;
  WearerUnitOptions wearer_units;
  po::options_description options("options");
  options.add_options()("dir", po::value<std::string>(&dir)->required(),
                        "plan folder after wearknit schedule (and wearability)")(
      "wearer", po::value<std::string>(&wearer),
      "the object the garment covers (OBJ, OFF, PLY or STL), drawn in assembly-3d.png")(
      "page-png", po::value<std::string>(&page_png),
      "N:OUT.png: also draw page N of the guide as a PNG picture (a preview)")(
      "quiet,q", "print nothing on success");
  add_wearer_unit_options(options, wearer_units);
  po::positional_options_description positional;
  positional.add("dir", 1);
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("assembly"), options, positional, values, context)) {
    return *code;
  }
  if (!std::filesystem::is_directory(dir)) {
    context.err << dir << ": error: [A001] not a folder\n";
    return kExitUsage;
  }
  std::string problem;
  const double wearer_factor = wearer_mm_per_unit(values, wearer_units, dir, problem);
  if (!problem.empty()) {
    context.err << "wearknit assembly: " << problem << '\n';
    return kExitUsage;
  }
  planner::AssemblySummary summary;
  const std::string failure = planner::write_assembly_guide(dir, wearer, &summary, wearer_factor);
  if (!failure.empty()) {
    context.err << failure << '\n';
    // A missing file is a usage problem; content that does not hold together is invalid input.
    return failure.find("[A001]") != std::string::npos ||
                   failure.find("[A006]") != std::string::npos
               ? kExitUsage
               : kExitInvalid;
  }
  std::string written = planner::write_assembly_record(dir, summary);
  if (written.empty()) written = planner::write_folder_summary(dir);
  if (!written.empty()) {
    context.err << "wearknit assembly: " << written << '\n';
    return kExitUsage;
  }
  if (!page_png.empty()) {
    const auto colon = page_png.find(':');
    int page = 0;
    try {
      page = colon == std::string::npos ? 0 : std::stoi(page_png.substr(0, colon));
    } catch (const std::exception&) {
      page = 0;
    }
    if (page < 1 || colon + 1 >= page_png.size()) {
      context.err << "wearknit assembly: --page-png takes N:OUT.png with a page number N >= 1\n";
      return kExitUsage;
    }
    const std::string png_failure =
        planner::write_assembly_page_png(dir, page, page_png.substr(colon + 1));
    if (!png_failure.empty()) {
      context.err << png_failure << '\n';
      return kExitUsage;
    }
  }
  if (!values.count("quiet")) {
    const std::filesystem::path base(dir);
    context.out << (base / "assembly.pdf").string() << ": " << summary.pieces << " piece"
                << (summary.pieces == 1 ? "" : "s") << ", " << summary.seams << " seam"
                << (summary.seams == 1 ? "" : "s") << " (" << summary.sewn << " to sew, "
                << std::lround(summary.sewn_mm) << " mm; " << summary.laced << " to lace, "
                << std::lround(summary.laced_mm) << " mm) from " << summary.arcs << " cut-arc"
                << (summary.arcs == 1 ? "" : "s") << ", " << summary.pdf_pages << " page"
                << (summary.pdf_pages == 1 ? "" : "s") << "; also "
                << (base / "assembly.svg").string() << " and "
                << (base / "assembly-3d.png").string() << '\n';
  }
  return kExitOk;
}

}  // namespace wearknit::cli
