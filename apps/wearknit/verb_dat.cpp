// wearknit dat: knitout -> Shima Seiki DAT (swg091n2 profile).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <ostream>

#include "apps/wearknit/cli.hpp"
#include "backends/dat/format.hpp"
#include "backends/dat/passes.hpp"
#include "backends/dat/profile.hpp"
#include "backends/dat/raster.hpp"
#include "backends/dat/reader.hpp"
#include "knitout/output_file.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_dat(const std::vector<std::string>& args, Context& context) {
  std::string input;
  std::string output;
  std::string machine;
  std::string format_name;
  po::options_description options("options");
  options.add_options()("input", po::value<std::string>(&input)->required(),
                        "knitout file ('-' reads stdin)")(
      "output,o", po::value<std::string>(&output)->required(), "the DAT file to write")(
      "machine", po::value<std::string>(&machine)->default_value("swg091n2"),
      "machine profile (the DAT backend writes for swg091n2)")(
      "verify", "read the written file back and check it holds the same passes")(
      "format", po::value<std::string>(&format_name)->default_value("text"),
      "diagnostics as text (stderr) or json (stdout)")("json", "same as --format json");
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("dat"), options, positional, values, context)) {
    return *code;
  }
  const auto format = text_or_json_format(values, format_name, "dat", context);
  if (!format) return kExitUsage;
  const dat::Profile* profile = dat::find_profile(machine);
  if (profile == nullptr) {
    context.err << "wearknit dat: machine '" << machine << "' has no DAT profile; profiles:";
    for (std::string_view name : dat::profile_names()) context.err << ' ' << name;
    context.err << '\n';
    return kExitUsage;
  }

  knitout::DiagnosticSink sink;
  std::optional<dat::PassList> passes;
  if (input == "-") {
    passes = dat::form_passes(std::cin, "<stdin>", sink, *profile);
  } else {
    std::ifstream in(input, std::ios::binary);
    if (!in) {
      context.err << input << ": error: cannot open file\n";
      return kExitUsage;
    }
    passes = dat::form_passes(in, input, sink, *profile);
  }
  std::optional<std::vector<std::uint8_t>> bytes;
  if (passes) bytes = dat::write_dat(*passes, sink);
  print_diagnostics(context, sink.diagnostics(), *format);
  if (!bytes) return kExitInvalid;

  const std::string failure = knitout::write_file_atomically(output, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes->data()),
              static_cast<std::streamsize>(bytes->size()));
  });
  if (!failure.empty()) {
    context.err << "wearknit dat: " << failure << '\n';
    return kExitUsage;
  }
  if (values.count("verify") == 0) return kExitOk;

  // Read the file as written, not the bytes in memory.
  knitout::DiagnosticSink verify_sink;
  bool ok = false;
  const std::vector<std::uint8_t> written = dat::read_bytes(output, verify_sink, ok);
  std::vector<std::string> problems;
  if (ok) {
    const dat::Raster raster = dat::decode(written, output, verify_sink);
    if (!verify_sink.has_errors()) {
      if (auto layout = dat::read_layout(raster, output, verify_sink)) {
        problems = dat::compare_passes(*passes, *layout);
      }
    }
  }
  for (const knitout::Diagnostic& d : verify_sink.diagnostics()) {
    if (d.severity == knitout::Severity::Error) problems.push_back(knitout::format(d));
  }
  if (problems.empty()) return kExitOk;
  std::error_code ignored;
  std::filesystem::remove(output, ignored);
  for (const std::string& problem : problems) {
    context.err << output << ": error: [D050] --verify: " << problem << '\n';
  }
  context.err << "wearknit dat: " << output << " did not read back as written; removed it\n";
  return kExitInvalid;
}

}  // namespace wearknit::cli
