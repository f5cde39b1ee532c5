// browser_probe [--size WxH] [--shot OUT.png] URL [EXPRESSION...]: opens URL
// in headless Chromium (the harness of tests/browser.hpp), waits until the
// page is interactive, then evaluates each expression in turn; prints one
// JSON object with the seconds to interactive, each expression's value and
// seconds, and the page's console errors. With --shot, the page as it is
// after the last expression is written as PNG. For the benches of the pages
// (bench/*.sh) and the pictures of docs/viewer.md.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/browser.hpp"

int main(int argc, char** argv) {
  int width = 1280;
  int height = 900;
  std::string shot;
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--size" && i + 1 < argc) {
      if (std::sscanf(argv[++i], "%dx%d", &width, &height) != 2) width = 0;
    } else if (arg == "--shot" && i + 1 < argc) {
      shot = argv[++i];
    } else {
      args.push_back(arg);
    }
  }
  if (args.empty() || width <= 0 || height <= 0) {
    std::cerr << "usage: browser_probe [--size WxH] [--shot OUT.png] URL [EXPRESSION...]\n";
    return 2;
  }
  std::string why;
  const auto browser = wearknit::test::Browser::start(&why, width, height);
  if (!browser) {
    std::cerr << "browser_probe: " << why << "\n";
    return 77;
  }
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
  };
  nlohmann::json report;
  try {
    const auto start = Clock::now();
    report["ready"] = browser->open(args[0], 300);
    report["interactive_s"] = seconds_since(start);
    report["values"] = nlohmann::json::array();
    for (std::size_t i = 1; i < args.size(); ++i) {
      const auto begin = Clock::now();
      nlohmann::json value = browser->evaluate(args[i], 300);
      report["values"].push_back(
          {{"expression", args[i]}, {"value", value}, {"seconds", seconds_since(begin)}});
    }
    if (!shot.empty()) {
      std::ofstream out(shot, std::ios::binary);
      out << browser->screenshot_png();
      if (!out.flush()) throw std::runtime_error("cannot write " + shot);
    }
  } catch (const std::exception& error) {
    report["error"] = error.what();
  }
  report["console_errors"] = browser->console_errors();
  std::cout << report.dump(2) << "\n";
  return report.contains("error") ? 1 : 0;
}
