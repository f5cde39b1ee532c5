// wearknit send: send a job to a machine, with progress, reconnection and
// resume.
#include <cstdio>

#include "apps/wearknit/cli.hpp"
#include "apps/wearknit/send_progress.hpp"
#include "devices/folder_drop.hpp"
#include "devices/sender.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_send(const std::vector<std::string>& args, Context& context) {
  std::string job_path;
  std::string to;
  int attempts = 8;
  po::options_description options("options");
  options.add_options()("job", po::value<std::string>(&job_path)->required(),
                        "DAT (.dat) or knitout (.k) file")(
      "to", po::value<std::string>(&to)->required(),
      "tcp://HOST:PORT, serial:PATH[?baud=N], usb://VID:PID[/SERIAL], dir:PATH or loopback:")(
      "resume", "finish this job where the device left it")(
      "attempts", po::value<int>(&attempts)->default_value(8),
      "reconnection attempts in a row before giving up")("quiet,q", "no progress output");
  po::positional_options_description positional;
  positional.add("job", 1);
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("send"), options, positional, values, context)) {
    return *code;
  }
  return send_file(job_path, to,
                   {values.count("resume") != 0, attempts, values.count("quiet") != 0}, context);
}

int send_file(const std::string& job_path, const std::string& to, const SendFileOptions& options,
              Context& context) {
  auto uri = devices::parse_uri(to);
  if (!uri) {
    context.err << "wearknit send: " << uri.error().text() << '\n';
    return kExitUsage;
  }
  auto job = devices::load_job(job_path);
  if (!job) {
    context.err << "wearknit send: " << job.error().text() << '\n';
    return job.error().error_class == devices::ErrorClass::OsFailure ? kExitUsage : kExitInvalid;
  }
  if (uri.value().kind == devices::DeviceUri::Kind::Dir) {
    devices::Outcome stored = devices::deliver_to_folder(job.value(), uri.value().path);
    if (!stored) {
      context.err << "wearknit send: " << stored.error().text() << '\n';
      return kExitUsage;
    }
    context.out << "stored " << uri.value().path << "/" << job.value().name << " ("
                << job.value().bytes.size() << " bytes, " << job.value().row_count()
                << " rows, read back with SHA-256 " << devices::to_hex(job.value().sha256) << ")\n";
    return kExitOk;
  }
  devices::SendOptions send_options;
  send_options.resume = options.resume;
  devices::LinkOptions link;
  link.max_attempts = std::max(options.attempts, 0);
  link.loopback_checkers = project_job_checkers();
  link.job_path = job_path;
  ProgressPrinter printer(context, options.quiet, to);
  auto report = devices::send_job(
      uri.value(), job.value(), send_options, link,
      [&](const devices::Progress& p, const std::string& note) { printer.update(p, note); });
  if (report) {
    printer.finish(report.value().progress);
  } else {
    printer.end_bar();
  }
  if (!report) {
    context.err << "wearknit send: " << job_path << ": " << report.error().text() << '\n';
    return kExitUsage;
  }
  const devices::SendReport& r = report.value();
  if (!r.done) {
    context.err << "wearknit send: " << job_path << ": " << r.message << '\n';
    return kExitInvalid;
  }
  if (!r.message.empty()) context.out << r.message << '\n';
  char seconds[32];
  std::snprintf(seconds, sizeof seconds, "%.2f", r.seconds);
  context.out << "done: " << job.value().name << " -> " << to << ": " << r.progress.rows_knitted
              << "/" << r.progress.rows_total << " rows knitted (device confirmed), "
              << r.reconnects << " reconnects, " << seconds << " s\n";
  return kExitOk;
}

}  // namespace wearknit::cli
