#include "planner/wearability/wearability_stage.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "knitout/output_file.hpp"
#include "planner/common/hash.hpp"
#include "planner/common/index.hpp"
#include "planner/common/json_file.hpp"
#include "planner/mesh/mesh_io.hpp"
#include "planner/pipeline.hpp"
#include "planner/wearability/coarse_cloth.hpp"
#include "planner/wearability/wearability_io.hpp"
#include "planner/wearability/wearability_picture.hpp"

namespace planner {

namespace {

namespace fs = std::filesystem;

// The seed of a successful trial of the final configuration: the last sewn
// arc's test (the configuration did not change after it), else the test
// with every cut open.
std::uint64_t final_seed(const EliminationResult& result) {
  const TestResult* last = &result.initial;
  int position = -1;
  for (const auto& arc : result.arcs) {
    if (arc.label == Label::Sew && arc.position > position) {
      position = arc.position;
      last = &arc.test;
    }
  }
  return last->trials.empty() ? 0 : last->trials.back().seed;
}

std::string seed_text(const std::optional<std::uint64_t>& seed) {
  return seed ? "seed " + std::to_string(*seed) : std::string("an unrecorded seed");
}

// The final check's garment, finer than the elimination's: the garment as
// it is when the elimination simulated it coarsened (the cut-mesh, the
// cloth of §8.2), else one subdivision step finer; then subdivided until it
// has cloth_vertices, dressed. A garment subdivided further than that is
// softer than the cloth it stands for: at a fixed count of constraint
// iterations, a closed shell stretched over four times the vertices slips
// over its wearer between the points that collide (docs/wearability.md,
// "The cloth's resolution").
CoverMesh check_garment(const Wearability& result, const cloth::SignedDistanceField& wearer) {
  return dressed(refined_for_cloth(result.coarse_cloth() ? result.cover : subdivided(result.cover),
                                   result.params.cloth_vertices),
                 wearer, result.params.test.cloth);
}

// The final check's trials: the elimination's, with the check's stall stop.
WearabilityParams check_params(const WearabilityStageParams& params) {
  WearabilityParams check = params.test;
  check.cloth.stall_switches = params.check_stall_switches;
  return check;
}

// The seed of the final check's round `round`: "CHECK" tags the stream,
// apart from the elimination's seeds.
std::uint64_t check_round_seed(const WearabilityStageParams& params, int round) {
  return mix64(mix64(params.test.seed ^ 0x434845434BULL) + static_cast<std::uint64_t>(round));
}

// The final check (FinalCheck): rounds of M trials on the chosen run's
// configuration, opening arcs after each failed round.
void final_check(Wearability& result, const cloth::SignedDistanceField& wearer) {
  const auto start = std::chrono::steady_clock::now();
  FinalCheck& check = result.check;
  check = FinalCheck{};
  const int chosen = chosen_run(result.study);
  if (chosen < 0 || result.params.check_trials <= 0) return;
  EliminationResult& run = result.study.runs[static_cast<std::size_t>(chosen)];
  check.ran = true;
  check.trials = result.params.check_trials;
  const CoverMesh garment = check_garment(result, wearer);
  check.cloth_vertices = static_cast<int>(garment.positions.size());
  const WearabilityParams patient = check_params(result.params);
  for (int round = 0;; ++round) {
    CheckRound r;
    r.seed = check_round_seed(result.params, round);
    r.test = test_every_trial(garment, run.open(), wearer, patient, r.seed, check.trials);
    const bool passed = r.test.wearable;
    if (!passed) {
      // One arc, then twice as many each round: few arcs laced, few rounds.
      const int count = round < 20 ? 1 << round : std::numeric_limits<int>::max();
      r.reopened = arcs_to_open(result.cover, run, r.test, count);
      for (const int a : r.reopened) {
        run.arcs[static_cast<std::size_t>(a)].label = Label::Lace;
        run.arcs[static_cast<std::size_t>(a)].reopened = true;
      }
    }
    const bool more = !passed && !r.reopened.empty();
    check.rounds.push_back(std::move(r));
    if (passed) check.passed = true;
    if (!more) break;
  }
  // The last batch laced may hold arcs the garment did not need open: the
  // round before it failed with all of them sewn, the round after passed
  // with none. Binary search, in the elimination's order, for the longest
  // run of them that can be sewn again and still pass every trial (sewing
  // less never makes a garment harder to take off): ⌈log2 n⌉ rounds more,
  // and the labels end as those of the last round that passed.
  if (check.passed && check.rounds.size() >= 2) {
    std::vector<int> batch = check.rounds[check.rounds.size() - 2].reopened;
    std::sort(batch.begin(), batch.end(), [&](int a, int b) {
      return run.arcs[static_cast<std::size_t>(a)].position <
             run.arcs[static_cast<std::size_t>(b)].position;
    });
    // Sewing batch[0, low) passes (low = 0: the round that passed); sewing
    // batch[0, high) fails (high = the batch: the round before).
    std::size_t low = 0, high = batch.size();
    while (high - low > 1) {
      const std::size_t middle = low + (high - low) / 2;
      for (std::size_t i = low; i < middle; ++i) {
        run.arcs[static_cast<std::size_t>(batch[i])].label = Label::Sew;
      }
      CheckRound r;
      r.seed = check_round_seed(result.params, static_cast<int>(check.rounds.size()));
      r.test = test_every_trial(garment, run.open(), wearer, patient, r.seed, check.trials);
      r.sewn_again.assign(batch.begin() + static_cast<std::ptrdiff_t>(low),
                          batch.begin() + static_cast<std::ptrdiff_t>(middle));
      if (r.test.wearable) {
        for (const int a : r.sewn_again) run.arcs[static_cast<std::size_t>(a)].reopened = false;
        low = middle;
      } else {
        for (const int a : r.sewn_again) run.arcs[static_cast<std::size_t>(a)].label = Label::Lace;
        r.reopened = r.sewn_again;
        high = middle;
      }
      std::sort(r.sewn_again.begin(), r.sewn_again.end());
      std::sort(r.reopened.begin(), r.reopened.end());
      check.rounds.push_back(std::move(r));
    }
  }
  check.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// §5's loop: the elimination on the garment of the current cut; while no
// run comes off with every cut open, the proxy of `cut` is cut again (when
// there is a cut to cut again).
Wearability label(CoverMesh garment, const Cut* cut, const cloth::SignedDistanceField& wearer,
                  const WearabilityStageParams& params, const WearabilityCallbacks& callbacks) {
  const auto start = std::chrono::steady_clock::now();
  Wearability result;
  result.params = params;
  result.cut_id = cut != nullptr ? cut->id : 0;
  WearabilityParams test = params.test;
  test.record = callbacks.record;
  std::optional<std::uint64_t> seed;
  if (cut != nullptr) seed = cut->report.params.seed;
  result.cover = std::move(garment);
  for (int attempt = 0;; ++attempt) {
    result.cloth = coarsened(result.cover, params.cloth_max_vertices);
    result.study = study_lacing(result.cloth, wearer, test, params.runs, callbacks.progress);
    int coarse_vertices = 0;
    // A garment linked with the wearer stays linked on any cloth.
    auto linked = [&] {
      return !result.study.runs.empty() && result.study.runs.front().initial.linked;
    };
    while (!result.wearable() && result.coarse_cloth() && !linked()) {
      // The coarse cloth does not come off even with every cut open: too
      // coarse to bend off this wearer. A cloth of twice the vertices, up
      // to the garment's own (§8.2), answers before the cut is called
      // unwearable.
      coarse_vertices = static_cast<int>(result.cloth.positions.size());
      result.cloth = coarsened(result.cover, 2 * coarse_vertices);
      result.study = study_lacing(result.cloth, wearer, test, params.runs, callbacks.progress);
    }
    CutAttempt tried;
    tried.cloth_vertices = static_cast<int>(result.cloth.positions.size());
    tried.coarse_cloth_vertices = coarse_vertices;
    tried.attempt = attempt;
    tried.cut_seed = seed;
    tried.arcs = static_cast<int>(result.cover.arcs.size());
    tried.wearable = result.wearable();
    tried.linked = linked();
    if (!result.study.runs.empty()) tried.trials = result.study.runs.front().initial.trials;
    result.attempts.push_back(tried);
    if (callbacks.attempted) callbacks.attempted(tried);
    if (tried.wearable || attempt >= params.recut_limit) break;

    // §5: the garment with every cut open is not wearable: cut again.
    CutAttempt next;
    next.attempt = attempt + 1;
    next.cut_seed = recut_seed(params.test.seed, attempt + 1);
    if (cut == nullptr) {
      next.failure = "a garment made by hand (no proxy.obj) cannot be cut again";
    } else {
      try {
        result.recut = recut(*cut, *next.cut_seed);
        result.cover = cover_of(*result.recut, params.cloth_vertices);
        seed = next.cut_seed;
        continue;
      } catch (const std::logic_error& e) {
        next.failure = std::string("internal error: ") + e.what();
      }
    }
    result.attempts.push_back(next);
    if (callbacks.attempted) callbacks.attempted(next);
    break;
  }
  final_check(result, wearer);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace

std::vector<int> arcs_to_open(const CoverMesh& cover, const EliminationResult& run,
                              const TestResult& test, int count) {
  std::vector<std::tuple<double, int, int>> by_distance;  // distance, -position, arc
  for (std::size_t a = 0; a < cover.arcs.size(); ++a) {
    if (run.arcs[a].label != Label::Sew) continue;
    double nearest = std::numeric_limits<double>::infinity();
    for (const TrialOutcome& trial : test.trials) {
      if (trial.success || trial.caught == 0) continue;
      for (const auto& edge : cover.arcs[a].edges) {
        for (const int v : edge) {
          const double d = (cover.positions[static_cast<std::size_t>(v)] - trial.caught_at).norm() -
                           trial.caught_radius;
          nearest = std::min(nearest, std::max(d, 0.0));
        }
      }
    }
    by_distance.emplace_back(nearest, -run.arcs[a].position, static_cast<int>(a));
  }
  std::sort(by_distance.begin(), by_distance.end());
  std::vector<int> chosen;
  for (const auto& entry : by_distance) {
    if (static_cast<int>(chosen.size()) >= count) break;
    chosen.push_back(std::get<2>(entry));
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

const CheckRound* FinalCheck::last_passed() const {
  for (auto it = rounds.rbegin(); it != rounds.rend(); ++it) {
    if (it->test.wearable) return &*it;
  }
  return nullptr;
}

int FinalCheck::reopened() const {
  int count = 0;
  for (const auto& r : rounds) {
    count += static_cast<int>(r.reopened.size()) - static_cast<int>(r.sewn_again.size());
  }
  return count;
}

std::optional<std::uint64_t> Wearability::cut_seed() const {
  for (auto it = attempts.rbegin(); it != attempts.rend(); ++it) {
    if (it->failure.empty()) return it->cut_seed;
  }
  return std::nullopt;
}

std::uint64_t recut_seed(std::uint64_t wearability_seed, int attempt) {
  // "CUT" tags the stream, apart from the runs' and trials' seeds.
  return mix64(mix64(wearability_seed ^ 0x435554ULL) + static_cast<std::uint64_t>(attempt));
}

CoverMesh cover_of(const Cut& cut, int min_vertices) {
  // The disc welded along its cuts: every disc vertex is the copy of one
  // proxy vertex (disc_source), so the garment is the proxy's vertices with
  // the disc's faces. Welding by position instead would merge proxy
  // vertices that lie closer than the files' precision.
  CoverMesh cover;
  const PolygonMesh proxy = cut.mesh.proxy.polygons();
  cover.positions = proxy.positions;
  for (const std::vector<int>& face : cut.mesh.disc.faces) {
    std::vector<int> welded;
    for (const int v : face) welded.push_back(cut.mesh.disc_source[at(v)]);
    cover.faces.push_back(std::move(welded));
  }
  for (std::size_t a = 0; a < cut.mesh.arcs.size(); ++a)
    cover.arcs.push_back(arc_from_path(cut.mesh.arcs[a].vertices, std::to_string(a)));
  if (const auto problems = validate(cover); !problems.empty())
    throw std::logic_error("the cut's own arcs do not make a garment: " + problems.front());
  return refined_for_cloth(std::move(cover), min_vertices);
}

cloth::SignedDistanceField wearer_field(const PolygonMesh& wearer,
                                        const WearabilityStageParams& params) {
  cloth::SdfParams sdf;
  sdf.resolution = params.sdf_resolution;
  sdf.threads = params.test.threads;
  return cloth::SignedDistanceField(wearer.positions, wearer.faces, sdf);
}

std::uint64_t journal_context(const PolygonMesh& wearer, const WearabilityStageParams& params) {
  std::ifstream program_in("/proc/self/exe", std::ios::binary);
  const std::string program((std::istreambuf_iterator<char>(program_in)),
                            std::istreambuf_iterator<char>());
  std::ostringstream wearer_text;
  write_obj(wearer_text, wearer);
  std::ostringstream text;
  text << "program " << fingerprint(program) << " wearer " << fingerprint(wearer_text.str())
       << " trials " << params.test.trials << " max-steps " << params.test.cloth.max_steps
       << " resolution " << params.sdf_resolution << " cloth-vertices " << params.cloth_vertices
       << " cloth-max-vertices " << params.cloth_max_vertices;
  return fingerprint(text.str());
}

Wearability label_arcs(const Cut& cut, const cloth::SignedDistanceField& wearer,
                       const WearabilityStageParams& params,
                       const WearabilityCallbacks& callbacks) {
  return label(cover_of(cut, params.cloth_vertices), &cut, wearer, params, callbacks);
}

Wearability label_garment(const CoverMesh& garment, const cloth::SignedDistanceField& wearer,
                          const WearabilityStageParams& params,
                          const WearabilityCallbacks& callbacks) {
  return label(garment, nullptr, wearer, params, callbacks);
}

std::string describe(const Wearability& result) {
  const LacingStudy& study = result.study;
  const int chosen = chosen_run(study);
  if (chosen < 0) return "wearability: not wearable\n";
  int sewn = 0;
  for (const auto& arc : study.runs[static_cast<std::size_t>(chosen)].arcs)
    sewn += arc.label == Label::Sew;
  double seconds = 0;
  std::uint64_t steps = 0;
  int replayed = 0, tests = 0, linked = 0;
  for (const auto& run : study.runs) {
    seconds += run.seconds;
    steps += run.steps;
    replayed += run.replayed;
    tests += run.tests + 1;
    linked += run.linked;
  }
  const std::size_t arcs = result.cover.arcs.size();
  std::ostringstream text;
  text << "wearability: " << arcs << " arcs, " << sewn << " sew, " << arcs - sewn << " lace";
  if (result.params.runs > 1)
    text << " (run " << chosen + 1 << " of " << result.params.runs << ", most sewn)";
  if (result.recut) {
    text << "; re-cut with " << seed_text(result.cut_seed()) << " (attempt "
         << result.attempts.size() - 1 << " of " << result.params.recut_limit << ")";
  }
  text << "; " << steps << " steps";
  if (result.coarse_cloth())
    text << " of a cloth of " << result.cloth.positions.size() << " vertices (the garment's "
         << result.cover.positions.size() << ", coarsened)";
  text << " in " << std::fixed << std::setprecision(1) << seconds << " s";
  if (replayed > 0) text << " (" << replayed << " tests read from the journal)";
  if (linked > 0) {
    text << "; " << linked << " of " << tests
         << " tests failed unsimulated, a garment curve linked with the wearer";
  }
  text << '\n';
  const FinalCheck& check = result.check;
  if (check.ran) {
    text << "final check: " << (check.passed ? "off" : "not off") << " in every one of "
         << check.trials << " fresh trials at " << check.cloth_vertices << " cloth vertices";
    if (check.reopened() > 0) {
      // Arcs the check laced and then sewed back in a round that passed.
      int sewn_back = 0;
      for (const auto& r : check.rounds) {
        if (r.test.wearable) sewn_back += static_cast<int>(r.sewn_again.size());
      }
      const int laced = check.reopened() + sewn_back;
      text << " after lacing " << laced << " more arc" << (laced == 1 ? "" : "s");
      if (sewn_back > 0) text << " and sewing " << sewn_back << " of them back";
      text << " (" << check.rounds.size() << " rounds)";
    }
    text << "; " << std::setprecision(1) << check.seconds << " s\n";
  }
  return text.str();
}

std::string check_warning(const Wearability& result) {
  const FinalCheck& check = result.check;
  if (!check.ran || check.passed || check.rounds.empty()) return {};
  const TestResult& last = check.rounds.back().test;
  int off = 0;
  for (const auto& t : last.trials) off += t.success;
  std::ostringstream text;
  text << "with every arc laced, the garment came off in " << off << " of the "
       << last.trials.size() << " trials of the final check that ran (at " << check.cloth_vertices
       << " cloth vertices), not in all " << check.trials
       << ": it comes off only sometimes; every arc is laced, and a looser garment, more cuts "
          "or a longer --max-steps make it come off reliably";
  return text.str();
}

const TrialOutcome* farthest_failed_trial(const Wearability& result) {
  const TrialOutcome* best = nullptr;
  for (const auto& a : result.attempts) {
    for (const TrialOutcome& t : a.trials) {
      if (!t.success && t.caught > 0 && (best == nullptr || t.caught < best->caught)) best = &t;
    }
  }
  return best;
}

std::string not_wearable_message(const Wearability& result) {
  std::ostringstream text;
  bool every_linked = true;
  for (const auto& a : result.attempts)
    every_linked = every_linked && (!a.failure.empty() || a.linked);
  if (every_linked) {
    text << "the garment with every cut open cannot come off the wearer: a closed curve of it "
            "winds around a handle of the wearer, ";
  } else {
    text << "the garment with every cut open did not come off the wearer in "
         << result.params.test.trials << " trials of " << result.params.test.cloth.max_steps
         << " steps, ";
  }
  std::vector<std::string> made;
  std::string not_made;
  for (const auto& a : result.attempts) {
    if (!a.failure.empty()) {
      not_made = a.failure;
    } else {
      made.push_back(seed_text(a.cut_seed) + (a.attempt == 0
                                                  ? std::string(" (the folder's)")
                                                  : " (re-cut " + std::to_string(a.attempt) + ")"));
    }
  }
  text << (made.size() == 1 ? "with the cut of " : "with each of the cuts of ");
  for (std::size_t i = 0; i < made.size(); ++i) text << (i ? ", " : "") << made[i];
  if (!not_made.empty()) {
    text << "; cannot cut again: " << not_made;
  } else if (made.size() == 1) {
    text << " (--recut-limit " << result.params.recut_limit << ")";
  }
  text << "; every arc is labelled lace";
  const TrialOutcome* best = farthest_failed_trial(result);
  if (best != nullptr && 2 * best->caught > best->cloth_vertices) {
    text << ". In the trial that got farthest, " << best->caught << " of the "
         << best->cloth_vertices
         << " cloth vertices are still on the wearer: the open garment does not move off it "
            "at all (it encloses the wearer, or the trials are too short: --max-steps)";
  } else if (best != nullptr) {
    text << std::fixed << std::setprecision(1) << ". It stays caught within " << best->caught_radius
         << " mm of (" << best->caught_at.x() << ", " << best->caught_at.y() << ", "
         << best->caught_at.z() << ") mm (" << best->caught << " of " << best->cloth_vertices
         << " cloth vertices still on the wearer in the trial that got farthest): a shape that "
            "locks the garment there (§9) comes off only with more cuts across that region or "
            "a looser garment; a longer --max-steps may be enough where the trials end early";
  }
  return text.str();
}

std::string write_wearability(const std::string& dir, const Wearability& result,
                              std::uint64_t labelled_cut_id, bool picture) {
  const fs::path base(dir);
  std::string failure = write_json_file((base / "wearability.json").string(),
                                        wearability_json(result, labelled_cut_id));
  if (!failure.empty() || !picture) return failure;
  // Green sewn, red laced; over several runs, the share of runs that laced
  // the arc (Fig. 18).
  std::vector<double> lace_share(result.cover.arcs.size(), 1.0);
  const int chosen = chosen_run(result.study);
  // Not wearable with every cut open (W020): where the garment stays caught.
  const TrialOutcome* caught = chosen < 0 ? farthest_failed_trial(result) : nullptr;
  if (chosen >= 0) {
    if (result.params.runs > 1) {
      lace_share = result.study.lace_probability;
    } else {
      const auto open = result.study.runs[static_cast<std::size_t>(chosen)].open();
      for (std::size_t a = 0; a < open.size(); ++a) lace_share[a] = open[a] ? 1.0 : 0.0;
    }
  }
  return knitout::write_file_atomically(
      (base / "wearability.png").string(),
      [&](std::ostream& out) { draw_wearability(out, result.cover, lace_share, caught); });
}

std::optional<WearabilityRecord> read_wearability(const std::string& dir,
                                                  knitout::DiagnosticSink& sink) {
  const std::string path = (fs::path(dir) / "wearability.json").string();
  auto file = read_json_object(path, sink, "W004", "W010");
  if (!file) return std::nullopt;
  WearabilityRecord record;
  try {
    if (!parse_hex64(file->at("cut_id").get<std::string>(), record.cut_id))
      throw std::runtime_error("\"cut_id\" is not 16 hex digits");
    record.wearable = file->at("summary").at("wearable").get<bool>();
    for (const auto& arc : file->at("arcs")) {
      const std::string label = arc.at("label").get<std::string>();
      if (label != "sew" && label != "lace")
        throw std::runtime_error("label \"" + label + "\" is not sew or lace");
      record.labels.push_back(label == "sew" ? Label::Sew : Label::Lace);
    }
  } catch (const std::exception& e) {
    sink.error(path, 0, 0, "W010", std::string("unexpected content: ") + e.what());
    return std::nullopt;
  }
  record.file = std::move(*file);
  return record;
}

std::string write_strip_off_frames(const Wearability& result,
                                   const cloth::SignedDistanceField& wearer, const std::string& dir,
                                   int every, int* written, bool* off) {
  *written = 0;
  *off = false;
  const int chosen = chosen_run(result.study);
  if (chosen < 0) return "no configuration came off the wearer: no frames to write";
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) return dir + ": cannot create folder: " + error.message();
  const EliminationResult& run = result.study.runs[static_cast<std::size_t>(chosen)];
  // The final configuration came off in a trial the frames repeat: the last
  // sewn arc's test, unless the final check laced arcs after it; then the
  // first trial of the check's last passing round, on the check's garment.
  const FinalCheck& check = result.check;
  const bool from_check = check.passed && check.reopened() > 0 && check.last_passed() != nullptr;
  const CoverMesh dressed_mesh = from_check
                                     ? check_garment(result, wearer)
                                     : dressed(result.cloth, wearer, result.params.test.cloth);
  const std::uint64_t seed =
      from_check ? check.last_passed()->test.trials.front().seed : final_seed(run);
  const PolygonMesh garment = open_cuts(dressed_mesh, run.open());
  // One thread: a garment of a few thousand vertices gains little from
  // splitting a step, and loses much when the cores are busy.
  const cloth::ClothParams cloth =
      from_check ? check_params(result.params).cloth : result.params.test.cloth;
  cloth::ClothSimulation sim(garment, wearer, cloth);
  std::string failure;
  auto write_frame = [&](int step, const cloth::ClothSimulation& state) {
    std::ostringstream name;
    name << "frame-" << std::setw(5) << std::setfill('0') << step << ".obj";
    failure = knitout::write_file_atomically(
        (fs::path(dir) / name.str()).string(), [&](std::ostream& out) {
          write_obj(out, PolygonMesh{state.positions(), state.mesh().faces});
        });
    ++*written;
    return failure.empty();
  };
  write_frame(0, sim);
  const auto outcome = sim.run(seed, [&](int step, const cloth::ClothSimulation& s) {
    return step % every != 0 || write_frame(step, s);
  });
  *off = outcome.success;
  return failure;
}

}  // namespace planner
