// The virtual machine's rules, one should-fail case next to its should-pass
// twin. Offending lines carry a `;!CODE` comment; a case passes when the
// diagnostics are exactly the marked ones (code and line), nothing more.
#include "simulators/bed/machine.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "knitout/generate.hpp"
#include "knitout/parser.hpp"
#include "simulators/bed/profile.hpp"
#include "simulators/bed/validate.hpp"

namespace bed {
namespace {

using ::testing::ElementsAre;
using ::testing::UnorderedElementsAre;

constexpr const char* kSwgHeader =
    ";!knitout-2\n;;Machine: SWG091N2\n;;Gauge: 15\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n";
constexpr const char* kKniterateHeader =
    ";!knitout-2\n;;Machine: Kniterate\n;;Gauge: 7\n;;Carriers: 1 2 3 4 5 6\n";
constexpr const char* kGenericHeader = ";!knitout-2\n;;Carriers: 1 2 3 L1\n";

struct Case {
  const char* name;
  const char* machine;
  const char* header;
  const char* body;
  std::vector<std::string> extra;  // expected "LINE:CODE" not marked in the body
};

struct Outcome {
  std::vector<knitout::Diagnostic> diagnostics;
  Stats stats;
};

Outcome run(const std::string& text, const std::string& machine = "swg091n2",
            MachineOptions options = {}) {
  const MachineProfile* profile = find_profile(machine);
  EXPECT_NE(profile, nullptr) << machine;
  knitout::DiagnosticSink sink;
  std::istringstream in(text);
  Outcome result;
  result.stats = validate_stream(in, "t.k", *profile, sink, options);
  result.diagnostics = sink.sorted();
  return result;
}

// "LINE:CODE" of every `;!CODE` marker in `text` (line numbers 1-based).
std::vector<std::string> markers(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto at = line.find(";!");
    if (at == std::string::npos || line.rfind(";!knitout", 0) == 0) continue;
    std::istringstream codes(line.substr(at + 2));
    std::string code;
    while (codes >> code) out.push_back(std::to_string(number) + ":" + code);
  }
  return out;
}

std::vector<std::string> found(const std::vector<knitout::Diagnostic>& diagnostics) {
  std::vector<std::string> out;
  for (const auto& d : diagnostics) out.push_back(std::to_string(d.line) + ":" + d.code);
  return out;
}

class RuleTest : public ::testing::TestWithParam<Case> {};

TEST_P(RuleTest, ReportsExactlyTheMarkedLines) {
  const Case& c = GetParam();
  const std::string text = std::string(c.header) + c.body;
  std::vector<std::string> expected = markers(text);
  expected.insert(expected.end(), c.extra.begin(), c.extra.end());
  std::vector<std::string> actual = found(run(text, c.machine).diagnostics);
  std::sort(expected.begin(), expected.end());
  std::sort(actual.begin(), actual.end());
  EXPECT_EQ(actual, expected) << text;
}

// clang-format off
const Case kCases[] = {
  // Carriers and the yarn-inserting hook.
  {"V001_CarrierNotOnMachine_Fails", "swg091n2", ";!knitout-2\n;;Carriers: 1 2 L1\n", "in L1 ;!V001\n", {}},
  {"V001_CarrierNotOnMachine_PassesOnGeneric", "generic", kGenericHeader, "in L1\ntuck + f1 L1\nout L1\n", {}},
  {"V002_CarrierNotInHeader_Fails", "swg091n2", ";!knitout-2\n;;Carriers: 1 2\n", "in 3 ;!V002\n", {}},
  {"V002_CarrierInHeader_Passes", "swg091n2", ";!knitout-2\n;;Carriers: 1 2 3\n", "in 3\ntuck + f1 3\nout 3\n", {}},
  {"V003_InTwice_Fails", "swg091n2", kSwgHeader, "in 3\nin 3 ;!V003\ntuck + f1 3\nout 3\n", {}},
  {"V003_InAgainAfterOut_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nout 3\nin 3\ntuck - f1 3\nout 3\n", {}},
  {"V004_CarrierNotIn_Fails", "swg091n2", kSwgHeader, "tuck + f1 3 ;!V004\n", {}},
  {"V004_CarrierBroughtIn_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nout 3\n", {}},
  {"V005_FirstUseDiffersFromIn_Fails", "swg091n2", kSwgHeader, "in 3 4\ntuck + f1 4 3 ;!V005\nout 3 4\n", {}},
  {"V005_FirstUseMatchesIn_Passes", "swg091n2", kSwgHeader, "in 3 4\ntuck + f1 3 4\nout 3 4\n", {}},
  {"V006_InhookWhileHookBusy_Fails", "swg091n2", kSwgHeader,
   "inhook 3\ntuck + f1 3\ninhook 4\ntuck + f2 4 ;!V006\nreleasehook 3\nouthook 3 4\n", {}},
  {"V006_InhookAfterRelease_Passes", "swg091n2", kSwgHeader,
   "inhook 3\ntuck + f1 3\nreleasehook 3\ninhook 4\ntuck + f2 4\nreleasehook 4\nouthook 3 4\n", {}},
  {"V007_ReleasehookBeforeFirstStitch_Fails", "swg091n2", kSwgHeader,
   "inhook 3\nreleasehook 3 ;!V007\ntuck + f1 3\nreleasehook 3\nouthook 3\n", {}},
  {"V007_ReleasehookAfterFirstStitch_Passes", "swg091n2", kSwgHeader,
   "inhook 3\ntuck + f1 3\nreleasehook 3\nouthook 3\n", {}},
  {"V008_ReleasehookOtherCarriers_Fails", "swg091n2", kSwgHeader,
   "inhook 3 4\ntuck + f1 3 4\nreleasehook 3 ;!V008\nreleasehook 3 4\nouthook 3 4\n", {}},
  {"V008_ReleasehookSameCarriers_Passes", "swg091n2", kSwgHeader,
   "inhook 3 4\ntuck + f1 3 4\nreleasehook 3 4\nouthook 3 4\n", {}},
  {"V009_OutOfCarrierNotIn_Fails", "swg091n2", kSwgHeader, "out 3 ;!V009\n", {}},
  {"V009_OutOfCarrierIn_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nout 3\n", {}},
  {"V010_OutOfUnusedCarrier_Fails", "swg091n2", kSwgHeader, "in 3\nout 3 ;!V010\n", {}},
  {"V010_OutAfterMiss_Passes", "swg091n2", kSwgHeader, "in 3\nmiss + f1 3\nout 3\n", {}},
  {"V011_OutWhileHookHolds_Fails", "swg091n2", kSwgHeader, "inhook 3\ntuck + f1 3\nout 3 ;!V011\n", {}},
  {"V011_OutAfterRelease_Passes", "swg091n2", kSwgHeader, "inhook 3\ntuck + f1 3\nreleasehook 3\nout 3\n", {}},
  {"V012_OuthookWhileHookBusy_Fails", "swg091n2", kSwgHeader,
   "inhook 3\ntuck + f1 3\nin 4\ntuck + f2 4\nouthook 4 ;!V012\nreleasehook 3\nouthook 3\n", {}},
  {"V012_OuthookWithHookFree_Passes", "swg091n2", kSwgHeader,
   "inhook 3\ntuck + f1 3\nin 4\ntuck + f2 4\nreleasehook 3\nouthook 4\nouthook 3\n", {}},
  {"V013_CarrierLeftIn_Fails", "swg091n2", kSwgHeader, "in 3 ;!V013\ntuck + f1 3\n", {}},
  {"V013_CarrierTakenOut_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nout 3\n", {}},

  // Racking.
  {"V020_RackingBeyondRange_Fails", "swg091n2", kSwgHeader, "rack 9 ;!V020\nrack -8.75 ;!V020\n", {}},
  {"V020_RackingWithinRange_Passes", "swg091n2", kSwgHeader, "rack 8\nrack -8\nrack 0\n", {}},
  {"V020_KniterateRackingBeyondFour_Fails", "kniterate", kKniterateHeader, "rack 5 ;!V020\n", {}},
  {"V021_HalfPitchOnSwg_Fails", "swg091n2", kSwgHeader, "rack 0.5 ;!V021\nrack -0.5 ;!V021\n", {}},
  {"V021_QuarterPitchOnSwg_Passes", "swg091n2", kSwgHeader, "rack 0.25\nrack -0.75\nrack 1.25\nrack 0\n", {}},
  {"V021_ThreeQuarterOnKniterate_Fails", "kniterate", kKniterateHeader, "rack 0.75 ;!V021\n", {}},
  {"V021_HalfPitchOnKniterate_Passes", "kniterate", kKniterateHeader, "rack 0.5\nrack 0\n", {}},

  // Needles, beds and sliders.
  {"V030_ProgramWiderThanBed_Fails", "swg091n2", kSwgHeader,
   "in 3\ntuck + f0 3\ntuck + f540 3 ;!V030\nout 3\n", {}},
  {"V030_ProgramAsWideAsBed_Passes", "swg091n2", kSwgHeader,
   "in 3\ntuck + f0 3\ntuck + f539 3 ;!V054\nout 3\n", {}},
  {"V030_KniterateBedIs252_Fails", "kniterate", kKniterateHeader,
   "in 3\ntuck + f-10 3\ntuck + f242 3 ;!V030\nout 3\n", {}},
  {"V031_SliderOnKniterate_Fails", "kniterate", kKniterateHeader,
   "in 3\ntuck + f1 3\nxfer f1 bs1 ;!V031\nout 3\n", {}},
  {"V031_SliderOnSwg_Passes", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nxfer f1 bs1\nxfer bs1 f1\nout 3\n", {}},
  {"V032_TuckOnSlider_Fails", "swg091n2", kSwgHeader, "in 3\ntuck + fs1 3 ;!V032\nout 3\n", {}},
  {"V032_DropOnSlider_Fails", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nxfer f1 bs1\ndrop bs1 ;!V032\nxfer bs1 f1\nout 3\n", {}},
  {"V032_TuckOnNeedle_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nout 3\n", {}},
  {"V033_SliderToSlider_Fails", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nxfer f1 bs1\nxfer bs1 fs1 ;!V033\nxfer bs1 f1\nout 3\n", {}},
  {"V033_SliderToNeedle_Passes", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nxfer f1 bs1\nxfer bs1 f1\nout 3\n", {}},
  {"V034_SplitFromSlider_Fails", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nxfer f1 bs1\nsplit + bs1 f1 3 ;!V034\nxfer bs1 f1\nout 3\n", {}},
  {"V034_SplitFromNeedle_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nsplit + f1 b1 3\nout 3\n", {}},
  {"V035_XferOnOneBed_Fails", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nxfer f1 f2 ;!V035\nxfer f1 fs1 ;!V035\nout 3\n", {}},
  {"V035_XferAcrossBeds_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nxfer f1 b1\nout 3\n", {}},
  {"V036_XferNotAligned_Fails", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nxfer f1 b2 ;!V036\nrack 0.25\nxfer f1 b1 ;!V036\nrack 0\nout 3\n", {}},
  {"V036_XferAlignedAtRacking_Passes", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nrack -1\nxfer f1 b2\nrack 0\nout 3\n", {}},
  {"V037_TooManyLoops_Fails", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\ntuck + f1 3\ntuck + f1 3\ntuck + f1 3\ntuck + f1 3 ;!V037\nout 3\n", {}},
  {"V037_AsManyLoopsAsAllowed_Passes", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\ntuck + f1 3\ntuck + f1 3\ntuck + f1 3\nout 3\n", {}},
  {"V037_XferOntoFullNeedle_Fails", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\ntuck + f1 3\ntuck + f1 3\ntuck + b1 3\ntuck + b1 3\nxfer b1 f1 ;!V037\nout 3\n", {}},

  // Operations and settings.
  {"V040_MissWithoutCarriers_Fails", "swg091n2", kSwgHeader, "miss + f1 ;!V040\n", {}},
  {"V040_MissWithCarriers_Passes", "swg091n2", kSwgHeader, "in 3\nmiss + f1 3\nout 3\n", {}},
  {"V041_FractionalStitch_Fails", "swg091n2", kSwgHeader, "stitch 5.5 10 ;!V041\nstitch -1 10 ;!V041\n", {}},
  {"V041_WholeStitch_Passes", "swg091n2", kSwgHeader, "stitch 5 10\n", {}},
  {"V041_FractionalStitchOnGeneric_Passes", "generic", kGenericHeader, "stitch 5.5 10\n", {}},
  {"V042_SpeedAboveRange_Fails", "swg091n2", kSwgHeader,
   "x-speed-number 16 ;!V042\nx-sub-roller-number 32 ;!V042\n", {}},
  {"V042_SpeedWithinRange_Passes", "swg091n2", kSwgHeader, "x-speed-number 15\nx-sub-roller-number 31\n", {}},

  // Loops.
  {"V050_KnitOnEmptyNeedle_Warns", "swg091n2", kSwgHeader, "in 3\nknit + f1 3 ;!V050\nout 3\n", {}},
  {"V050_KnitOnLoop_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nknit - f1 3\nout 3\n", {}},
  {"V051_XferFromEmptyNeedle_Warns", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nxfer f2 b2 ;!V051\nsplit + f3 b3 3 ;!V051\nout 3\n", {}},
  {"V051_XferOfLoop_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nxfer f1 b1\nout 3\n", {}},
  {"V052_DropOnEmptyNeedle_Warns", "swg091n2", kSwgHeader, "drop f1 ;!V052\namiss f2 ;!V052\n", {}},
  {"V052_DropOfTuckLoop_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\namiss f1\nout 3\ndrop f1\n", {}},
  {"V053_DropOfLooseStitch_Warns", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nknit - f1 3\nout 3\ndrop f1 ;!V053\n", {}},
  {"V053_DropOfHeldLoop_Passes", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nknit - f1 3\nsplit + f1 b1 3\nout 3\ndrop b1\n", {}},
  {"V054_LongFloat_Warns", "swg091n2", kSwgHeader, "in 3\ntuck + f0 3\ntuck + f25 3 ;!V054\nout 3\n", {}},
  {"V054_FloatAtThreshold_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f0 3\ntuck + f24 3\nout 3\n", {}},
  {"V054_FloatOnKniterateAbove12_Warns", "kniterate", kKniterateHeader,
   "in 3\ntuck + f0 3\ntuck + f13 3 ;!V054\nout 3\n", {}},
  {"V055_LoopsLeftOnSlider_Warns", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nxfer f1 bs1\nout 3 ;!V055\n", {}},
  {"V055_LoopsReturnedFromSlider_Passes", "swg091n2", kSwgHeader,
   "in 3\ntuck + f1 3\nxfer f1 bs1\nxfer bs1 f1\nout 3\n", {}},

  // Pauses.
  {"V060_PauseTwice_Warns", "swg091n2", kSwgHeader, "pause\npause ;!V060\nin 3\ntuck + f1 3\nout 3\n", {}},
  {"V060_PausesApart_Passes", "swg091n2", kSwgHeader, "pause\nin 3\ntuck + f1 3\npause\nout 3\n", {}},
  {"V061_PauseAtEnd_Warns", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nout 3\npause ;!V061\n", {}},
  {"V061_PauseBeforeLastOperation_Passes", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\npause\nout 3\n", {}},

  // Headers.
  {"V070_GaugeNotANumber_Fails", "swg091n2", ";!knitout-2\n;;Carriers: 1 2 3\n;;Gauge: fifteen\n", "", {"3:V070"}},
  {"V070_GaugeNumber_Passes", "swg091n2", ";!knitout-2\n;;Carriers: 1 2 3\n;;Gauge: 15\n", "", {}},
  {"V071_GaugeOfOtherMachine_Warns", "swg091n2", ";!knitout-2\n;;Carriers: 1 2 3\n;;Gauge: 7\n", "", {"3:V071"}},
  {"V071_GaugeOfKniterate_Passes", "kniterate", ";!knitout-2\n;;Carriers: 1 2 3\n;;Gauge: 7\n", "", {}},
  {"V072_PositionUnknown_Fails", "swg091n2", ";!knitout-2\n;;Carriers: 1 2 3\n;;Position: Middle\n", "", {"3:V072"}},
  {"V072_PositionKnown_Passes", "swg091n2", ";!knitout-2\n;;Carriers: 1 2 3\n;;Position: Keep\n", "", {}},
  {"V073_MachineHeaderOfOtherMachine_Warns", "swg091n2", ";!knitout-2\n;;Machine: Kniterate\n;;Carriers: 1 2 3\n", "", {"2:V073"}},
  {"V073_MachineHeaderMatches_Passes", "kniterate", ";!knitout-2\n;;Machine: Kniterate\n;;Carriers: 1 2 3\n", "", {}},

  // Syntax problems reach validate's output too (parser codes).
  {"K012_BadDirection_Fails", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nknit x f1 3 ;!K012\nout 3\n", {}},
  {"K013_MissingNeedle_Fails", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nknit + ;!K013\nout 3\n", {}},
  {"K014_XferWithCarrier_Fails", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nxfer f1 b1 3 ;!K014\nout 3\n", {}},
  {"K014_DropWithCarrier_Fails", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\ndrop f1 3 ;!K014\nout 3\n", {}},
  {"K010_UnknownOperation_Fails", "swg091n2", kSwgHeader, "knot + f1 3 ;!K010\n", {}},
  {"K0xx_WellFormedLines_Pass", "swg091n2", kSwgHeader, "in 3\ntuck + f1 3\nknit - f1 3\nxfer f1 b1\nout 3\n", {}},
};
// clang-format on

INSTANTIATE_TEST_SUITE_P(Rules, RuleTest, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<Case>& param_info) {
                           return std::string(param_info.param.name);
                         });

// ----------------------------------------------------------- exact messages

TEST(MachineTest, ReportsInactiveCarrierWithExactText) {
  const Outcome r = run(std::string(kSwgHeader) + "knit - f1 3\nknit + f1 3\n");
  ASSERT_EQ(r.diagnostics.size(), 2u);
  EXPECT_EQ(knitout::format(r.diagnostics[0]),
            "t.k:5: error: [V004] carrier '3' is not in; bring it in with in or inhook before "
            "using it");
  // Reported once: the machine carries on as if the carrier were in.
  EXPECT_EQ(r.diagnostics[1].code, "V050");
}

TEST(MachineTest, ExplainsReleasehookBeforeFirstStitch) {
  const Outcome r = run(std::string(kSwgHeader) + "inhook 3\nreleasehook 3\n");
  ASSERT_GE(r.diagnostics.size(), 1u);
  EXPECT_EQ(knitout::format(r.diagnostics[0]),
            "t.k:5: error: [V013] carrier '3' brought in here is still in at the end of the "
            "program (line 6); take it out with out or outhook");
  EXPECT_EQ(knitout::format(r.diagnostics[1]),
            "t.k:6: error: [V007] releasehook 3: the hook holds nothing; carrier '3' (inhook at "
            "line 5) has not stitched yet: the hook takes its yarn at the first stitch");
}

TEST(MachineTest, SuggestsTheProfileTheMachineHeaderNames) {
  const Outcome r = run(";!knitout-2\n;;Machine: Kniterate\n;;Carriers: 1 2 3\n");
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_EQ(knitout::format(r.diagnostics[0]),
            "t.k:2: warning: [V073] file is for machine 'Kniterate' but is validated on swg091n2 "
            "(--machine kniterate validates on it)");
  const Outcome other = run(";!knitout-2\n;;Machine: SWG061N2\n;;Carriers: 1 2 3\n");
  ASSERT_EQ(other.diagnostics.size(), 1u);
  EXPECT_EQ(other.diagnostics[0].message,
            "file is for machine 'SWG061N2' but is validated on swg091n2 (--machine picks "
            "another profile)");
}

TEST(MachineTest, NamesMisalignedNeedlesAndWhatFacesThem) {
  const Outcome r = run(std::string(kSwgHeader) + "in 3\ntuck + f1 3\nrack 1\nxfer f1 b1\nout 3\n");
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_EQ(knitout::format(r.diagnostics[0]),
            "t.k:8: error: [V036] xfer f1 b1: the needles are not aligned at racking 1; f1 "
            "faces b0 here");
}

TEST(MachineTest, ReportsARunOfUnravellingDropsOnce) {
  const Outcome r = run(std::string(kSwgHeader) +
                        "in 3\ntuck + f1 3\ntuck + f2 3\nknit - f2 3\nknit - f1 3\nout 3\n"
                        "drop f1\ndrop f2\n");
  ASSERT_EQ(r.diagnostics.size(), 1u);
  EXPECT_EQ(knitout::format(r.diagnostics[0]),
            "t.k:11: warning: [V053] the drops of lines 11-12 let go of 2 loops that hold "
            "stitches but that nothing holds: the fabric can unravel from here (bind off first "
            "if it must not)");
}

TEST(MachineTest, SummarisesRepeatedWarningsAfterTheCap) {
  MachineOptions options;
  options.max_repeats = 2;
  const Outcome r =
      run(std::string(kSwgHeader) + "drop f1\ndrop f2\ndrop f3\ndrop f4\n", "swg091n2", options);
  EXPECT_THAT(found(r.diagnostics), ElementsAre("0:V099", "5:V052", "6:V052"));
  EXPECT_EQ(r.diagnostics[0].message, "2 more V052 warnings not shown (the first 2 are)");
  options.max_repeats = 0;
  const Outcome all =
      run(std::string(kSwgHeader) + "drop f1\ndrop f2\ndrop f3\ndrop f4\n", "swg091n2", options);
  EXPECT_EQ(all.diagnostics.size(), 4u);
}

TEST(MachineTest, KnitoutWithoutMagicOrCarriersHeaderStillRuns) {
  // Header-less files are valid knitout (the parser warns): carriers are
  // named by their first use and must exist on the machine.
  const Outcome r = run("inhook 2\ntuck + f1 2\nreleasehook 2\nouthook 2\n");
  EXPECT_THAT(found(r.diagnostics), UnorderedElementsAre("1:K001", "1:K032"));
  EXPECT_EQ(r.stats.errors, 0u);
  // A carrier the machine lacks is reported where it comes in and where it
  // is used; the hook never took it, so releasing it is wrong too.
  const Outcome bad = run("inhook A\ntuck + f1 A\nreleasehook A\nouthook A\n");
  EXPECT_THAT(found(bad.diagnostics),
              UnorderedElementsAre("1:K032", "1:K001", "1:V001", "2:V001", "3:V007"));
}

// ----------------------------------------------------------- machine state

TEST(MachineTest, CarriersFollowTheirLoopsAcrossTransfers) {
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(
      std::string(kSwgHeader) + "in 3\nknit + f5 3\nxfer f5 b5\n", "t.k", sink);
  Machine machine(default_profile(), sink, "t.k", program.carriers, 10);
  for (const auto& instruction : program.instructions) machine.step(instruction);
  const auto id = *program.carriers.find("3");
  // knitout spec: after xfer f5 b5, a carrier that sat at f5 sits at b5.
  EXPECT_EQ(machine.carrier(id).needle, (knitout::Needle{knitout::Bed::Back, 5}));
  EXPECT_EQ(machine.carrier(id).side, knitout::Direction::Plus);
  ASSERT_EQ(machine.loops_on({knitout::Bed::Back, 5}).size(), 1u);
  EXPECT_TRUE(machine.loops_on({knitout::Bed::Front, 5}).empty());
}

TEST(MachineTest, KnitPullsTheNewLoopThroughTheStack) {
  knitout::DiagnosticSink sink;
  const knitout::Program program = knitout::parse_string(
      std::string(kSwgHeader) + "in 3\ntuck + f1 3\ntuck - f1 3\nknit + f1 3\n", "t.k", sink);
  Machine machine(default_profile(), sink, "t.k", program.carriers, 10);
  for (const auto& instruction : program.instructions) machine.step(instruction);
  const auto loops = machine.loops_on({knitout::Bed::Front, 1});
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].id, 2u);
  EXPECT_TRUE(loops[0].has_parents);
}

TEST(MachineTest, CountsStatistics) {
  const Outcome r = run(std::string(kSwgHeader) +
                        "inhook 3\ntuck - f4 3\ntuck - f2 3\ntuck + f1 3\ntuck + f3 3\n"
                        "releasehook 3\nknit - f4 3\nknit - f3 3\nknit - f2 3\nknit - f1 3\n"
                        "rack 1\nrack 0\nxfer f1 b1\nxfer f2 b2\nxfer f3 b3\nknit + b1 3\n"
                        "knit + b2 3\nknit + b3 3\nknit + f4 3\nouthook 3\n");
  EXPECT_EQ(r.stats.errors, 0u);
  const Stats& s = r.stats;
  EXPECT_EQ(s.instructions, 20u);
  EXPECT_EQ(s.by_op[static_cast<std::size_t>(knitout::Op::Knit)], 8u);
  EXPECT_EQ(s.by_op[static_cast<std::size_t>(knitout::Op::Tuck)], 4u);
  EXPECT_EQ(s.loops_made, 12u);
  EXPECT_EQ(s.transfers, 3u);
  EXPECT_EQ(s.loops_transferred, 3u);
  EXPECT_EQ(s.racks, 2u);
  EXPECT_EQ(s.largest_stack, 1);
  EXPECT_EQ(s.bed_span(), 4);
  ASSERT_EQ(s.carriers.size(), 1u);
  EXPECT_EQ(s.carriers[0].name, "3");
  EXPECT_EQ(s.carriers[0].loops, 12u);
  // Floats between consecutive loops: 2+1+2 (cast-on), 1+1+1+1 (row), then
  // 0+1+1+1: the carrier sat at f1 and moved to b1 with the transfer.
  EXPECT_DOUBLE_EQ(s.carriers[0].float_pitches, 12.0);
  // Sweeps: cast-on left, cast-on right, row left, transfers, row right.
  EXPECT_EQ(s.knit_sweeps, 4u);
  EXPECT_EQ(s.transfer_sweeps, 1u);
  EXPECT_FALSE(s.dat_passes.has_value());
  EXPECT_GT(s.estimated_time_s, 0.0);
}

TEST(MachineTest, EstimatedTimeFollowsTheDocumentedModel) {
  const Outcome r = run(std::string(kSwgHeader) + "in 3\ntuck + f0 3\ntuck + f9 3\nout 3\n");
  // One knit sweep over 10 needles + 2 x 20 overrun at 25.4/15 mm per needle,
  // 0.8 m/s, plus 0.5 s turnaround (docs/vm.md).
  const double expected = 50 * (25.4 / 15.0) / 1000.0 / 0.8 + 0.5;
  EXPECT_NEAR(r.stats.estimated_time_s, expected, 1e-9);
  EXPECT_EQ(r.stats.sweeps, 1u);
}

TEST(MachineTest, ValidateOfProgramMatchesStreaming) {
  const std::string text = std::string(kSwgHeader) +
                           "inhook 3\ntuck + f1 3\nknit - f1 3\nreleasehook 3\nin 4\n"
                           "knit + f2 4\nxfer f2 b3\nouthook 3\nout 4\n";
  knitout::DiagnosticSink parse_sink;
  const knitout::Program program = knitout::parse_string(text, "t.k", parse_sink);
  knitout::DiagnosticSink sink;
  const Stats from_program = validate(program, default_profile(), sink, "t.k");
  const Outcome streamed = run(text);
  EXPECT_EQ(found(sink.sorted()), found(streamed.diagnostics));
  EXPECT_EQ(found(sink.sorted()), std::vector<std::string>({"10:V050", "11:V036"}));
  EXPECT_EQ(from_program.loops_made, streamed.stats.loops_made);
  EXPECT_EQ(from_program.sweeps, streamed.stats.sweeps);
}

// Profiles are data: a profile built in the test changes the verdicts.
std::vector<std::string> run_on(const MachineProfile& profile, const std::string& body) {
  knitout::DiagnosticSink sink;
  std::istringstream in(std::string(kSwgHeader) + body);
  validate_stream(in, "t.k", profile, sink);
  return found(sink.sorted());
}

TEST(ProfileTest, InhookNeedsAHookOnTheMachine) {
  MachineProfile no_hook = default_profile();
  no_hook.has_inserting_hook = false;
  const std::string body = "inhook 3\ntuck + f1 3\nreleasehook 3\nouthook 3\n";
  EXPECT_THAT(run_on(no_hook, body), ElementsAre("5:V015"));
  EXPECT_THAT(run_on(default_profile(), body), ElementsAre());
  EXPECT_THAT(run_on(no_hook, "in 3\ntuck + f1 3\nout 3\n"), ElementsAre());
}

TEST(ProfileTest, LimitsComeFromTheProfile) {
  MachineProfile small = default_profile();
  small.needle_count = 10;
  small.max_loops_per_needle = 1;
  small.long_float_needles = 3;
  const std::string body = "in 3\ntuck + f0 3\ntuck + f4 3\ntuck + f4 3\ntuck + f10 3\nout 3\n";
  EXPECT_THAT(run_on(small, body), ElementsAre("7:V054", "8:V037", "9:V030"));
  EXPECT_THAT(run_on(default_profile(), body), ElementsAre());
}

TEST(ProfileTest, KnowsTheBuiltInMachines) {
  EXPECT_EQ(profile_names(), "swg091n2, kniterate, generic");
  EXPECT_EQ(default_profile().name, "swg091n2");
  EXPECT_EQ(find_profile("nope"), nullptr);
  const MachineProfile* swg = find_profile("swg091n2");
  ASSERT_NE(swg, nullptr);
  EXPECT_EQ(swg->needle_count, 540);
  EXPECT_TRUE(swg->carrier_exists("10"));
  EXPECT_FALSE(swg->carrier_exists("11"));
  EXPECT_TRUE(find_profile("generic")->carrier_exists("L1"));
}

}  // namespace
}  // namespace bed

namespace bed {
namespace {

// The project's own generated sheets (used by demo and the benchmarks) are
// valid knitout for the default machine.
TEST(MachineTest, GeneratedSheetsValidate) {
  for (auto pattern : {knitout::SheetPattern::Plain, knitout::SheetPattern::Seed}) {
    knitout::SheetParams params;
    params.width_needles = 30;
    params.rows = 12;
    params.pattern = pattern;
    const Outcome r = run(knitout::sheet_text(params));
    EXPECT_EQ(r.stats.errors, 0u);
    // The only finding: the last course is dropped off without a bind-off.
    EXPECT_THAT(found(r.diagnostics), ElementsAre(::testing::EndsWith(":V053")));
    EXPECT_EQ(r.stats.largest_stack, 1);
  }
}

TEST(MachineTest, ExtremeNeedlesAndRackingsAreReportedNotOverflowed) {
  const std::string body =
      "in 3\nrack 1000000000000\ntuck + b2147483647 3\ntuck + f-2147483648 3\n"
      "tuck + b-2147483648 3\nrack 0\nout 3\n";
  for (const char* machine : {"swg091n2", "generic"}) {
    const Outcome r = run(std::string(kGenericHeader) + body, machine);
    EXPECT_GT(r.stats.errors, 0u) << machine;
  }
  const Outcome generic = run(std::string(kGenericHeader) + body, "generic");
  // generic has no bed width: the float is long, and b-2147483648 is too far from b2147483647.
  EXPECT_THAT(found(generic.diagnostics), ElementsAre("6:V054", "7:V030"));
}

// Random instruction soup (fixed seed): the machine reports, never crashes,
// and is deterministic.
TEST(MachineTest, SurvivesRandomProgramsDeterministically) {
  std::uint32_t state = 12345;
  auto next = [&](std::uint32_t n) {
    state = state * 1664525u + 1013904223u;
    return (state >> 8) % n;
  };
  const char* ops[] = {"in",   "inhook", "releasehook", "out",   "outhook",
                       "knit", "tuck",   "split",       "drop",  "amiss",
                       "xfer", "miss",   "rack",        "pause", "stitch"};
  const char* beds[] = {"f", "b", "fs", "bs"};
  std::string text = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n";
  for (int i = 0; i < 3000; ++i) {
    const std::string op = ops[next(15)];
    auto needle = [&] {
      return std::string(beds[next(4)]) + std::to_string(static_cast<int>(next(700)) - 50);
    };
    const std::string carrier = std::to_string(1 + next(10));
    const std::string dir = next(2) ? "+" : "-";
    if (op == "in" || op == "inhook" || op == "releasehook" || op == "out" || op == "outhook") {
      text += op + " " + carrier + "\n";
    } else if (op == "knit" || op == "tuck" || op == "miss") {
      text += op + " " + dir + " " + needle() + " " + carrier + "\n";
    } else if (op == "split") {
      text += op + " " + dir + " " + needle() + " " + needle() + " " + carrier + "\n";
    } else if (op == "xfer") {
      text += op + " " + needle() + " " + needle() + "\n";
    } else if (op == "drop" || op == "amiss") {
      text += op + " " + needle() + "\n";
    } else if (op == "rack") {
      text +=
          "rack " + std::to_string(static_cast<int>(next(40)) - 20) + (next(4) ? "" : ".25") + "\n";
    } else if (op == "stitch") {
      text += "stitch " + std::to_string(next(10)) + " " + std::to_string(next(20)) + "\n";
    } else {
      text += op + "\n";
    }
  }
  for (const char* machine : {"swg091n2", "kniterate", "generic"}) {
    MachineOptions options;
    options.max_repeats = 0;
    auto once = [&](Stats& stats) {
      knitout::DiagnosticSink sink(1000000);  // no cap: run every line
      std::istringstream in(text);
      stats = validate_stream(in, "t.k", *find_profile(machine), sink, options);
      return found(sink.sorted());
    };
    Stats first;
    Stats second;
    const auto a = once(first);
    const auto b = once(second);
    EXPECT_EQ(a, b) << machine;
    EXPECT_GT(first.errors, 100u) << machine;
    EXPECT_EQ(first.lines, 3002u) << machine;
    EXPECT_EQ(first.instructions, 3000u) << machine;
  }
}

}  // namespace
}  // namespace bed
