// wearknit status: what a machine is doing; pause, continue or cancel its job.
#include <filesystem>
#include <iostream>

#include "apps/wearknit/cli.hpp"
#include "devices/sender.hpp"
#include "knitout/diagnostic.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

namespace {

void print_status(Context& context, const std::string& uri, const devices::DeviceStatus& d,
                  bool json) {
  const devices::StatusMessage& s = d.status;
  if (json) {
    context.out << "{\"device\": " << knitout::json_quote(uri)
                << ", \"state\": " << knitout::json_quote(devices::to_string(s.state))
                << ", \"alarm\": " << knitout::json_quote(devices::to_string(s.alarm))
                << ", \"job\": " << knitout::json_quote(s.name)
                << ", \"format\": " << knitout::json_quote(devices::to_string(s.format))
                << ", \"sha256\": " << knitout::json_quote(devices::to_hex(s.sha256))
                << ", \"rows_total\": " << s.rows_total
                << ", \"rows_received\": " << s.rows_received
                << ", \"rows_knitted\": " << s.rows_knitted
                << ", \"buffer_free\": " << s.buffer_free
                << ", \"buffer_capacity\": " << s.buffer_capacity
                << ", \"reason\": " << knitout::json_quote(s.reason) << "}\n";
    return;
  }
  context.out << "device " << uri << ": protocol " << int(s.version) << ", buffer " << s.buffer_free
              << "/" << s.buffer_capacity << " rows free\n";
  if (s.state == devices::JobState::Idle) {
    context.out << "no job\n";
    return;
  }
  context.out << "job '" << s.name << "' (" << devices::to_string(s.format) << ", sha256 "
              << devices::to_hex(s.sha256) << "): " << devices::to_string(s.state);
  if (s.alarm != devices::Alarm::None) context.out << " (" << devices::to_string(s.alarm) << ")";
  context.out << ", " << s.rows_knitted << "/" << s.rows_total << " rows knitted, "
              << s.rows_received << "/" << s.rows_total << " received\n";
  if (!s.reason.empty()) context.out << "reason: " << s.reason << '\n';
}

}  // namespace

int run_status(const std::vector<std::string>& args, Context& context) {
  std::string to;
  po::options_description options("options");
  options.add_options()("to", po::value<std::string>(&to)->required(), "device URI")(
      "pause", "pause the device's job (acknowledged)")(
      "continue", "resume a paused job, or one stopped by an alarm")(
      "cancel", "cancel the device's job (acknowledged)")("json", "print the status as JSON");
  po::positional_options_description positional;
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("status"), options, positional, values, context)) {
    return *code;
  }
  auto uri = devices::parse_uri(to);
  if (!uri) {
    context.err << "wearknit status: " << uri.error().text() << '\n';
    return kExitUsage;
  }
  const int commands =
      static_cast<int>(values.count("pause") + values.count("continue") + values.count("cancel"));
  if (commands > 1) {
    context.err << "wearknit status: give at most one of --pause, --continue, --cancel\n";
    return kExitUsage;
  }
  if (uri.value().kind == devices::DeviceUri::Kind::Dir) {
    if (commands != 0) {
      context.err << "wearknit status: a dir: target takes no commands\n";
      return kExitUsage;
    }
    std::error_code ec;
    context.out << "folder " << uri.value().path << ":\n";
    for (const auto& entry : std::filesystem::directory_iterator(uri.value().path, ec)) {
      const std::string name = entry.path().filename().string();
      const std::string suffix = ".manifest.json";
      if (name.size() > suffix.size() && name.ends_with(suffix)) {
        context.out << "  " << name.substr(0, name.size() - suffix.size()) << '\n';
      }
    }
    if (ec) {
      context.err << "wearknit status: " << uri.value().path << ": " << ec.message() << '\n';
      return kExitUsage;
    }
    return kExitOk;
  }
  devices::LinkOptions link;
  link.loopback_checkers = project_job_checkers();
  auto result = commands == 0 ? devices::query_status(uri.value(), link)
                : values.count("pause")
                    ? devices::send_command(uri.value(), devices::Command::Pause, link)
                : values.count("continue")
                    ? devices::send_command(uri.value(), devices::Command::Resume, link)
                    : devices::send_command(uri.value(), devices::Command::Cancel, link);
  if (!result) {
    context.err << "wearknit status: " << result.error().text() << '\n';
    return result.error().error_class == devices::ErrorClass::Protocol ? kExitInvalid : kExitUsage;
  }
  print_status(context, to, result.value(), values.count("json") != 0);
  return kExitOk;
}

}  // namespace wearknit::cli
