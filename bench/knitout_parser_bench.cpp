// Parser throughput on real input files.
//   knitout_parser_bench FILE.k... [google-benchmark flags]
// For each file: BM_Reader streams it through knitout::Reader (what the
// virtual machine does), BM_Parse builds a whole Program, BM_Format parses and
// writes the canonical form. The file is read into memory first, so disk
// speed is not measured; `lines/s` counts source lines.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "knitout/parser.hpp"
#include "knitout/writer.hpp"

namespace {

struct Input {
  std::string name;
  std::string text;
  double lines = 0;
};

class NullBuffer : public std::streambuf {
 protected:
  std::streamsize xsputn(const char*, std::streamsize n) override { return n; }
  int_type overflow(int_type c) override { return c; }
};

void bm_reader(benchmark::State& state, const Input* input) {
  for (auto _ : state) {
    std::istringstream in(input->text);
    knitout::DiagnosticSink sink;
    knitout::Reader reader(in, input->name, sink);
    knitout::Instruction instruction;
    std::size_t count = 0;
    while (reader.next(instruction)) ++count;
    benchmark::DoNotOptimize(count);
  }
  state.counters["lines/s"] =
      benchmark::Counter(input->lines, benchmark::Counter::kIsIterationInvariantRate);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * input->text.size()));
}

void bm_parse(benchmark::State& state, const Input* input) {
  for (auto _ : state) {
    knitout::DiagnosticSink sink;
    knitout::Program program = knitout::parse_string(input->text, input->name, sink);
    benchmark::DoNotOptimize(program.instructions.data());
  }
  state.counters["lines/s"] =
      benchmark::Counter(input->lines, benchmark::Counter::kIsIterationInvariantRate);
}

void bm_format(benchmark::State& state, const Input* input) {
  NullBuffer null_buffer;
  std::ostream null_stream(&null_buffer);
  for (auto _ : state) {
    knitout::DiagnosticSink sink;
    const knitout::Program program = knitout::parse_string(input->text, input->name, sink);
    knitout::write(null_stream, program);
  }
  state.counters["lines/s"] =
      benchmark::Counter(input->lines, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  static std::vector<Input> inputs;
  inputs.reserve(static_cast<std::size_t>(argc));
  for (int i = 1; i < argc; ++i) {
    std::ifstream in(argv[i], std::ios::binary);
    if (!in) {
      std::cerr << "knitout_parser_bench: cannot open " << argv[i] << '\n';
      return 2;
    }
    std::ostringstream buffer;
    buffer << in.rdbuf();
    Input input{argv[i], buffer.str(), 0};
    input.lines = static_cast<double>(std::count(input.text.begin(), input.text.end(), '\n'));
    inputs.push_back(std::move(input));
  }
  if (inputs.empty()) {
    std::cerr << "usage: knitout_parser_bench FILE.k... [benchmark flags]\n";
    return 2;
  }
  for (const Input& input : inputs) {
    const std::string base = input.name.substr(input.name.find_last_of('/') + 1);
    benchmark::RegisterBenchmark(("Reader/" + base).c_str(), bm_reader, &input)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Parse/" + base).c_str(), bm_parse, &input)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("Format/" + base).c_str(), bm_format, &input)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
