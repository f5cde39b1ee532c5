// browser_probe URL [EXPRESSION...]: opens URL in headless Chromium (the
// harness of tests/browser.hpp), waits until the page is interactive, then
// evaluates each expression in turn; prints one JSON object with the
// seconds to interactive, each expression's value and seconds, and the
// page's console errors. For the benches of the pages (bench/*.sh).
#include <chrono>
#include <iostream>
#include <string>

#include "tests/browser.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: browser_probe URL [EXPRESSION...]\n";
    return 2;
  }
  std::string why;
  const auto browser = wearknit::test::Browser::start(&why);
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
    report["ready"] = browser->open(argv[1], 300);
    report["interactive_s"] = seconds_since(start);
    report["values"] = nlohmann::json::array();
    for (int i = 2; i < argc; ++i) {
      const auto begin = Clock::now();
      nlohmann::json value = browser->evaluate(argv[i], 300);
      report["values"].push_back(
          {{"expression", argv[i]}, {"value", value}, {"seconds", seconds_since(begin)}});
    }
  } catch (const std::exception& error) {
    report["error"] = error.what();
  }
  report["console_errors"] = browser->console_errors();
  std::cout << report.dump(2) << "\n";
  return report.contains("error") ? 1 : 0;
}
