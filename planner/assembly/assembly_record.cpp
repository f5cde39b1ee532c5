// assembly.json: the figures of the assembly guide (planner/pipeline.hpp).
#include <cmath>
#include <filesystem>

#include "planner/common/json_file.hpp"
#include "planner/pipeline.hpp"

namespace planner {

std::string write_assembly_record(const std::string& dir, const AssemblySummary& summary) {
  return write_json_file((std::filesystem::path(dir) / "assembly.json").string(),
                         {{"format", "wearknit-assembly 1"},
                          {"summary",
                           {{"pieces", summary.pieces},
                            {"seams", summary.seams},
                            {"parts", summary.parts},
                            {"sewn", summary.sewn},
                            {"laced", summary.laced},
                            {"sewn_mm", std::round(summary.sewn_mm * 10) / 10},
                            {"laced_mm", std::round(summary.laced_mm * 10) / 10},
                            {"arcs", summary.arcs},
                            {"pdf_pages", summary.pdf_pages}}}});
}

}  // namespace planner
