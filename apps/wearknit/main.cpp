// wearknit: the command-line front end. Thin: picks the verb and exits with
// its code; the verbs live in verb_*.cpp and call the libraries.
#include <unistd.h>

#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "apps/wearknit/cli.hpp"

#ifndef WEARKNIT_VERSION
#define WEARKNIT_VERSION "unknown"
#endif

int main(int argc, char** argv) {
  using namespace wearknit::cli;
  std::ios::sync_with_stdio(false);
  Context context{std::cout, std::cerr, ::isatty(STDOUT_FILENO) == 1};
  if (argc < 2) {
    print_usage(std::cerr);
    return kExitUsage;
  }
  const std::string first = argv[1];
  if (first == "--version" || first == "version") {
    std::cout << "wearknit " << WEARKNIT_VERSION << '\n';
    return kExitOk;
  }
  if (first == "--help" || first == "-h" || first == "help") {
    print_usage(std::cout);
    return kExitOk;
  }
  const Verb* verb = find_verb(first);
  if (verb == nullptr) {
    std::cerr << "wearknit: unknown verb '" << first << "'\n";
    print_usage(std::cerr);
    return kExitUsage;
  }
  std::vector<std::string> args(argv + 2, argv + argc);
  int code = kExitUsage;
  try {
    code = verb->run(args, context);
  } catch (const std::exception& e) {
    std::cerr << "wearknit " << verb->name << ": internal error: " << e.what() << '\n';
    code = kExitUsage;
  }
  std::cout.flush();
  return code;
}
