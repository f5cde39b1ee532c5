// wearknit view: (re)writes a plan folder's page, DIR/index.html
// (planner/viewer/plan_page.hpp): the garment on its wearer in 3D with its
// seams, the stitch mesh, the pieces laid flat and their figures, one file
// that works offline. `plan` and `demo` write it at their end too.
#include <filesystem>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "planner/viewer/plan_page.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_view(const std::vector<std::string>& args, Context& context) {
  std::string dir;
  po::options_description options("options");
  options.add_options()("dir", po::value<std::string>(&dir)->required(),
                        "plan folder (after wearknit plan, or any of its stages)")(
      "quiet,q", "print nothing on success");
  po::positional_options_description positional;
  positional.add("dir", 1);
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("view"), options, positional, values, context)) {
    return *code;
  }
  if (!std::filesystem::is_directory(dir)) {
    context.err << dir << ": error: not a folder\n";
    return kExitUsage;
  }
  planner::viewer::PlanPageSummary summary;
  const std::string failure = planner::viewer::write_plan_page(dir, &summary);
  if (!failure.empty()) {
    context.err << "wearknit view: " << failure << '\n';
    return kExitUsage;
  }
  if (!values.count("quiet")) print_page_line(dir, summary, context);
  return kExitOk;
}

void print_page_line(const std::string& dir, const planner::viewer::PlanPageSummary& summary,
                     Context& context) {
  context.out << "open: " << (std::filesystem::path(dir) / "index.html").string() << "  ("
              << (summary.bytes + 512 * 1024) / (1024 * 1024) << " MB; " << summary.pieces
              << " piece" << (summary.pieces == 1 ? "" : "s") << ", " << summary.seams << " seam"
              << (summary.seams == 1 ? "" : "s") << (summary.wearer ? ", with the wearer" : "")
              << ")\n";
}

}  // namespace wearknit::cli
