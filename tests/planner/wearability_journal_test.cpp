// The wearability stage's journal: a run cut short resumes from it with the
// results an uninterrupted run gets.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "planner/wearability/journal.hpp"
#include "tests/planner/cover_shapes.hpp"
#include "tests/test_support.hpp"

namespace wearknit::test {
namespace {

namespace fs = std::filesystem;

planner::TestResult sample(bool wearable, int trials) {
  planner::TestResult result;
  result.wearable = wearable;
  result.steps = 1234 + trials;
  result.projections = 98765432100ULL;
  for (int t = 0; t < trials; ++t) {
    planner::TrialOutcome outcome;
    outcome.seed = 0xF00DCAFE12345678ULL + t;
    outcome.success = wearable && t + 1 == trials;
    outcome.steps = 300 * (t + 1);
    outcome.stalled = t % 2 == 0;
    outcome.min_distance = 0.1 / 3.0 + t * 1e-17;
    result.trials.push_back(outcome);
  }
  // An initial test measured for the opening order.
  if (trials == 3) result.openings = {1.0 / 3.0, 0.0, 12.5 + 1e-13};
  return result;
}

void expect_same(const planner::TestResult& a, const planner::TestResult& b) {
  EXPECT_EQ(a.wearable, b.wearable);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.projections, b.projections);
  ASSERT_EQ(a.trials.size(), b.trials.size());
  for (std::size_t t = 0; t < a.trials.size(); ++t) {
    EXPECT_EQ(a.trials[t].seed, b.trials[t].seed);
    EXPECT_EQ(a.trials[t].success, b.trials[t].success);
    EXPECT_EQ(a.trials[t].steps, b.trials[t].steps);
    EXPECT_EQ(a.trials[t].stalled, b.trials[t].stalled);
    EXPECT_EQ(a.trials[t].min_distance, b.trials[t].min_distance) << "read back exactly";
  }
  EXPECT_EQ(a.openings, b.openings) << "read back exactly";
}

TEST(WearabilityJournalTest, ALineReadsBackExactlyAndMalformedLinesAreRejected) {
  const auto test = sample(true, 3);
  ASSERT_EQ(test.openings.size(), 3u);
  const std::string line = planner::journal_line(0xABCDEF0123456789ULL, test);
  const auto parsed = planner::parse_journal_line(line);
  ASSERT_TRUE(parsed.has_value()) << line;
  EXPECT_EQ(parsed->first, 0xABCDEF0123456789ULL);
  expect_same(parsed->second, test);
  // Cut short anywhere (also by one digit of the check), with a word too
  // many, or with one digit changed: the check does not match.
  for (std::size_t length = 0; length < line.size(); ++length) {
    EXPECT_FALSE(planner::parse_journal_line(line.substr(0, length)).has_value()) << length;
  }
  EXPECT_FALSE(planner::parse_journal_line(line + " 7").has_value());
  std::string changed = line;
  changed[20] = changed[20] == '1' ? '2' : '1';
  EXPECT_FALSE(planner::parse_journal_line(changed).has_value());
  // A well-formed body with a right check but a bad flag is still refused.
  const std::string bad_flag = "abcdef0123456789 2 1 1 0 0";
  const auto check = [](const std::string& body) {
    std::ostringstream out;
    out << std::hex << std::setw(16) << std::setfill('0') << planner::fingerprint(body);
    return body + ' ' + out.str();
  };
  EXPECT_FALSE(planner::parse_journal_line(check(bad_flag)).has_value());
  EXPECT_TRUE(planner::parse_journal_line(check("abcdef0123456789 1 1 1 0 0")).has_value());
  // Without the count of openings, or with fewer openings than it says.
  EXPECT_FALSE(planner::parse_journal_line(check("abcdef0123456789 1 1 1 0")).has_value());
  EXPECT_FALSE(planner::parse_journal_line(check("abcdef0123456789 1 1 1 0 2 0.5")).has_value());
}

TEST(WearabilityJournalTest, KeepsTheTestsOfTheSameContextOnly) {
  const fs::path dir = make_temp_dir("journal-context");
  const std::string path = (dir / "wearability.journal").string();
  {
    planner::TestJournal journal(path, 7);
    ASSERT_EQ(journal.error(), "");
    EXPECT_EQ(journal.loaded(), 0);
    journal.add(1, sample(false, 2));
    journal.add(2, sample(true, 1));
    expect_same(*journal.find(2), sample(true, 1));
    EXPECT_FALSE(journal.find(3).has_value());
  }
  {
    planner::TestJournal journal(path, 7);
    EXPECT_EQ(journal.loaded(), 2);
    EXPECT_EQ(journal.skipped(), 0);
    expect_same(*journal.find(1), sample(false, 2));
    expect_same(*journal.find(2), sample(true, 1));
  }
  {
    planner::TestJournal journal(path, 7, /*fresh=*/true);
    EXPECT_EQ(journal.loaded(), 0);
    EXPECT_FALSE(journal.find(1).has_value());
    journal.add(5, sample(false, 4));
  }
  {
    // Another wearer or other options: nothing is reused, and the file is
    // started afresh for the new context.
    planner::TestJournal journal(path, 8);
    EXPECT_EQ(journal.loaded(), 0);
    EXPECT_FALSE(journal.find(5).has_value());
  }
  EXPECT_EQ(read_file(path), "wearknit wearability journal 3 0000000000000008\n");
  fs::remove_all(dir);
}

TEST(WearabilityJournalTest, ALineCutShortByAKillIsSkippedAndSpoilsNothing) {
  const fs::path dir = make_temp_dir("journal-torn");
  const std::string path = (dir / "wearability.journal").string();
  {
    planner::TestJournal journal(path, 3);
    journal.add(1, sample(false, 2));
    journal.add(2, sample(false, 2));
  }
  const std::string torn = planner::journal_line(3, sample(true, 2));
  {
    std::ofstream out(path, std::ios::app | std::ios::binary);
    out << torn.substr(0, torn.size() / 2);  // the kill came in the middle of a write
  }
  {
    planner::TestJournal journal(path, 3);
    EXPECT_EQ(journal.loaded(), 2);
    EXPECT_EQ(journal.skipped(), 1);
    EXPECT_FALSE(journal.find(3).has_value());
    journal.add(4, sample(true, 1));
  }
  planner::TestJournal journal(path, 3);
  EXPECT_EQ(journal.loaded(), 3) << read_file(path);
  EXPECT_EQ(journal.skipped(), 0);
  expect_same(*journal.find(4), sample(true, 1));
  EXPECT_EQ(journal.remove(), "");
  EXPECT_FALSE(fs::exists(path));
  fs::remove_all(dir);
}

TEST(WearabilityJournalTest, AJournalThatCannotBeWrittenIsReportedAndTestsStillRun) {
  const fs::path dir = make_temp_dir("journal-unwritable");
  const std::string path = (dir / "no-such-folder" / "wearability.journal").string();
  planner::TestJournal journal(path, 1);
  EXPECT_NE(journal.error().find(path), std::string::npos) << journal.error();
  journal.add(1, sample(false, 1));  // kept in memory only
  EXPECT_TRUE(journal.find(1).has_value());
  EXPECT_FALSE(fs::exists(path));
  fs::remove_all(dir);
}

// Stops the elimination after `limit` new tests, as a kill would.
struct Killed {};
class CutShort : public planner::TestRecord {
 public:
  CutShort(planner::TestRecord& inner, int limit) : inner_(inner), limit_(limit) {}
  std::optional<planner::TestResult> find(std::uint64_t key) override { return inner_.find(key); }
  void add(std::uint64_t key, const planner::TestResult& result) override {
    inner_.add(key, result);
    if (++added_ == limit_) throw Killed{};
  }

 private:
  planner::TestRecord& inner_;
  int limit_;
  int added_ = 0;
};

TEST(WearabilityJournalTest, AnEliminationCutShortResumesWithTheSameLabelsAndTrials) {
  // The torus cover cut into a disc (one meridian, four equator arcs): the
  // elimination runs the initial test and then several more.
  const CoverMesh cover = torus_cover(1.0, 0.4, 24, 12, 4);
  const CoverMesh ring = torus_mesh(1.0, 0.4, 48, 24);
  cloth::SdfParams sdf;
  sdf.resolution = 32;
  const cloth::SignedDistanceField field(ring.positions, ring.faces, sdf);
  planner::WearabilityParams params;
  params.cloth.max_steps = 1500;
  params.trials = 2;
  params.threads = 2;
  params.seed = 5;
  // Every test simulated and journalled: the linking test would fail the
  // equator arcs' tests without a simulation, and nothing to journal.
  params.linking = false;
  const auto whole = planner::eliminate(cover, field, params);
  ASSERT_TRUE(whole.wearable());
  ASSERT_GE(whole.tests, 3);
  EXPECT_EQ(whole.replayed, 0);

  const fs::path dir = make_temp_dir("journal-resume");
  const std::string path = (dir / "wearability.journal").string();
  {
    planner::TestJournal journal(path, 11);
    CutShort cut(journal, 3);
    params.record = &cut;
    EXPECT_THROW(planner::eliminate(cover, field, params), Killed);
  }
  planner::TestJournal journal(path, 11);
  EXPECT_EQ(journal.loaded(), 3);
  params.record = &journal;
  const auto resumed = planner::eliminate(cover, field, params);
  EXPECT_EQ(resumed.replayed, 3);
  EXPECT_EQ(resumed.tests, whole.tests);
  EXPECT_EQ(resumed.order, whole.order);
  expect_same(resumed.initial, whole.initial);
  for (std::size_t a = 0; a < cover.arcs.size(); ++a) {
    EXPECT_EQ(resumed.arcs[a].label, whole.arcs[a].label) << cover.arcs[a].name;
    EXPECT_EQ(resumed.arcs[a].position, whole.arcs[a].position);
    EXPECT_EQ(resumed.arcs[a].test.wearable, whole.arcs[a].test.wearable);
    ASSERT_EQ(resumed.arcs[a].test.trials.size(), whole.arcs[a].test.trials.size());
    for (std::size_t t = 0; t < whole.arcs[a].test.trials.size(); ++t) {
      EXPECT_EQ(resumed.arcs[a].test.trials[t].seed, whole.arcs[a].test.trials[t].seed);
      EXPECT_EQ(resumed.arcs[a].test.trials[t].steps, whole.arcs[a].test.trials[t].steps);
    }
  }
  // Every test is now in the journal: a third run simulates nothing.
  const auto replayed = planner::eliminate(cover, field, params);
  EXPECT_EQ(replayed.replayed, whole.tests + 1);
  EXPECT_EQ(replayed.open(), whole.open());
  // Another garment (one arc fewer) finds none of them.
  CoverMesh other = cover;
  other.arcs.pop_back();
  params.cloth.max_steps = 10;  // its tests only need to run, not to decide anything
  const auto unrelated = planner::eliminate(other, field, params);
  EXPECT_EQ(unrelated.replayed, 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace wearknit::test
