// assembly.json: the figures of the assembly guide (planner/pipeline.hpp).
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
                            {"sewn", summary.sewn},
                            {"laced", summary.laced},
                            {"arcs", summary.arcs},
                            {"pdf_pages", summary.pdf_pages}}}});
}

}  // namespace planner
