// wearknit mock-device: the loopback mock knitting machine on a real link.
#include <csignal>
#include <iostream>
#include <istream>

#include "apps/wearknit/cli.hpp"
#include "backends/dat/format.hpp"
#include "backends/dat/reader.hpp"
#include "devices/file_view.hpp"
#include "devices/mock_server.hpp"
#include "simulators/bed/validate.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

namespace {
std::atomic<bool> stop_requested{false};
extern "C" void request_stop(int) {
  stop_requested.store(true);
}
}  // namespace

devices::JobCheckers project_job_checkers() {
  devices::JobCheckers checkers;
  // knitout: the needle-bed virtual machine, on the default machine profile:
  // the parser's syntax errors (K codes) and the machine's (V codes) alike.
  // Warnings do not stop a machine, so they do not refuse a job.
  checkers.knitout = [](const std::string& name, std::span<const std::uint8_t> bytes) {
    devices::SpanStreambuf view(bytes);  // read in place: no copy of the job
    std::istream in(&view);
    knitout::DiagnosticSink sink(20);
    bed::validate_stream(in, name, bed::default_profile(), sink);
    for (const knitout::Diagnostic& d : sink.sorted()) {
      if (d.severity != knitout::Severity::Error) continue;
      std::string reason = knitout::format(d);
      if (sink.error_count() > 1) {
        reason += " (and " + std::to_string(sink.error_count() - 1) + " more errors)";
      }
      return reason;
    }
    return std::string();
  };
  // DAT: the device itself checks the header, that the run-length rows add
  // up to the width and the row count (devices::split_rows); the DAT reader
  // decodes the raster and reads its layout (passes, option lines).
  checkers.dat = [](const std::string& name, std::span<const std::uint8_t> bytes) {
    knitout::DiagnosticSink sink(20);
    const dat::Raster raster = dat::decode(bytes, name, sink);
    if (!sink.has_errors()) (void)dat::read_layout(raster, name, sink);
    for (const knitout::Diagnostic& d : sink.diagnostics()) {
      if (d.severity == knitout::Severity::Error) return knitout::format(d);
    }
    return std::string();
  };
  return checkers;
}

int run_mock_device(const std::vector<std::string>& args, Context& context) {
  std::string listen;
  std::string store;
  std::string fault_text;
  double rows_per_s = 200;
  std::uint32_t buffer_rows = 32;
  std::uint64_t seed = 1;
  po::options_description options("options");
  options.add_options()("listen", po::value<std::string>(&listen)->required(),
                        "tcp://HOST:PORT (port 0: any free port), pty: or serial:PATH")(
      "store", po::value<std::string>(&store)->required(),
      "folder for received jobs and the device's counters")(
      "fault", po::value<std::string>(&fault_text),
      "corrupt=P,drop=P,dup=P,disconnect-every=N,reboot-every=N,stall-ms=N,"
      "yarn-break-at=ROW,stop-at=ROW")("rows-per-s",
                                       po::value<double>(&rows_per_s)->default_value(200),
                                       "knitting speed; 0 knits a verified job at once")(
      "buffer-rows", po::value<std::uint32_t>(&buffer_rows)->default_value(32),
      "rows the device buffers before they reach its store")(
      "seed", po::value<std::uint64_t>(&seed)->default_value(1), "seed of the fault injector")(
      "no-sync", "do not fsync the store (benchmarks only: a power cut may lose counters)")(
      "exit-when-done", "exit once a job is done, refused or cancelled");
  po::positional_options_description positional;
  po::variables_map values;
  if (auto code =
          parse_options(args, *find_verb("mock-device"), options, positional, values, context)) {
    return *code;
  }
  auto uri = devices::parse_uri(listen);
  if (!uri) {
    context.err << "wearknit mock-device: " << uri.error().text() << '\n';
    return kExitUsage;
  }
  devices::FaultSpec faults;
  if (!fault_text.empty()) {
    auto parsed = devices::parse_fault_spec(fault_text);
    if (!parsed) {
      context.err << "wearknit mock-device: --fault: " << parsed.error().text() << '\n';
      return kExitUsage;
    }
    faults = parsed.value();
  }
  if (buffer_rows == 0 || rows_per_s < 0) {
    context.err << "wearknit mock-device: --buffer-rows must be at least 1 and --rows-per-s "
                   "not negative\n";
    return kExitUsage;
  }
  devices::MockServerOptions server;
  server.listen = uri.value();
  server.device.store = store;
  server.device.buffer_rows = buffer_rows;
  server.device.rows_per_s = rows_per_s;
  server.device.sync = values.count("no-sync") == 0;
  server.device.checkers = project_job_checkers();
  server.device.yarn_break_at_row = faults.yarn_break_at;
  server.device.stop_at_row = faults.stop_at;
  server.device.on_event = [&](const std::string& text) { context.out << text << std::endl; };
  server.faults = faults;
  server.seed = seed;
  server.on_listening = [&](const std::string& where) {
    context.out << "listening " << where << std::endl;
  };
  server.stop = &stop_requested;
  server.exit_when_job_ends = values.count("exit-when-done") != 0;
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  devices::Outcome result = devices::Outcome(devices::Ok{});
  try {
    result = devices::run_mock_server(std::move(server));
  } catch (const std::exception& e) {
    context.err << "wearknit mock-device: " << e.what() << '\n';
    return kExitUsage;
  }
  if (!result) {
    context.err << "wearknit mock-device: " << result.error().text() << '\n';
    return kExitUsage;
  }
  return kExitOk;
}

}  // namespace wearknit::cli
