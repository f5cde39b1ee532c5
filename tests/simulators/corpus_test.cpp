// The whole public corpus through the virtual machine, against the verdict
// table tests/simulators/corpus_verdicts.tsv (derived from corpus/README.md).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "simulators/bed/profile.hpp"
#include "simulators/bed/validate.hpp"
#include "tests/test_support.hpp"

namespace bed {
namespace {

struct Verdict {
  std::string file;
  std::string reference;  // accepted | rejected
  std::string machine;
  std::string expect;  // valid | error
  std::string code;
  std::uint32_t line = 0;
  std::string category;
};

std::vector<Verdict> read_verdicts() {
  std::ifstream in(wearknit::test::source_dir() / "tests/simulators/corpus_verdicts.tsv");
  EXPECT_TRUE(in) << "corpus_verdicts.tsv missing";
  std::vector<Verdict> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    std::stringstream ss(line);
    std::string field;
    while (std::getline(ss, field, '\t')) fields.push_back(field);
    EXPECT_GE(fields.size(), 7u) << line;
    if (fields.size() < 7) continue;
    out.push_back({fields[0], fields[1], fields[2], fields[3], fields[4],
                   static_cast<std::uint32_t>(std::stoul(fields[5])), fields[6]});
  }
  return out;
}

TEST(CorpusTest, TableCoversTheCorpusAndAgreesWithItsReadme) {
  WEARKNIT_REQUIRE_SHARED(shared);
  const auto verdicts = read_verdicts();
  std::map<std::string, Verdict> by_file;
  for (const Verdict& v : verdicts) by_file[v.file] = v;
  std::set<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(shared / "corpus/knitout")) {
    if (entry.path().extension() == ".k") files.insert(entry.path().filename().string());
  }
  EXPECT_EQ(files.size(), by_file.size());
  for (const std::string& f : files) EXPECT_TRUE(by_file.count(f)) << f << " has no verdict";
  // The README's reference verdicts: every accepted file must be valid on
  // swg091n2 in the table.
  std::ifstream readme(shared / "corpus/README.md");
  std::string line;
  const std::regex row(R"(^\| (\S+\.k) \|.*\| (accepted|REJECTED \(exit 1\)) \|)");
  int rows = 0;
  while (std::getline(readme, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, row)) continue;
    ++rows;
    const auto it = by_file.find(m[1]);
    ASSERT_NE(it, by_file.end()) << m[1];
    const bool accepted = m[2] == "accepted";
    EXPECT_EQ(it->second.reference, accepted ? "accepted" : "rejected") << m[1];
    if (accepted) {
      EXPECT_EQ(it->second.machine, "swg091n2") << m[1];
      EXPECT_EQ(it->second.expect, "valid") << m[1];
    }
    if (std::string(m[1]).rfind("neg-", 0) == 0) {
      EXPECT_TRUE(it->second.expect == "error" || it->second.category == "dat") << m[1];
    }
  }
  EXPECT_EQ(rows, static_cast<int>(files.size()));
}

TEST(CorpusTest, EveryFileGetsItsExpectedVerdict) {
  WEARKNIT_REQUIRE_SHARED(shared);
  for (const Verdict& v : read_verdicts()) {
    SCOPED_TRACE(v.file + " on " + v.machine);
    const MachineProfile* profile = find_profile(v.machine);
    ASSERT_NE(profile, nullptr);
    knitout::DiagnosticSink sink;
    const std::string path = (shared / "corpus/knitout" / v.file).string();
    validate_file(path, *profile, sink);
    if (v.expect == "valid") {
      for (const auto& d : sink.diagnostics()) {
        EXPECT_NE(d.severity, knitout::Severity::Error) << knitout::format(d);
      }
    } else {
      ASSERT_EQ(v.expect, "error");
      bool hit = false;
      for (const auto& d : sink.diagnostics()) {
        hit |= d.severity == knitout::Severity::Error && d.code == v.code && d.line == v.line;
      }
      EXPECT_TRUE(hit) << "expected error " << v.code << " at line " << v.line;
    }
  }
}

}  // namespace
}  // namespace bed
