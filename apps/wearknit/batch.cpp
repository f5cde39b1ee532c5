#include "apps/wearknit/batch.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/plan_display.hpp"
#include "knitout/diagnostic_reports.hpp"
#include "knitout/output_file.hpp"
#include "planner/common/hash.hpp"
#include "planner/common/json_file.hpp"

namespace wearknit::cli {

namespace fs = std::filesystem;
namespace po = boost::program_options;
using nlohmann::json;

namespace {

// The fields of one CSV record starting at `pos` (RFC 4180); advances `pos`
// past the record's line end and counts the lines it spans in `lines`.
// Returns false with `problem` set for an unterminated quote.
bool read_record(const std::string& text, std::size_t& pos, std::vector<std::string>& fields,
                 int& lines, std::string& problem) {
  fields.assign(1, std::string());
  lines = 1;
  bool quoted = false;
  while (pos < text.size()) {
    const char c = text[pos++];
    if (quoted) {
      if (c == '"') {
        if (pos < text.size() && text[pos] == '"') {
          fields.back() += '"';
          ++pos;
        } else {
          quoted = false;
        }
      } else {
        if (c == '\n') ++lines;
        fields.back() += c;
      }
    } else if (c == '"' && fields.back().empty()) {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c == '\n') {
      break;
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  if (quoted) {
    problem = "a quoted field is not closed";
    return false;
  }
  return true;
}

std::string trim(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t") - begin + 1);
}

// A row's name becomes a folder name: letters, digits, '-', '_' and '.', not
// starting with '.', at most 100 characters.
std::string name_problem(const std::string& name) {
  if (name.empty()) return "the name is empty";
  if (name.size() > 100) return "the name is longer than 100 characters";
  if (name[0] == '.') return "the name starts with '.'";
  for (const char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') {
      return "the name '" + name + "' has a character other than letters, digits, - _ .";
    }
  }
  return "";
}

std::string now_utc() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::ostringstream text;
  text << std::put_time(&tm, "%Y-%m-%dT%H:%M:%SZ");
  return text.str();
}

// The CSV field for `text`: quoted when it holds a comma, a quote or a line end.
std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) {
    out += c;
    if (c == '"') out += '"';
  }
  return out + "\"";
}

std::string number_text(const json& value) {
  if (!value.is_number()) return "";
  std::ostringstream text;
  if (value.is_number_integer() || value.is_number_unsigned()) {
    text << value.dump();
  } else {
    text << std::fixed << std::setprecision(2) << value.get<double>();
  }
  return text.str();
}

// `wearknit plan`'s own table of options, made once: the manifest's columns
// are checked against it, and it says which options are flags.
const po::options_description& plan_option_table() {
  static PlanVerbOptions values;
  static const po::options_description table = [] {
    po::options_description plan("plan");
    add_plan_options(plan, values);
    return plan;
  }();
  return table;
}

}  // namespace

std::optional<Manifest> read_manifest(const fs::path& path, std::vector<std::string>& problems) {
  const auto text = slurp(path.string());
  const std::string where = path.string();
  if (!text) {
    problems.push_back(where + ": error: cannot read the manifest");
    return std::nullopt;
  }
  // The columns `wearknit plan` takes, from its own option table.
  const po::options_description& plan = plan_option_table();
  static const std::set<std::string> kSetByBatch = {"output", "threads", "quiet", "send"};

  Manifest manifest;
  manifest.path = path;
  std::size_t pos = 0;
  int line = 1;
  std::vector<std::string> header;
  std::vector<std::string> fields;
  int lines = 0;
  std::string problem;
  // The header: the first line that is not blank.
  while (pos < text->size() && header.empty()) {
    if (!read_record(*text, pos, fields, lines, problem)) {
      problems.push_back(where + ":" + std::to_string(line) + ": error: " + problem);
      return std::nullopt;
    }
    line += lines;
    if (fields.size() == 1 && trim(fields[0]).empty()) continue;
    for (const std::string& f : fields) header.push_back(trim(f));
  }
  if (header.empty()) {
    problems.push_back(where +
                       ": error: the manifest is empty; its first line names the columns "
                       "(name,garment,wearer and any plan option)");
    return std::nullopt;
  }
  const int header_line = line - 1;
  std::set<std::string> seen_columns;
  for (const std::string& column : header) {
    const std::string at = where + ":" + std::to_string(header_line) + ": error: ";
    if (!seen_columns.insert(column).second) {
      problems.push_back(at + "column '" + column + "' appears twice");
      continue;
    }
    if (column == "name" || column == "garment" || column == "wearer") continue;
    std::string option = column;
    std::replace(option.begin(), option.end(), '_', '-');
    if (kSetByBatch.count(option) != 0) {
      problems.push_back(at + "column '" + column + "': the batch sets --" + option +
                         " itself (--jobs and --threads set the threads)");
    } else if (plan.find_nothrow(option, false) == nullptr) {
      problems.push_back(at + "column '" + column + "' is not an option of wearknit plan (--" +
                         option + ")");
    }
  }
  for (const char* required : {"name", "garment", "wearer"}) {
    if (seen_columns.count(required) == 0) {
      problems.push_back(where + ":" + std::to_string(header_line) + ": error: no column '" +
                         required + "' (the header needs name, garment and wearer)");
    }
  }
  if (!problems.empty()) return std::nullopt;

  std::set<std::string> names;
  while (pos < text->size()) {
    const int row_line = line;
    if (!read_record(*text, pos, fields, lines, problem)) {
      problems.push_back(where + ":" + std::to_string(row_line) + ": error: " + problem);
      break;
    }
    line += lines;
    if (fields.size() == 1 && trim(fields[0]).empty()) continue;  // a blank line
    const std::string at = where + ":" + std::to_string(row_line) + ": error: ";
    if (fields.size() != header.size()) {
      problems.push_back(at + "the row has " + std::to_string(fields.size()) +
                         " fields; the header has " + std::to_string(header.size()));
      continue;
    }
    BatchRow row;
    row.line = row_line;
    for (std::size_t c = 0; c < header.size(); ++c) {
      const std::string value = trim(fields[c]);
      if (header[c] == "name") {
        row.name = value;
      } else if (header[c] == "garment") {
        row.garment = value;
      } else if (header[c] == "wearer") {
        row.wearer = value;
      } else if (!value.empty()) {
        std::string option = header[c];
        std::replace(option.begin(), option.end(), '_', '-');
        row.options.emplace_back(option, value);
      }
    }
    if (const std::string p = name_problem(row.name); !p.empty()) {
      problems.push_back(at + p);
      continue;
    }
    if (!names.insert(row.name).second) {
      problems.push_back(at + "the name '" + row.name + "' is used by an earlier row");
      continue;
    }
    if (row.garment.empty() || row.wearer.empty()) {
      problems.push_back(at + "row '" + row.name + "' has no " +
                         (row.garment.empty() ? "garment" : "wearer"));
      continue;
    }
    // Relative paths are relative to the manifest's folder.
    const fs::path base = fs::absolute(path).parent_path();
    row.garment_path =
        fs::path(row.garment).is_absolute() ? fs::path(row.garment) : base / row.garment;
    row.wearer_path = fs::path(row.wearer).is_absolute() ? fs::path(row.wearer) : base / row.wearer;
    manifest.rows.push_back(std::move(row));
  }
  if (!problems.empty()) return std::nullopt;
  if (manifest.rows.empty()) {
    problems.push_back(where + ": error: the manifest has a header but no rows");
    return std::nullopt;
  }
  return manifest;
}

std::vector<std::string> plan_arguments(const BatchRow& row, const fs::path& dir, int threads) {
  std::vector<std::string> args = {
      "plan",   row.garment_path.string(), "--wearer",  row.wearer_path.string(),
      "-o",     (dir / row.name).string(), "--threads", std::to_string(threads),
      "--quiet"};
  for (const auto& [option, value] : row.options) {
    args.push_back("--" + option);
    // A flag column (no-pictures, restart, ...) takes true/yes/1 or nothing.
    if (value != "true" && value != "yes" && value != "1") {
      args.push_back(value);
    } else {
      const po::option_description* d = plan_option_table().find_nothrow(option, false);
      if (d != nullptr && d->semantic()->max_tokens() > 0) args.push_back(value);
    }
  }
  return args;
}

std::optional<std::uint64_t> row_fingerprint(const BatchRow& row) {
  std::string key = "wearknit-batch-row 1\n";
  for (const auto& [option, value] : row.options) key += option + "=" + value + "\n";
  const auto garment = slurp(row.garment_path.string());
  const auto wearer = slurp(row.wearer_path.string());
  if (!garment || !wearer) return std::nullopt;
  std::uint64_t h = planner::fingerprint(key);
  h = planner::fingerprint(*garment, h);
  h = planner::fingerprint(*wearer, h);
  return h;
}

fs::path batch_state_dir(const fs::path& dir) {
  return dir / ".batch";
}

std::optional<RowState> read_row_state(const fs::path& dir, const std::string& name) {
  const auto value =
      planner::read_json_object_if_any((batch_state_dir(dir) / (name + ".json")).string());
  if (!value || !value->is_object()) return std::nullopt;
  RowState state;
  state.status = value->value("status", "");
  if (!planner::parse_hex64(value->value("fingerprint", ""), state.fingerprint))
    return std::nullopt;
  state.exit_code = value->value("exit", -1);
  state.error = value->value("error", "");
  state.seconds = value->value("seconds", 0.0);
  state.started = value->value("started", "");
  return state;
}

std::string write_row_state(const fs::path& dir, const std::string& name, const RowState& state) {
  std::error_code ignored;
  fs::create_directories(batch_state_dir(dir), ignored);
  const json value = {
      {"status", state.status},   {"fingerprint", planner::hex64(state.fingerprint)},
      {"exit", state.exit_code},  {"error", state.error},
      {"seconds", state.seconds}, {"started", state.started.empty() ? now_utc() : state.started}};
  return knitout::write_file_atomically((batch_state_dir(dir) / (name + ".json")).string(),
                                        [&](std::ostream& out) { out << value.dump(2) << '\n'; });
}

bool row_done(const fs::path& dir, const BatchRow& row,
              const std::optional<std::uint64_t>& fingerprint) {
  const auto state = read_row_state(dir, row.name);
  return state && state->status == "ok" && fingerprint && *fingerprint == state->fingerprint;
}

std::string write_batch_summary(const fs::path& dir, const Manifest& manifest,
                                std::size_t* ok_rows) {
  json rows = json::array();
  std::size_t ok = 0;
  for (const BatchRow& row : manifest.rows) {
    json r = {
        {"name", row.name}, {"garment", row.garment}, {"wearer", row.wearer}, {"folder", row.name}};
    json options = json::object();
    for (const auto& [option, value] : row.options) options[option] = value;
    r["options"] = options;
    const auto state = read_row_state(dir, row.name);
    const auto fingerprint = row_fingerprint(row);
    if (!state) {
      r["status"] = "not run";
    } else if (state->status == "running") {
      r["status"] = "unfinished";  // killed, or running elsewhere now
    } else if (state->status == "ok" && (!fingerprint || *fingerprint != state->fingerprint)) {
      r["status"] = "changed";  // its inputs or options changed since it ran
    } else {
      r["status"] = state->status;
    }
    if (state) {
      r["exit"] = state->exit_code;
      r["seconds"] = state->seconds;
      if (!state->error.empty()) r["error"] = state->error;
    }
    ok += r["status"] == "ok";
    // The plan's own figures.
    if (const auto plan = planner::read_json_object_if_any((dir / row.name / "plan.json").string());
        plan && plan->contains("plan")) {
      const json& p = (*plan)["plan"];
      json stages = json::object();
      for (const json& s : p.value("stages", json::array())) {
        stages[s.value("name", "?")] = s.value("time_s", 0.0);
      }
      r["stage_s"] = stages;
      r["total_s"] = p.value("total_s", 0.0);
      r["summary"] = p.value("summary", json::object());
    }
    if (const auto report =
            planner::read_json_object_if_any((dir / row.name / "report.json").string());
        report && report->contains("assembly")) {
      const json& a = (*report)["assembly"];
      r["seams"] = a.value("seams", json());
      r["seams_sewn"] = a.value("sewn", json());
      r["seams_laced"] = a.value("laced", json());
    }
    if (fs::exists(dir / row.name / "index.html")) r["page"] = row.name + "/index.html";
    rows.push_back(std::move(r));
  }
  if (ok_rows) *ok_rows = ok;
  const json summary = {{"format", "wearknit-batch 1"},
                        {"manifest", fs::absolute(manifest.path).string()},
                        {"written", now_utc()},
                        {"rows", rows}};
  std::string failure = knitout::write_file_atomically(
      (dir / "batch.json").string(), [&](std::ostream& out) { out << summary.dump(2) << '\n'; });
  if (!failure.empty()) return failure;

  static const char* kStages[] = {"cut", "wearability", "stitch-mesh", "schedule", "assembly"};
  failure = knitout::write_file_atomically((dir / "batch.csv").string(), [&](std::ostream& out) {
    out << "name,status,error,cut_s,wearability_s,stitch_mesh_s,schedule_s,assembly_s,total_s,"
           "arcs,seams,seams_sewn,seams_laced,arcs_sewn,arcs_laced,pieces,schedule_cuts,"
           "stitches,estimated_knit_time_s,folder,page\n";
    for (const json& r : rows) {
      const json none;
      const json& stages = r.contains("stage_s") ? r["stage_s"] : none;
      const json& s = r.contains("summary") ? r["summary"] : none;
      const auto field = [](const json& object, const char* key) {
        return object.is_object() && object.contains(key) ? number_text(object[key])
                                                          : std::string();
      };
      out << csv_field(r["name"].get<std::string>()) << ',' << r["status"].get<std::string>() << ','
          << csv_field(r.value("error", "")) << ',';
      for (const char* stage : kStages) out << field(stages, stage) << ',';
      out << field(r, "total_s") << ',' << field(s, "arcs") << ',' << field(r, "seams") << ','
          << field(r, "seams_sewn") << ',' << field(r, "seams_laced") << ',' << field(s, "sewn")
          << ',' << field(s, "laced") << ',' << field(s, "pieces") << ','
          << field(s, "schedule_cuts") << ',' << field(s, "stitches") << ','
          << field(s, "estimated_knit_time_s") << ',' << csv_field(r["folder"].get<std::string>())
          << ',' << csv_field(r.value("page", "")) << '\n';
    }
  });
  if (!failure.empty()) return failure;

  // DIR/index.html: a table of the rows, each linking its plan's own page.
  return knitout::write_file_atomically((dir / "index.html").string(), [&](std::ostream& out) {
    out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
        << "<title>wearknit batch: " << knitout::xml_escape(manifest.path.filename().string())
        << "</title>\n<style>body{font-family:system-ui,sans-serif;margin:16px;color:#1d2330}"
        << "table{border-collapse:collapse;font-variant-numeric:tabular-nums}"
        << "td,th{padding:3px 8px;border-bottom:1px solid #d5d9e2;text-align:left}"
        << "td.n{text-align:right}.ok{color:#1f9d55}.failed,.unfinished,.changed{color:#d64545}"
        << "</style>\n</head>\n<body>\n<h1>wearknit batch: "
        << knitout::xml_escape(manifest.path.filename().string()) << "</h1>\n"
        << "<table>\n<tr><th>name</th><th>status</th><th>pieces</th><th>seams sewn / "
           "laced</th><th>stitches</th><th>est. knit time</th><th>plan time</th><th>error</th>"
           "</tr>\n";
    for (const json& r : rows) {
      const std::string name = knitout::xml_escape(r["name"].get<std::string>());
      const json none;
      const json& s = r.contains("summary") ? r["summary"] : none;
      const auto n = [&](const json& object, const char* key) {
        return object.is_object() && object.contains(key) ? number_text(object[key])
                                                          : std::string("—");
      };
      out << "<tr><td>"
          << (r.contains("page")
                  ? "<a href=\"" + knitout::xml_escape(r["page"].get<std::string>()) + "\">" +
                        name + "</a>"
                  : name)
          << "</td><td class=\"" << r["status"].get<std::string>() << "\">"
          << r["status"].get<std::string>() << "</td><td class=\"n\">" << n(s, "pieces")
          << "</td><td class=\"n\">" << n(r, "seams_sewn") << " / " << n(r, "seams_laced")
          << "</td><td class=\"n\">" << n(s, "stitches") << "</td><td class=\"n\">"
          << n(s, "estimated_knit_time_s") << " s</td><td class=\"n\">" << n(r, "total_s")
          << " s</td><td>" << knitout::xml_escape(r.value("error", "")) << "</td></tr>\n";
    }
    out << "</table>\n</body>\n</html>\n";
  });
}

}  // namespace wearknit::cli
