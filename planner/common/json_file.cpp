#include "planner/common/json_file.hpp"

#include <fstream>
#include <ostream>

#include "knitout/output_file.hpp"

namespace planner {

using nlohmann::json;

std::optional<json> read_json_object(const std::string& path, knitout::DiagnosticSink& sink,
                                     std::string_view missing_code,
                                     std::string_view malformed_code) {
  std::ifstream in(path);
  if (!in) {
    sink.error(path, 0, 0, missing_code, "cannot open file");
    return std::nullopt;
  }
  json value;
  try {
    value = json::parse(in);
  } catch (const json::exception& e) {
    sink.error(path, 0, 0, malformed_code, std::string("malformed JSON: ") + e.what());
    return std::nullopt;
  }
  if (!value.is_object()) {
    sink.error(path, 0, 0, malformed_code, "not a JSON object");
    return std::nullopt;
  }
  return value;
}

std::optional<json> read_json_object_if_any(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  json value = json::parse(in, nullptr, false);
  if (value.is_discarded() || !value.is_object()) return std::nullopt;
  return value;
}

std::string write_json_file(const std::string& path, const json& value) {
  return knitout::write_file_atomically(path,
                                        [&](std::ostream& out) { out << value.dump(1) << '\n'; });
}

}  // namespace planner
