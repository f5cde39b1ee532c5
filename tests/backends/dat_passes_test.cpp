// Pass formation and the checks of the DAT backend, on small programs. Each
// accept/reject decision here is the one knitout-to-dat.js makes on the
// same program; where it crashes, the backend gives a clear error.
#include <gtest/gtest.h>

#include <random>

#include "backends/dat/passes.hpp"
#include "backends/dat/raster.hpp"
#include "backends/dat/reader.hpp"
#include "knitout/parser.hpp"

namespace dat {
namespace {

using knitout::Direction;

const std::string kHead = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\n";

struct Result {
  std::optional<PassList> passes;
  std::optional<std::vector<std::uint8_t>> bytes;
  knitout::DiagnosticSink sink;

  std::string first_error() const {
    for (const auto& d : sink.diagnostics()) {
      if (d.severity == knitout::Severity::Error) return knitout::format(d);
    }
    return "";
  }
};

// Streams `body` (after the standard header) through the backend.
void run(const std::string& body, Result& result, const std::string& head = kHead) {
  std::istringstream in(head + body);
  result.passes = form_passes(in, "t.k", result.sink);
  if (result.passes) result.bytes = write_dat(*result.passes, result.sink);
}

std::vector<std::uint8_t> colours(const PassList& list, const Pass& pass) {
  std::vector<std::uint8_t> out;
  for (const SlotEntry& entry : list.slots(pass)) out.push_back(slot_op_colour(entry.op));
  return out;
}

TEST(DatPassesTest, MergesARowOfKnitsIntoOnePass) {
  Result r;
  run("inhook 3\nknit + f1 3\nknit + f2 3\nknit + f3 3\nknit - f3 3\nknit - f2 3\n"
      "releasehook 3\nknit + f2 3\noutgoing\n",
      r);
  // `outgoing` is not an operation: the parser rejects the line.
  EXPECT_EQ(r.first_error(), "t.k:11:1: error: [K010] unknown operation 'outgoing'");
  Result ok;
  run("inhook 3\nknit + f1 3\nknit + f2 3\nknit + f3 3\nknit - f3 3\nknit - f2 3\n"
      "releasehook 3\nknit + f2 3\nouthook 3\n",
      ok);
  ASSERT_TRUE(ok.bytes.has_value()) << ok.first_error();
  const PassList& list = *ok.passes;
  ASSERT_EQ(list.passes.size(), 4u);
  const Pass& first = list.passes[0];
  EXPECT_EQ(first.direction, Direction::Plus);
  EXPECT_EQ(first.entry_count, 3u);
  EXPECT_EQ(first.hook, Hook::In);
  EXPECT_EQ(first.gripper, Gripper::In);
  EXPECT_EQ(colours(list, first), (std::vector<std::uint8_t>{51, 51, 51}));
  EXPECT_EQ(list.passes[1].direction, Direction::Minus);
  EXPECT_EQ(list.passes[1].entry_count, 2u);
  // The release gets a pass of its own, without carriers, in the direction
  // the hooked carrier first went.
  EXPECT_EQ(list.passes[2].hook, Hook::Release);
  EXPECT_EQ(list.passes[2].direction, Direction::Plus);
  EXPECT_TRUE(list.passes[2].carriers.empty());
  // The last knit and the carrier's way out share a pass.
  EXPECT_EQ(list.passes[3].direction, Direction::Plus);
  EXPECT_EQ(list.passes[3].entry_count, 1u);
  EXPECT_EQ(list.passes[3].gripper, Gripper::Out);
  EXPECT_EQ(list.passes[3].hook, Hook::Out);
}

TEST(DatPassesTest, ReleaseAfterAPassTheSameWayFollowsAnEmptyOppositePass) {
  Result r;
  run("inhook 3\nknit + f1 3\nknit + f2 3\nreleasehook 3\nknit - f2 3\nouthook 3\n", r);
  ASSERT_TRUE(r.bytes.has_value()) << r.first_error();
  const PassList& list = *r.passes;
  ASSERT_GE(list.passes.size(), 3u);
  // KnitPaint refuses a release on a carriage-move row.
  EXPECT_EQ(list.passes[1].direction, Direction::Minus);
  EXPECT_EQ(list.passes[1].hook, Hook::None);
  EXPECT_TRUE(list.passes[1].carriers.empty());
  EXPECT_EQ(colours(list, list.passes[1]), (std::vector<std::uint8_t>{16}));
  EXPECT_EQ(list.passes[2].direction, Direction::Plus);
  EXPECT_EQ(list.passes[2].hook, Hook::Release);
}

TEST(DatPassesTest, OwnCarrierIsKickedToTheSideItMustStartFrom) {
  Result r;
  run("in 3\nknit + f1 3\nknit + f2 3\nknit + f5 3\nout 3\n", r);
  ASSERT_TRUE(r.bytes.has_value()) << r.first_error();
  const PassList& list = *r.passes;
  // The carrier ends right of f5 after a rightward pass. `out` leaves with
  // a rightward move, and the carrier may have stopped anywhere right of f5,
  // so it is first brought back left of f5 (a soft miss, colour 16).
  ASSERT_EQ(list.passes.size(), 3u);
  EXPECT_EQ(list.passes[0].entry_count, 3u);
  EXPECT_EQ(list.passes[0].gripper, Gripper::In);
  const Pass& kick = list.passes[1];
  EXPECT_EQ(kick.direction, Direction::Minus);
  EXPECT_EQ(to_string(kick.carriers), "3");
  EXPECT_EQ(colours(list, kick), (std::vector<std::uint8_t>{16}));
  EXPECT_EQ(list.slots(kick)[0].slot, 5);
  EXPECT_EQ(list.passes[2].direction, Direction::Plus);
  EXPECT_EQ(list.passes[2].gripper, Gripper::Out);
}

TEST(DatPassesTest, OtherCarriersAreKickedOutOfTheWay) {
  Result r;
  run("in 3\nin 4\nknit + f1 3\nknit + f2 3\nknit + f1 4\nknit + f2 4\nknit + f3 4\n"
      "knit + f4 3\nout 3\nout 4\n",
      r);
  ASSERT_TRUE(r.bytes.has_value()) << r.first_error();
  const PassList& list = *r.passes;
  // Before carrier 3 knits f4, carrier 4 (hanging right of f3) is moved
  // left of f3 on a pass of its own.
  auto knit_f4 = std::find_if(list.passes.begin(), list.passes.end(), [&](const Pass& pass) {
    return to_string(pass.carriers) == "3" && list.slots(pass)[0].slot == 4 &&
           list.slots(pass)[0].op == SlotOp::KnitFront;
  });
  ASSERT_NE(knit_f4, list.passes.end());
  ASSERT_NE(knit_f4, list.passes.begin());
  const Pass& kick = *(knit_f4 - 1);
  EXPECT_EQ(to_string(kick.carriers), "4");
  EXPECT_EQ(kick.direction, Direction::Minus);
  EXPECT_EQ(list.slots(kick)[0].slot, 3);
  EXPECT_EQ(list.slots(kick)[0].op, SlotOp::SoftMiss);
  EXPECT_EQ(kick.line, 10u);
}

TEST(DatPassesTest, QuarterPitchCombinesFrontAndBackInOneSlot) {
  Result r;
  run("in 3\nrack 0.25\nknit + f1 3\nknit + b1 3\nknit + f2 3\nrack 0\nout 3\n", r);
  ASSERT_TRUE(r.bytes.has_value()) << r.first_error();
  const PassList& list = *r.passes;
  EXPECT_EQ(colours(list, list.passes[0]), (std::vector<std::uint8_t>{3, 51}));
  Result aligned;
  run("in 3\nknit + f1 3\nknit + b1 3\nout 3\n", aligned);
  ASSERT_TRUE(aligned.bytes.has_value()) << aligned.first_error();
  // At whole racking f1 and b1 share a slot but cannot share a pass.
  EXPECT_EQ(colours(*aligned.passes, aligned.passes->passes[0]), (std::vector<std::uint8_t>{51}));
}

TEST(DatPassesTest, TransfersMergeInAnyOrderAndBackNeedlesFollowRacking) {
  Result r;
  run("in 3\nknit + f1 3\nknit + f2 3\nknit + f3 3\nxfer f3 b3\nxfer f1 b1\nrack 1\n"
      "xfer b1 f2\nrack 0\nknit - f3 3\nout 3\n",
      r);
  ASSERT_TRUE(r.bytes.has_value()) << r.first_error();
  const PassList& list = *r.passes;
  const Pass& xfers = list.passes[1];
  EXPECT_EQ(xfers.type, PassType::Xfer);
  EXPECT_EQ(xfers.direction, Direction::None);
  EXPECT_EQ(xfers.entry_count, 2u);
  const Pass& racked = list.passes[2];
  EXPECT_EQ(racked.racking, 1);
  EXPECT_EQ(list.slots(racked)[0].slot, 2);  // b1 + floor(1)
  EXPECT_EQ(colours(list, racked), (std::vector<std::uint8_t>{30}));
}

TEST(DatPassesTest, ThreeCarriersInOnePassIsAClearError) {
  Result r;
  run("in 1 2 3\nknit + f1 1 2 3\nout 1 2 3\n", r);
  EXPECT_FALSE(r.bytes.has_value());
  EXPECT_EQ(r.first_error(),
            "t.k:4: error: [D025] a pass with 3 carriers (1 2 3): the DAT yarn-carrier option "
            "notates at most two carriers per pass");
}

TEST(DatPassesTest, TwoCarriersAreNotatedByTheirDigits) {
  Result r;
  run("in 10 5\nknit + f1 10 5\nout 10 5\nin 5 10\nknit + f1 5 10\nout 5 10\nin 1 10\n"
      "knit + f1 1 10\nout 1 10\n",
      r);
  ASSERT_TRUE(r.bytes.has_value()) << r.first_error();
  std::vector<std::int64_t> codes;
  for (const Pass& pass : r.passes->passes) {
    if (pass.gripper == Gripper::In) codes.push_back(carrier_code(pass));
  }
  EXPECT_EQ(codes, (std::vector<std::int64_t>{15, 50, 110}));
}

TEST(DatPassesTest, FirstUseMustMatchTheInSet) {
  Result r;
  run("in 3 4\nknit + f1 3\nout 3 4\n", r);
  EXPECT_EQ(r.first_error(),
            "t.k:4: error: [D012] first use of carriers 3 does not match the set brought in "
            "together: 3 4");
}

TEST(DatPassesTest, OutBeforeReleasehookIsRejected) {
  Result r;
  run("inhook 3\nknit + f1 3\nout 3\n", r);
  EXPECT_EQ(r.first_error(),
            "t.k:5: error: [D017] out 3: the carrier came in with inhook and the hook still "
            "holds it; releasehook first, or use outhook");
  Result ok;
  run("inhook 3\nknit + f1 3\nreleasehook 3\nout 3\n", ok);
  EXPECT_TRUE(ok.bytes.has_value()) << ok.first_error();
}

TEST(DatPassesTest, MisalignedTransferIsRejected) {
  Result r;
  run("in 3\nknit + f1 3\nrack 1\nxfer f1 b1\nout 3\n", r);
  EXPECT_EQ(r.first_error(),
            "t.k:6: error: [D022] needles f1 and b1 do not face each other at racking 1");
}

TEST(DatPassesTest, RackingBeyondEightIsRejectedOnlyWhenAPassUsesIt) {
  Result r;
  run("in 3\nknit + f1 3\nrack 9\nxfer f10 b1\nrack 0\nout 3\n", r);
  EXPECT_EQ(r.first_error(), "t.k:6: error: [D021] racking 9 is beyond the machine's range -8..8");
  Result ok;
  run("in 3\nknit + f1 3\nrack 9\nrack 0\nout 3\n", ok);
  EXPECT_TRUE(ok.bytes.has_value()) << ok.first_error();
}

TEST(DatPassesTest, HalfRackingIsRejected) {
  Result r;
  run("rack 0.5\n", r);
  EXPECT_EQ(r.first_error(),
            "t.k:3: error: [D020] racking 0.5 is neither whole nor whole + 0.25 (quarter pitch)");
  Result ok;
  run("in 3\nrack -0.75\nknit + f1 3\nrack 0\nout 3\n", ok);
  EXPECT_TRUE(ok.bytes.has_value()) << ok.first_error();
}

TEST(DatPassesTest, SliderToSliderIsRejected) {
  Result r;
  run("xfer fs1 bs1\n", r);
  EXPECT_EQ(r.first_error(),
            "t.k:3: error: [D026] cannot move loops from slider fs1 to slider bs1");
}

TEST(DatPassesTest, SplitViaSlidersMustBeReturned) {
  Result ok;
  run("in 3\nknit + f1 3\nsplit + f1 bs1 3\nrack 1\nxfer bs1 f2\nrack 0\nout 3\n", ok);
  ASSERT_TRUE(ok.bytes.has_value()) << ok.first_error();
  const PassList& list = *ok.passes;
  const Pass& split = list.passes[2];  // after a kick to the left of f1
  EXPECT_EQ(split.type, PassType::SplitViaSliders);
  EXPECT_TRUE(split.has_return_racking);
  EXPECT_EQ(split_via_sliders_colours(split),
            (std::optional<std::pair<std::uint8_t, std::uint8_t>>{{107, 108}}));
  Result pending;
  run("in 3\nknit + f1 3\nsplit + f1 bs1 3\nknit + f2 3\n", pending);
  EXPECT_EQ(pending.first_error(),
            "t.k:6: error: [D027] 'knit' while split-via-sliders loops wait on the sliders; "
            "return them all with xfer first");
  Result never;
  run("in 3\nknit + f1 3\nsplit + f1 bs1 3\nrack 0\nout 3\n", never);
  EXPECT_EQ(never.first_error(),
            "t.k:7: error: [D027] 'out' while split-via-sliders loops wait on the sliders; "
            "return them all with xfer first");
}

TEST(DatPassesTest, KeepPositionMustFitTheBed) {
  Result r;
  run("in 3\nknit + f0 3\nout 3\n", r, kHead + ";;Position: Keep\n");
  EXPECT_EQ(r.first_error(),
            "t.k:5: error: [D028] Position Keep: needle slots 0..0 lie outside the bed 1..540");
}

// D030 names the first pass that makes the raster too large for a DAT.
TEST(DatPassesTest, ARasterTooLargeNamesTheFirstPassBeyondTheLimit) {
  Result r;
  run("in 3\nknit + f1 3\nknit - f1 3\nknit + f70000 3\nknit - f1 3\nout 3\n", r);
  EXPECT_EQ(r.first_error().rfind("t.k:6: error: [D030] the design needs a ", 0), 0u)
      << r.first_error();
}

TEST(DatPassesTest, PositionCodes) {
  PassList list;
  list.bed_width = 100;
  list.position = Position::Center;
  EXPECT_EQ(position_code(list, 1, 21), 40);  // (100 - 21) / 2 = 39.5 rounds up
  list.position = Position::Keep;
  EXPECT_EQ(position_code(list, 7, 21), 7);
  list.position = Position::Left;
  EXPECT_EQ(position_code(list, 7, 21), 1);
  list.position = Position::Right;
  EXPECT_EQ(position_code(list, 7, 21), 0);
  list.position = Position::Center;
  list.bed_width = 10;
  EXPECT_EQ(position_code(list, 1, 21), -5);  // (10 - 21) / 2 = -5.5 rounds up to -5
}

TEST(DatPassesTest, EmptyProgramIsAClearError) {
  Result r;
  run("; nothing\n", r);
  EXPECT_EQ(r.first_error(),
            "t.k:3: error: [D029] nothing to knit: the program forms no carriage pass");
}

TEST(DatPassesTest, MissingHeadersAndMagicAreRejected) {
  Result magic;
  run("in 3\n", magic, ";;Carriers: 1 2 3 4 5 6 7 8 9 10\n");
  EXPECT_EQ(magic.first_error(),
            "t.k:1: error: [D001] missing magic line ';!knitout-N': the DAT backend only reads "
            "knitout files that start with it");
  Result width;
  run("in 3\n", width, kHead + ";;Width: 0\n");
  EXPECT_EQ(width.first_error(),
            "t.k:3: error: [D005] Width header '0' is not a positive whole number of needles (at "
            "most 999999999)");
  Result spaced;
  run("in 3\nknit + f1 3\nout 3\n", spaced, ";!knitout-2\n;;Carriers: 1 2  3 4 5 6 7 8 9 10\n");
  EXPECT_TRUE(spaced.bytes.has_value()) << spaced.first_error();
}

TEST(DatPassesTest, UnsupportedExtensionsAreWarnedAboutOnce) {
  Result r;
  run("in 3\nx-sub-roller-number 3\nx-sub-roller-number 4\nknit + f1 3\nout 3\n", r);
  ASSERT_TRUE(r.bytes.has_value()) << r.first_error();
  int warnings = 0;
  for (const auto& d : r.sink.diagnostics()) {
    if (d.code == "D031") {
      ++warnings;
      EXPECT_EQ(knitout::format(d),
                "t.k:4: warning: [D031] extension 'x-sub-roller-number' is not supported by "
                "the DAT backend and is ignored (reported once per file)");
    }
  }
  EXPECT_EQ(warnings, 1);
}

TEST(DatPassesTest, CarriagePassesSummariseWhatTheDatHolds) {
  knitout::DiagnosticSink sink;
  const auto program = knitout::parse_string(
      kHead + "in 3\nknit + f1 3\nknit + f2 3\nxfer f1 b1\nxfer f2 b2\nknit - f3 3\nout 3\n", "t.k",
      sink);
  const auto passes = carriage_passes(program, "t.k", sink);
  ASSERT_TRUE(passes.has_value());
  // knits, transfers, two kicks (the carrier went right past f2, the knit
  // at f3 goes left), the knit, the way out.
  ASSERT_EQ(passes->size(), 6u);
  EXPECT_EQ((*passes)[0].direction, Direction::Plus);
  EXPECT_EQ((*passes)[0].carriers, (std::vector<std::string>{"3"}));
  EXPECT_EQ((*passes)[0].slots, 2u);
  EXPECT_EQ((*passes)[0].line, 4u);
  EXPECT_EQ((*passes)[1].type, PassType::Xfer);
  EXPECT_EQ((*passes)[1].direction, Direction::None);
  EXPECT_TRUE((*passes)[1].carriers.empty());
  EXPECT_EQ((*passes)[1].slots, 2u);
  EXPECT_EQ((*passes)[2].direction, Direction::Minus);
  EXPECT_EQ((*passes)[3].direction, Direction::Plus);
  EXPECT_EQ((*passes)[4].direction, Direction::Minus);
  EXPECT_EQ((*passes)[4].line, 8u);
  EXPECT_EQ(pass_type_name((*passes)[5].type), "knit-tuck");
  knitout::DiagnosticSink bad_sink;
  const auto bad = knitout::parse_string(kHead + "knit + f1 3\n", "b.k", bad_sink);
  EXPECT_FALSE(carriage_passes(bad, "b.k", bad_sink).has_value());
  EXPECT_TRUE(bad_sink.has_errors());
}

TEST(DatPassesTest, CarriagePassesPrintAsTextAndJson) {
  // Streamed as `simulate` would: a PassBuilder fed instruction by instruction.
  std::istringstream in(kHead +
                        "in 3\nknit + f1 3\nknit + f2 3\nxfer f1 b1\nrack 0.25\n"
                        "knit - f2 3\nrack 0\nout 3\n");
  knitout::DiagnosticSink sink;
  knitout::Reader reader(in, "t.k", sink);
  PassBuilder builder("t.k", sink);
  ASSERT_TRUE(builder.begin(reader.has_magic(), reader.headers()));
  knitout::Instruction instruction;
  while (reader.next(instruction)) builder.add(instruction, reader.carriers(), reader.text());
  ASSERT_TRUE(builder.finish(static_cast<std::uint32_t>(reader.lines_read())));
  const std::vector<CarriagePass> passes = summarize(builder.passes());
  std::ostringstream text;
  write_carriage_passes_text(text, passes, true);
  EXPECT_EQ(text.str(),
            "carriage passes: 4 (3 knit-tuck, 1 xfer)\n"
            "  pass 1 (line 4): + carriers 3 racking 0 knit-tuck, 2 slots\n"
            "  pass 2 (line 6): none carriers - racking 0 xfer, 1 slot\n"
            "  pass 3 (line 8): - carriers 3 racking 0.25 knit-tuck, 1 slot\n"
            "  pass 4 (line 10): + carriers 3 racking 0 knit-tuck, 1 slot\n");
  std::ostringstream json;
  write_carriage_passes_json(json, std::vector<CarriagePass>(passes.begin(), passes.begin() + 2));
  EXPECT_EQ(json.str(),
            "{\"count\": 2, \"passes\": [{\"type\": \"knit-tuck\", \"direction\": \"+\", "
            "\"carriers\": [\"3\"], \"racking\": 0, \"slots\": 2, \"line\": 4}, {\"type\": "
            "\"xfer\", \"direction\": \"none\", \"carriers\": [], \"racking\": 0, \"slots\": 1, "
            "\"line\": 6}]}");
}

TEST(DatPassesTest, ProgramAndStreamGiveTheSamePasses) {
  const std::string text = kHead +
                           "inhook 3\nknit + f1 3\nknit + f2 3\nreleasehook 3\nrack 0.25\n"
                           "knit - b2 3\nknit - f2 3\nrack 0\nxfer f1 b1\nouthook 3\n";
  knitout::DiagnosticSink a;
  knitout::DiagnosticSink b;
  std::istringstream in(text);
  const auto streamed = form_passes(in, "t.k", a);
  const auto whole = form_passes(knitout::parse_string(text, "t.k", b), "t.k", b);
  ASSERT_TRUE(streamed && whole);
  const auto x = write_dat(*streamed, a);
  const auto y = write_dat(*whole, b);
  ASSERT_TRUE(x && y);
  EXPECT_EQ(*x, *y);
}

TEST(DatPassesTest, VerifyFindsTheWrittenPassesAndNoticesAChangedPixel) {
  Result r;
  run("in 3\nknit + f1 3\nknit + f2 3\nxfer f1 b1\nknit - f2 3\nout 3\n", r);
  ASSERT_TRUE(r.bytes.has_value()) << r.first_error();
  knitout::DiagnosticSink sink;
  Raster raster = decode(*r.bytes, "t.dat", sink);
  auto layout = read_layout(raster, "t.dat", sink);
  ASSERT_TRUE(layout.has_value());
  EXPECT_TRUE(compare_passes(*r.passes, *layout).empty());
  // The first pass's first knit (row 8, column 55) becomes a tuck.
  raster.pixels[static_cast<std::size_t>(8 * raster.width + 55)] = 11;
  auto changed = read_layout(raster, "t.dat", sink);
  ASSERT_TRUE(changed.has_value());
  EXPECT_EQ(compare_passes(*r.passes, *changed),
            (std::vector<std::string>{"pass 1 (line 4, row 8): operations differ (expected "
                                      "knit-front at slot column 0)"}));
}

// Random programs (fixed seed) from a vocabulary biased towards valid
// knitout: whatever the backend decides, it must not crash, and every DAT
// it writes must read back to the passes it formed.
TEST(DatPassesTest, RandomProgramsNeverCrashAndReadBackAsWritten) {
  std::mt19937 random(4242);
  auto chance = [&](int percent) {
    return std::uniform_int_distribution<int>(0, 99)(random) < percent;
  };
  auto pick = [&](const std::vector<std::string>& items) {
    return items[std::uniform_int_distribution<std::size_t>(0, items.size() - 1)(random)];
  };
  auto index = [&]() { return std::uniform_int_distribution<int>(-3, 12)(random); };
  int accepted = 0;
  int rejected = 0;
  for (int program = 0; program < 300; ++program) {
    // Two carriers in and used; mostly valid operations on them; rarely
    // something the backend rejects.
    std::string body = "in 3\nknit + f0 3\nin 4\nknit + f1 4\n";
    int racking = 0;
    bool quarter = false;
    const int lines = std::uniform_int_distribution<int>(1, 60)(random);
    for (int i = 0; i < lines; ++i) {
      const std::string cs = chance(3) ? pick({"1 2 3", "11", "5"}) : pick({"3", "4", "3 4"});
      const std::string dir = chance(50) ? "+" : "-";
      const std::string bed = chance(70) ? "f" : "b";
      const int kind = std::uniform_int_distribution<int>(0, 9)(random);
      if (kind == 0) {
        racking = std::uniform_int_distribution<int>(-2, 2)(random);
        quarter = chance(25);
        if (chance(3)) {
          body += pick({"rack 9", "rack 0.5"});
        } else {
          body += "rack " + std::to_string(racking) + (quarter ? ".25" : "");
        }
      } else if (kind == 1) {
        body += pick({"pause", "x-speed-number 4", "x-stitch-number 300", "x-presser-mode auto",
                      "x-presser-mode on", "x-presser-mode off", "stitch 20 20", "x-foo 1"});
      } else if (kind < 7) {
        body += pick({"knit ", "knit ", "tuck ", "miss "}) + dir + " " + bed +
                std::to_string(index()) + " " + cs;
      } else if (kind == 7) {
        body += pick({"drop ", "amiss "}) + bed + std::to_string(index());
      } else {
        // Transfers and splits between facing needles (random when quarter pitched).
        const int n = index();
        const bool to_back = chance(50);
        const int m = quarter ? index() : (to_back ? n - racking : n + racking);
        const std::string from = (to_back ? "f" : "b") + std::string(chance(10) ? "s" : "");
        const std::string to = (to_back ? "b" : "f") + std::string(chance(10) ? "s" : "");
        if (kind == 8) {
          body += "xfer " + from + std::to_string(n) + " " + to + std::to_string(m);
        } else {
          body += "split " + dir + " " + from + std::to_string(n) + " " + to + std::to_string(m) +
                  " " + cs;
        }
      }
      body += '\n';
    }
    body += chance(95) ? "out 3\nout 4\n" : "out 3\n";
    SCOPED_TRACE(body);
    Result r;
    run(body, r);
    if (!r.bytes) {
      EXPECT_TRUE(r.sink.has_errors());
      ++rejected;
      continue;
    }
    ++accepted;
    knitout::DiagnosticSink sink;
    const Raster raster = decode(*r.bytes, "r.dat", sink);
    auto layout = read_layout(raster, "r.dat", sink);
    ASSERT_TRUE(layout.has_value());
    EXPECT_EQ(compare_passes(*r.passes, *layout), std::vector<std::string>{});
  }
  // Both outcomes are exercised.
  EXPECT_GT(accepted, 30);
  EXPECT_GT(rejected, 30);
}

}  // namespace
}  // namespace dat
