// strip_rate: how often one strip-off trial (§5, §8.2) takes a garment off its
// wearer, on a cut folder the wearability stage has labelled (its
// wearability.json, written by `wearknit wearability` or `wearknit plan`).
//
// Runs TRIALS trials, each with its own global-force directions, on the
// labelled configuration (laced arcs open, sewn arcs closed: a configuration
// that passed a test) and on MORE configurations with one laced arc closed as
// well. Every trial runs twice on the same directions, with the stall stop and
// without it, so the successes the stop costs are counted on the same
// trajectories; STALL sets the stop's switches without progress (the
// elimination's 2 by default), to weigh another setting. CLOTH sets the
// cloth: coarsened to CLOTH vertices (the stage's --cloth-max-vertices by
// default, the elimination's cloth), 0 for the garment as it is, -1 for it
// subdivided once (the final check's cloth when nothing is coarsened). The elimination's
// tests run K = 4 trials: a per-trial success rate p gives a test that
// passes with probability 1 - (1 - p)^4.
//   strip_rate DIR WEARER.obj [TRIALS [MORE [THREADS [STALL [CLOTH]]]]]
//   (defaults 24, 4, 2, 2, 1000)
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "planner/pipeline.hpp"
#include "planner/wearability/coarse_cloth.hpp"
#include "planner/wearability/wearability.hpp"
#include "planner/wearability/wearability_io.hpp"

namespace {

struct Job {
  int config = 0;
  int trial = 0;
  bool stall_stop = true;
};

struct Tally {
  int successes = 0;
  long success_steps = 0;
  long steps = 0;
  int stalled = 0;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: strip_rate DIR WEARER.obj [TRIALS [MORE [THREADS [STALL [CLOTH]]]]]\n";
    return 2;
  }
  const std::string dir = argv[1];
  const int trials = argc > 3 ? std::max(1, std::atoi(argv[3])) : 24;
  const int more = argc > 4 ? std::max(0, std::atoi(argv[4])) : 4;
  const int threads = argc > 5 ? std::max(1, std::atoi(argv[5])) : 2;
  const int stall =
      argc > 6 ? std::max(1, std::atoi(argv[6])) : planner::elimination_cloth().stall_switches;
  const int cloth_vertices =
      argc > 7 ? std::atoi(argv[7]) : planner::WearabilityStageParams{}.cloth_max_vertices;

  knitout::DiagnosticSink sink;
  // As the stage reads it by default (--cloth-vertices 500): a coarse garment
  // is subdivided for the cloth, its arcs keeping their indices.
  const auto cut = planner::read_cut(dir, sink);
  const auto labels = planner::read_wearability(dir, sink);
  const auto wearer = planner::read_stage_mesh(argv[2], sink);
  if (!cut || !labels || !wearer) {
    knitout::print_text(std::cerr, sink.diagnostics());
    return 1;
  }
  const planner::CoverMesh full = planner::cover_of(*cut, 500);
  const planner::CoverMesh cover = cloth_vertices < 0    ? planner::subdivided(full)
                                   : cloth_vertices == 0 ? full
                                                         : planner::coarsened(full, cloth_vertices);
  std::vector<bool> open(cover.arcs.size(), false);
  std::vector<int> laced;
  for (std::size_t a = 0; a < cover.arcs.size(); ++a) {
    open[a] = a >= labels->labels.size() || labels->labels[a] != planner::Label::Sew;
    if (open[a]) laced.push_back(static_cast<int>(a));
  }

  cloth::SdfParams sdf;
  sdf.threads = threads;
  const cloth::SignedDistanceField field(wearer->positions, wearer->faces, sdf);
  cloth::ClothParams params;
  params.threads = 1;
  const planner::CoverMesh garment = planner::dressed(cover, field, params);

  // Configuration 0 is the labelled one; configuration c > 0 closes one more
  // laced arc, spread evenly over the laced arcs.
  const int configs = 1 + std::min<int>(more, static_cast<int>(laced.size()));
  std::vector<std::vector<bool>> open_of(configs, open);
  std::vector<int> closed_arc(configs, -1);
  for (int c = 1; c < configs; ++c) {
    closed_arc[c] = laced[(c - 1) * laced.size() / (configs - 1)];
    open_of[c][closed_arc[c]] = false;
  }
  std::vector<cloth::PolygonMesh> meshes;
  for (const auto& o : open_of) meshes.push_back(planner::open_cuts(garment, o));

  std::vector<Job> jobs;
  for (int c = 0; c < configs; ++c) {
    for (int t = 0; t < trials; ++t) {
      jobs.push_back({c, t, true});
      jobs.push_back({c, t, false});
    }
  }
  std::vector<cloth::StripResult> results(jobs.size());
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t j = next++; j < jobs.size(); j = next++) {
      cloth::ClothParams p = params;
      p.stall_switches = jobs[j].stall_stop ? stall : 0;
      cloth::ClothSimulation sim(meshes[jobs[j].config], field, p);
      std::seed_seq seq{jobs[j].config, jobs[j].trial};
      std::mt19937_64 random(seq);
      results[j] = sim.run(random(), {});
    }
  };
  std::vector<std::thread> pool;
  for (int w = 0; w < threads; ++w) pool.emplace_back(work);
  for (auto& thread : pool) thread.join();

  std::printf(
      "%s: %zu arcs, %zu laced; %d trials per configuration, at most %d steps, stall stop after "
      "%d switches; cloth of %zu vertices\n",
      dir.c_str(), cover.arcs.size(), laced.size(), trials, params.max_steps, stall,
      cover.positions.size());
  std::printf("%-22s | %-36s | %s\n", "configuration", "with the stall stop", "without it");
  std::printf("%-22s | %-36s | %s\n", "", "off / steps when off / stalled / steps",
              "off / steps when off / steps");
  Tally all_with, all_without;
  for (int c = 0; c < configs; ++c) {
    Tally with, without;
    for (std::size_t j = 0; j < jobs.size(); ++j) {
      if (jobs[j].config != c) continue;
      Tally& tally = jobs[j].stall_stop ? with : without;
      Tally& total = jobs[j].stall_stop ? all_with : all_without;
      for (Tally* t : {&tally, &total}) {
        t->steps += results[j].steps;
        t->stalled += results[j].stalled ? 1 : 0;
        if (results[j].success) {
          ++t->successes;
          t->success_steps += results[j].steps;
        }
      }
    }
    const std::string name =
        c == 0 ? "labelled" : "+ arc " + std::to_string(closed_arc[c]) + " closed";
    auto mean = [](const Tally& t) { return t.successes ? t.success_steps / t.successes : 0L; };
    std::printf("%-22s | %3d / %14ld / %7d / %7ld | %3d / %14ld / %7ld\n", name.c_str(),
                with.successes, mean(with), with.stalled, with.steps, without.successes,
                mean(without), without.steps);
  }
  const int total = configs * trials;
  std::printf(
      "all %d trials: %d came off with the stall stop (%.0f%%) in %ld steps, %d without "
      "it (%.0f%%) in %ld steps\n",
      total, all_with.successes, 100.0 * all_with.successes / total, all_with.steps,
      all_without.successes, 100.0 * all_without.successes / total, all_without.steps);
  return 0;
}
