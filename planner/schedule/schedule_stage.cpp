#include "planner/schedule/schedule_stage.hpp"

#include <algorithm>
#include <chrono>
#include <sstream>
#include <stdexcept>

#include "backends/dat/passes.hpp"
#include "backends/dat/raster.hpp"
#include "knitout/parser.hpp"
#include "planner/pipeline.hpp"
#include "planner/schedule/schoolbus.hpp"
#include "simulators/bed/bed_view.hpp"
#include "simulators/bed/machine.hpp"
#include "simulators/bed/profile.hpp"
#include "simulators/cloth/parallel.hpp"

namespace planner {

struct PieceCheck {
  knitout::Program program;
  knitout::DiagnosticSink sink;
  bed::BedView view;
  std::unique_ptr<bed::Machine> machine;
};

namespace {

// The carriers the `;;Carriers:` header names, if it is there.
std::optional<std::size_t> header_carriers(const knitout::Program& program) {
  const auto carriers = program.header("Carriers");
  if (!carriers) return std::nullopt;
  std::istringstream names{std::string(*carriers)};
  std::size_t n = 0;
  for (std::string word; names >> word;) ++n;
  return n;
}

// Runs the piece through the needle-bed VM. An error there is a bug of the
// scheduler, never the user's: std::logic_error with the VM's messages.
std::shared_ptr<PieceCheck> run_vm(const EmittedPiece& emitted, const std::string& name) {
  auto check = std::make_shared<PieceCheck>();
  check->program = knitout::parse_string(emitted.knitout, name, check->sink);
  bed::MachineOptions options;
  options.observer = &check->view;
  check->machine = std::make_unique<bed::Machine>(bed::default_profile(), check->sink, name,
                                                  check->program.carriers,
                                                  header_carriers(check->program), options);
  check->machine->check_headers(check->program.headers);
  for (const knitout::Instruction& instruction : check->program.instructions)
    check->machine->step(instruction);
  check->machine->finish(static_cast<std::uint32_t>(emitted.stats.lines));
  if (check->sink.has_errors()) {
    std::ostringstream message;
    message << "the needle-bed VM rejects " << name << ":\n";
    knitout::print_text(message, check->sink.sorted());
    throw std::logic_error(message.str());
  }
  return check;
}

// The piece as DAT. A piece the DAT backend refuses is a scheduler bug, like
// a VM error.
std::vector<std::uint8_t> compile_dat(const knitout::Program& program, const std::string& name) {
  knitout::DiagnosticSink sink;
  std::optional<std::vector<std::uint8_t>> bytes;
  if (auto passes = dat::form_passes(program, name, sink)) bytes = dat::write_dat(*passes, sink);
  if (!bytes) {
    std::ostringstream message;
    message << "the DAT backend rejects " << name << ":\n";
    knitout::print_text(message, sink.sorted());
    throw std::logic_error(message.str());
  }
  return std::move(*bytes);
}

}  // namespace

std::optional<ScheduleOutcome> schedule_stitches(const StitchMeshFile& stitches,
                                                 const ScheduleStageParams& params,
                                                 const std::string& source,
                                                 knitout::DiagnosticSink& sink) {
  const auto start = std::chrono::steady_clock::now();
  ScheduleOutcome outcome;
  outcome.params = params;
  outcome.stitch_mesh_id = stitches.id;
  outcome.cut_id = stitches.cut_id;
  // The trials' threads as schedule() resolves them (OMP_NUM_THREADS, else every core).
  outcome.threads = static_cast<unsigned>(cloth::resolve_threads(params.schedule.threads));
  std::vector<EmittedPiece> emitted;
  try {
    outcome.schedule = schedule(stitches.mesh, params.schedule);
    for (std::size_t p = 0; p < outcome.schedule.pieces.size(); ++p) {
      try {
        emitted.push_back(emit_piece(stitches.mesh, outcome.schedule, p, params.emit));
      } catch (const NoTransferRoute& e) {
        // Loops held around a row leave a moving loop no stop: the stitch
        // mesh's rows there move too far at once for the bed. Another cut
        // (another seed) or size makes other rows.
        sink.error(source, 0, 0, "S911",
                   "piece " + std::to_string(p + 1) + " cannot be knit: " + e.what() +
                       ", where its rows shift too far at once for the loops held beside "
                       "them; cut again with another seed (`wearknit cut --seed N`, "
                       "`wearknit plan --seed N`) or at another size");
        return std::nullopt;
      }
    }
  } catch (const ScheduleError& e) {
    sink.error(source, 0, 0, "S910", e.what());
    return std::nullopt;
  }
  outcome.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Every piece runs through the needle-bed VM and the DAT backend before
  // anything is written.
  for (std::size_t p = 0; p < emitted.size(); ++p) {
    ScheduledPiece piece;
    piece.name = "piece-" + std::to_string(p + 1);
    piece.check = run_vm(emitted[p], piece.name + ".k");
    piece.vm_stats = piece.check->machine->stats();
    piece.vm_warnings = piece.check->sink.warning_count();
    piece.dat = compile_dat(piece.check->program, piece.name + ".k");
    for (int r : outcome.schedule.pieces[p].rows)
      piece.stitches += outcome.schedule.rows[static_cast<std::size_t>(r)].faces.size();
    piece.emitted = std::move(emitted[p]);
    outcome.pieces.push_back(std::move(piece));
  }
  return outcome;
}

std::string write_bed_view(const ScheduledPiece& piece, const std::string& path) {
  return piece.check->view.write(path, *piece.check->machine, piece.name + ".k");
}

std::string cut_cause_text(const Schedule& s, std::size_t cut) {
  const auto [lower, upper] = s.cut_rows.at(cut);
  std::ostringstream text;
  text << "cut " << cut + 1 << ": rows " << lower << " and " << upper << " are parted";
  if (cut < s.cut_causes.size() && s.cut_causes[cut].covering != kNone) {
    text << " because row " << s.cut_causes[cut].covering << " is knit before row " << upper
         << " over the needle where the loops from row " << lower << " wait for it";
  }
  return text.str();
}

std::string describe(const ScheduleOutcome& outcome, const std::string& smobj_path,
                     const std::string& pieces_dir) {
  const Schedule& s = outcome.schedule;
  double total = 0;
  for (const ScheduledPiece& piece : outcome.pieces) total += piece.vm_stats.estimated_time_s;
  std::ostringstream text;
  text << smobj_path << ": " << s.faces.size() << " stitches, " << s.rows.size() << " rows, "
       << s.patches.size() << " patches; " << s.trials.size() << " orders tried, best has "
       << s.cuts << " cut" << (s.cuts == 1 ? "" : "s") << "; " << outcome.pieces.size() << " piece"
       << (outcome.pieces.size() == 1 ? "" : "s") << " in " << pieces_dir << " ("
       << stitch_pattern_name(outcome.params.emit.pattern) << ", about "
       << static_cast<int>(total / 60 + 0.5) << " min on the machine)\n";
  // Why each cut is made (§7.3), the first few; schedule.json has them all.
  constexpr std::size_t kCausesShown = 5;
  for (std::size_t i = 0; i < s.cut_rows.size() && i < kCausesShown; ++i) {
    text << "  " << cut_cause_text(s, i) << '\n';
  }
  if (s.cut_rows.size() > kCausesShown) {
    text << "  ... and " << s.cut_rows.size() - kCausesShown
         << " more cuts (schedule_cuts in cuts.json, each with its `why`)\n";
  }
  return text.str();
}

}  // namespace planner
