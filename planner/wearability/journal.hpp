// A wearability stage cut short resumes where it stopped: every test the
// elimination runs is appended to a journal file as soon as it ends, and a
// later run with the same inputs reads its results back instead of
// simulating them again (planner/wearability/wearability.hpp, TestRecord).
//
// The file is text, one test per line, after a first line naming what else
// decides a test (the wearer, the options, the program's version) by a
// fingerprint the caller computes:
//
//   wearknit wearability journal 1 <context, 16 hex digits>
//   <key> <wearable 0|1> <steps> <projections> <trials> {<seed> <success 0|1>
//       <steps> <stalled 0|1> <min_distance>}... <check>
//
// Keys, seeds and the check (the fingerprint of the line before it) are 16
// hex digits; min_distance is written with 17 significant digits, so it
// reads back exactly. A line is written and fsync'ed in one piece; a line
// cut short by a kill, or changed, fails its check and is ignored. A
// journal whose first line names another context is started afresh.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <unordered_map>

#include "planner/wearability/wearability.hpp"

namespace planner {

class TestJournal : public TestRecord {
 public:
  // Opens (or creates) the journal at `path` for `context`. A journal of
  // the same context is kept (its complete lines are rewritten, so a line
  // cut short does not spoil the next one); any other content is replaced.
  // `fresh` replaces it in any case. error() tells whether it worked.
  TestJournal(std::string path, std::uint64_t context, bool fresh = false);
  ~TestJournal() override;
  TestJournal(const TestJournal&) = delete;
  TestJournal& operator=(const TestJournal&) = delete;

  std::optional<TestResult> find(std::uint64_t key) override;
  // Appends the test. A write that fails is reported by error(); the tests
  // still run, they are only not kept.
  void add(std::uint64_t key, const TestResult& result) override;

  // Tests read from an earlier run of the same context.
  int loaded() const { return loaded_; }
  // Lines of an earlier run that could not be read (a line cut short).
  int skipped() const { return skipped_; }
  // The first failure to read or write the file, naming it; empty if none.
  const std::string& error() const { return error_; }
  const std::string& path() const { return path_; }
  // Closes and deletes the file (the stage finished and wrote its results).
  // Returns the failure, if any.
  std::string remove();

 private:
  std::string path_;
  std::uint64_t context_;
  std::unordered_map<std::uint64_t, TestResult> tests_;
  std::FILE* file_ = nullptr;
  int loaded_ = 0;
  int skipped_ = 0;
  std::string error_;
};

// One journal line (without the newline) and its parse; the parse returns
// nothing for a malformed line.
std::string journal_line(std::uint64_t key, const TestResult& result);
std::optional<std::pair<std::uint64_t, TestResult>> parse_journal_line(const std::string& line);

}  // namespace planner
