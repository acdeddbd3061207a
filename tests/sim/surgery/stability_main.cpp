// surgery_stability: the surgical scenes' stability suite at full size (stability_suite.h). Runs
// random tool sequences on the liver and knee scenes and prints, per scene, how many ran, the
// failures with their seeds, and the worst cases. Exits 1 on any failure, 2 on bad arguments.
//
//   surgery_stability [--sequences N] [--steps M] [--seed S] [--scene liver|knee|both]
//                     [--seconds T] [--verbose] [--no-simplify] [--trace N]
//                     [--no-adaptivity]
// Steps default to 1500 (liver) and 6000 (knee). Sequence k of a scene has seed S + k; --seconds
// stops each scene after T / #scenes seconds (whatever --sequences says). Replay a failure: --scene
// <it> --seed <its seed> --sequences 1.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "stability_suite.h"

namespace stab = incise::sim::surgery::stability;
using incise::sim::surgery::EventKind;
using incise::sim::surgery::to_string;

namespace {

struct Options {
  long sequences = 100;
  int steps = 0;  // 0: the scene's default (default_generator)
  std::uint64_t seed = 1;
  std::vector<std::string> scenes = {"liver", "knee"};
  double seconds = 0;      // 0: no time limit
  bool verbose = false;    // a line per sequence
  bool simplify = true;    // --no-simplify: no sliver collapses after strokes (for comparison)
  bool adaptivity = true;  // --no-adaptivity: no refinement around the tools (for comparison)
  int trace_every = 0;     // --trace N: a line every N steps of each sequence (stderr)
};

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "surgery_stability: %s\nusage: surgery_stability [--sequences N] [--steps M] "
               "[--seed S] [--scene liver|knee|both] [--seconds T] [--verbose] [--no-simplify] "
               "[--no-adaptivity] [--trace N]\n",
               why.c_str());
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--verbose") {
      o.verbose = true;
      continue;
    }
    if (arg == "--no-adaptivity") {
      o.adaptivity = false;
      continue;
    }
    if (arg == "--no-simplify") {
      o.simplify = false;
      continue;
    }
    if (i + 1 >= argc) usage("missing a value after " + arg);
    const std::string value = argv[++i];
    try {
      if (arg == "--sequences") {
        o.sequences = std::stol(value);
        if (o.sequences < 1) usage("--sequences must be >= 1");
      } else if (arg == "--steps") {
        o.steps = std::stoi(value);
        if (o.steps < 1) usage("--steps must be >= 1");
      } else if (arg == "--seed") {
        o.seed = std::stoull(value);
      } else if (arg == "--scene") {
        if (value == "both") {
          o.scenes = {"liver", "knee"};
        } else if (value == "liver" || value == "knee") {
          o.scenes = {value};
        } else {
          usage("--scene must be liver, knee or both, not " + value);
        }
      } else if (arg == "--trace") {
        o.trace_every = std::stoi(value);
        if (o.trace_every < 1) usage("--trace must be >= 1");
      } else if (arg == "--seconds") {
        o.seconds = std::stod(value);
        if (!(o.seconds > 0)) usage("--seconds must be > 0");
      } else {
        usage("unknown argument " + arg);
      }
    } catch (const std::logic_error&) {
      usage("bad value '" + value + "' for " + arg);
    }
  }
  return o;
}

// The result that is largest by key, and whether there is one.
const stab::SequenceResult* worst(const std::vector<stab::SequenceResult>& results,
                                  const std::function<double(const stab::SequenceResult&)>& key) {
  const stab::SequenceResult* w = nullptr;
  for (const stab::SequenceResult& r : results) {
    if (w == nullptr || key(r) > key(*w)) w = &r;
  }
  return w;
}

void print_worst(const std::vector<stab::SequenceResult>& results, const char* what,
                 const std::function<double(const stab::SequenceResult&)>& key) {
  const stab::SequenceResult* w = worst(results, key);
  if (w == nullptr) return;
  std::printf(
      "  %-28s %10.4g  seed %-8llu (%d steps + %d settle, %.2f s, tets %d -> peak %d, "
      "peak inverted %d, cuts refused %d)\n",
      what, key(*w), static_cast<unsigned long long>(w->seed), w->steps, w->settle_steps,
      w->seconds, w->initial_tets, w->peak_tets, w->peak_inverted, w->cuts_refused);
}

// Runs a scene's sequences; returns its failures.
int run_scene(const std::string& name, const Options& o, double budget) {
  using Clock = std::chrono::steady_clock;
  const auto built = Clock::now();
  incise::sim::surgery::SurgicalSceneSetup setup = stab::stability_scene(name);
  if (!o.simplify) setup.spec.simplify.min_quality = 0;
  if (!o.adaptivity) setup.spec.adaptivity.enabled = false;
  const stab::SceneGeometry geometry = stab::geometry_of(setup);
  const double build_seconds = std::chrono::duration<double>(Clock::now() - built).count();
  stab::GeneratorSettings generator = stab::default_generator(name);
  if (o.steps > 0) generator.steps = o.steps;
  stab::RunSettings run;
  run.trace_every = o.trace_every;
  std::vector<stab::SequenceResult> results;
  long rss_first = -1;  // after the first sequence: what the scene itself takes
  const auto start = Clock::now();
  for (long k = 0; k < o.sequences; ++k) {
    if (budget > 0 && std::chrono::duration<double>(Clock::now() - start).count() > budget) break;
    const std::uint64_t seed = o.seed + static_cast<std::uint64_t>(k);
    const stab::Sequence sequence = stab::make_sequence(geometry, seed, generator);
    results.push_back(stab::run_sequence(setup.spec, name, sequence, run));
    const stab::SequenceResult& r = results.back();
    if (!r.passed) {
      std::fprintf(stderr, "FAIL %s seed %llu: %s\n", name.c_str(),
                   static_cast<unsigned long long>(seed), r.failure.c_str());
    }
    if (o.verbose) {
      std::printf(
          "%s seed %llu: %s, %d+%d steps, %.2f s, tets %d->%d (peak %d), inverted peak %d "
          "end %d, speed at end %.3g m/s, refused %d, cuts %d, grabs %d\n",
          name.c_str(), static_cast<unsigned long long>(seed), r.passed ? "ok" : "FAIL", r.steps,
          r.settle_steps, r.seconds, r.initial_tets, r.final_tets, r.peak_tets, r.peak_inverted,
          r.inverted_at_end, r.speed_at_end, r.cuts_refused,
          r.events[static_cast<std::size_t>(EventKind::cut)],
          r.events[static_cast<std::size_t>(EventKind::grasp)]);
    }
    if (k == 0) rss_first = stab::resident_kib();
    if ((k + 1) % 100 == 0) {
      std::fprintf(stderr, "%s: %ld sequences, %.0f s, RSS %ld KiB\n", name.c_str(), k + 1,
                   std::chrono::duration<double>(Clock::now() - start).count(),
                   stab::resident_kib());
    }
  }
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  int failures = 0;
  long steps = 0, settle = 0;
  long recovered = 0;  // sequences whose tissue pulled inverted tets back (a tangle recovered)
  std::array<long, stab::kSegmentKinds> segments{};
  std::array<long, stab::kEventKinds> events{};
  for (const stab::SequenceResult& r : results) {
    failures += r.passed ? 0 : 1;
    recovered += r.inverted_tets_pulled > 0 ? 1 : 0;
    steps += r.steps;
    settle += r.settle_steps;
    for (int k = 0; k < stab::kSegmentKinds; ++k)
      segments[static_cast<std::size_t>(k)] += r.segments[static_cast<std::size_t>(k)];
    for (int k = 0; k < stab::kEventKinds; ++k)
      events[static_cast<std::size_t>(k)] += r.events[static_cast<std::size_t>(k)];
  }
  std::printf("\n== %s: %zu tets, %zu nodes, dt %.3g s (built in %.1f s)\n", name.c_str(),
              static_cast<std::size_t>(setup.spec.tissue.num_tets()),
              static_cast<std::size_t>(setup.spec.tissue.num_nodes()), setup.spec.dt,
              build_seconds);
  std::printf(
      "  sequences %zu (seeds %llu..%llu), failures %d, %.1f s; %ld sequence steps + %ld "
      "retract/settle steps (%.0f steps/s)\n",
      results.size(), static_cast<unsigned long long>(o.seed),
      static_cast<unsigned long long>(o.seed + results.size() - 1), failures, seconds, steps,
      settle, static_cast<double>(steps + settle) / seconds);
  std::printf("  RSS %ld KiB after the first sequence, %ld KiB after the last\n", rss_first,
              stab::resident_kib());
  std::printf("  sequences whose tissue recovered inverted tets once left alone: %ld\n", recovered);
  std::printf("  segments:");
  for (int k = 0; k < stab::kSegmentKinds; ++k) {
    std::printf(" %s %ld", std::string(stab::to_string(static_cast<stab::SegmentKind>(k))).c_str(),
                segments[static_cast<std::size_t>(k)]);
  }
  std::printf("\n  events:  ");
  for (int k = 0; k < stab::kEventKinds; ++k) {
    std::printf(" %s %ld", std::string(to_string(static_cast<EventKind>(k))).c_str(),
                events[static_cast<std::size_t>(k)]);
  }
  std::printf("\n  worst cases:\n");
  using R = stab::SequenceResult;
  print_worst(results, "peak inverted elements", [](const R& r) { return r.peak_inverted; });
  print_worst(results, "inverted at end", [](const R& r) { return r.inverted_at_end; });
  print_worst(results, "peak tets / initial",
              [](const R& r) { return static_cast<double>(r.peak_tets) / r.initial_tets; });
  print_worst(results, "peak nodes / initial",
              [](const R& r) { return static_cast<double>(r.peak_nodes) / r.initial_nodes; });
  print_worst(results, "settle steps", [](const R& r) { return r.settle_steps; });
  print_worst(results, "max node speed at end [m/s]", [](const R& r) { return r.speed_at_end; });
  print_worst(results, "cuts refused", [](const R& r) { return r.cuts_refused; });
  print_worst(results, "inverted tets pulled", [](const R& r) { return r.inverted_tets_pulled; });
  print_worst(results, "peak mass-scaled nodes",
              [](const R& r) { return r.peak_mass_scaled_nodes; });
  print_worst(results, "max mass scale", [](const R& r) { return r.max_mass_scale; });
  print_worst(results, "mass scale at end", [](const R& r) { return r.mass_scale_at_end; });
  print_worst(results, "edge collapses", [](const R& r) { return r.collapses; });
  print_worst(results, "edge splits", [](const R& r) { return r.splits; });
  print_worst(results, "splits not undone", [](const R& r) { return r.splits - r.splits_undone; });
  print_worst(results, "wall time [s]", [](const R& r) { return r.seconds; });
  for (const R& r : results) {
    if (!r.passed) {
      std::printf("  FAILED seed %llu: %s\n", static_cast<unsigned long long>(r.seed),
                  r.failure.c_str());
    }
  }
  return failures;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const long rss_start = stab::resident_kib();
  int failures = 0;
  try {
    for (const std::string& scene : o.scenes) {
      failures +=
          run_scene(scene, o, o.seconds > 0 ? o.seconds / static_cast<double>(o.scenes.size()) : 0);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "surgery_stability: %s\n", e.what());
    return 1;
  }
  std::printf("\nRSS: %ld KiB at start, %ld KiB at end\n", rss_start, stab::resident_kib());
  std::printf("%s: %d failure(s)\n", failures == 0 ? "PASS" : "FAIL", failures);
  return failures == 0 ? 0 : 1;
}
