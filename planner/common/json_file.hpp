// JSON files of a plan folder: read with a diagnostic naming the file when
// it is missing or malformed, written atomically (knitout/output_file.hpp).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

#include "knitout/diagnostic.hpp"

namespace planner {

// The JSON object in `path`. A missing or unreadable file is reported with
// `missing_code`, malformed JSON or a value that is not an object with
// `malformed_code`; both give nullopt.
std::optional<nlohmann::json> read_json_object(const std::string& path,
                                               knitout::DiagnosticSink& sink,
                                               std::string_view missing_code,
                                               std::string_view malformed_code);

// The JSON object in `path`, or nullopt when the file is absent or is not a
// JSON object (for files that are optional).
std::optional<nlohmann::json> read_json_object_if_any(const std::string& path);

// Writes `value` (one space of indent per level, a final newline)
// atomically. Returns an empty string or the failure, naming the file.
std::string write_json_file(const std::string& path, const nlohmann::json& value);

}  // namespace planner
