// wearknit fmt: read a knitout file and write it in canonical form.
#include <fstream>
#include <iostream>
#include <sstream>

#include "apps/wearknit/cli.hpp"
#include "knitout/output_file.hpp"
#include "knitout/parser.hpp"
#include "knitout/writer.hpp"

namespace wearknit::cli {

namespace po = boost::program_options;

int run_fmt(const std::vector<std::string>& args, Context& context) {
  std::string input;
  std::string output;
  std::string format_name;
  po::options_description options("options");
  options.add_options()("input", po::value<std::string>(&input)->required(),
                        "knitout file ('-' reads stdin)")(
      "output,o", po::value<std::string>(&output), "write here (default: stdout)")(
      "check", "write nothing; exit 1 when the file is not in canonical form")(
      "format", po::value<std::string>(&format_name)->default_value("text"),
      "diagnostics as text (stderr) or json (stdout)")("json", "same as --format json");
  po::positional_options_description positional;
  positional.add("input", 1);
  po::variables_map values;
  if (auto code = parse_options(args, *find_verb("fmt"), options, positional, values, context)) {
    return *code;
  }
  const auto format = text_or_json_format(values, format_name, "fmt", context);
  if (!format) return kExitUsage;

  knitout::DiagnosticSink sink;
  knitout::Program program;
  std::string original;
  if (input == "-") {
    std::ostringstream buffer;
    buffer << std::cin.rdbuf();
    original = buffer.str();
    program = knitout::parse_string(original, "<stdin>", sink);
  } else {
    std::ifstream in(input, std::ios::binary);
    if (!in) {
      context.err << input << ": error: cannot open file\n";
      return kExitUsage;
    }
    if (values.count("check")) {
      std::ostringstream buffer;
      buffer << in.rdbuf();
      original = buffer.str();
      program = knitout::parse_string(original, input, sink);
    } else {
      program = knitout::parse(in, input, sink);
    }
  }
  print_diagnostics(context, sink.diagnostics(), *format);
  if (sink.has_errors()) return kExitInvalid;

  if (values.count("check")) {
    if (knitout::write_to_string(program) != original) {
      context.err << (input == "-" ? "<stdin>" : input) << ": not in canonical form\n";
      return kExitInvalid;
    }
    return kExitOk;
  }
  if (output.empty()) {
    knitout::write(context.out, program);
    context.out.flush();
    return context.out ? kExitOk : kExitUsage;
  }
  const std::string failure = knitout::write_file_atomically(
      output, [&](std::ostream& out) { knitout::write(out, program); });
  if (!failure.empty()) {
    context.err << "wearknit fmt: " << failure << '\n';
    return kExitUsage;
  }
  return kExitOk;
}

}  // namespace wearknit::cli
