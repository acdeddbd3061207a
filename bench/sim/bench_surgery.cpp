// bench_surgery: the surgical scenes' benchmarks on the stability suite's scenes (liver cell 10 mm,
// knee tissue cell 4 mm; stability_suite.h). Per scene:
//   idle      every tool away: SurgicalScene::step per step;
//   probing   the probe pressed 6 mm into a target and dragged slowly;
//   cutting   after the probe is lifted and the tissue has settled, the scalpel along the marked
//             cut line 5 mm deep at 5 cm/s; steps on which the
//             cutter runs (every cut_every steps) are timed apart from the others, and the cut
//             update per call is estimated as each such step minus the step before it;
//   collision the probing state's surface tree (a copy of tissue().bvh()): refit to x, the probe
//             tip's sphere contacts and its shaft capsule's overlapping triangles, per step;
//   force     SurgicalScene::force_model(device) calls per second while the probe is in contact
//             (timed in batches of 1000 calls: one takes tens of nanoseconds);
//   adapt     the steps that refine around the probe as it lands and coarsen once it has left
//             (the scene's adaptivity; --no-adaptivity turns it off for comparison).
// Times are wall clock (steady_clock) on one thread; medians and 99th percentiles per step.
//
//   bench_surgery [--scene liver|knee|both] [--steps N] [--no-adaptivity]

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <string>
#include <vector>

#include "sim/collide/surface_bvh.h"
#include "tests/sim/surgery/stability_suite.h"

namespace {

using incise::sim::Real;
using incise::sim::Vec3;
using namespace incise::sim::surgery;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// q-quantile of samples (sorted in place) [same unit].
double quantile(std::vector<double>& samples, double q) {
  if (samples.empty()) return 0;
  std::sort(samples.begin(), samples.end());
  const auto k = static_cast<std::size_t>(q * static_cast<double>(samples.size() - 1));
  return samples[k];
}

double mean(const std::vector<double>& samples) {
  double sum = 0;
  for (const double s : samples)
    sum += s;
  return samples.empty() ? 0 : sum / static_cast<double>(samples.size());
}

ToolInput at(const Vec3& tip, const Vec3& direction) {
  ToolInput in;
  in.tip = tip;
  in.orientation = Eigen::Quaternion<Real>::FromTwoVectors(Vec3::UnitZ(), direction.normalized());
  return in;
}

void row(const char* what, std::vector<double> seconds) {
  const double m = mean(seconds);
  const double median = quantile(seconds, 0.5), p99 = quantile(seconds, 0.99);
  std::printf("  %-40s %8zu %10.3f %10.3f %10.3f %10.0f\n", what, seconds.size(), 1e6 * median,
              1e6 * p99, 1e6 * m, m > 0 ? 1 / m : 0);
}

void bench(const std::string& name, int steps, bool adaptivity) {
  SurgicalSceneSetup setup = stability::stability_scene(name);
  setup.spec.adaptivity.enabled = setup.spec.adaptivity.enabled && adaptivity;
  const stability::SceneGeometry g = stability::geometry_of(setup);
  SurgicalScene scene(setup.spec);
  const int probe_device = name == "liver" ? 0 : 1;
  const std::size_t probe = static_cast<std::size_t>(probe_device);
  const std::size_t scalpel = 2;
  // Each tool at its start (home or outside its portal), as the stability suite puts them.
  const stability::Sequence rest = stability::make_sequence(g, 1, {});
  std::vector<ToolInput> inputs;
  for (const stability::DeviceScript& d : rest.devices)
    inputs.push_back(d.start);
  std::printf(
      "\n== %s: %d tets, %d nodes, dt %.3g s, cut every %d steps (%.3g ms), adaptivity %s\n",
      name.c_str(), scene.tissue().mesh().num_tets(), scene.tissue().mesh().num_nodes(),
      setup.spec.dt, setup.spec.cut_every, 1e3 * setup.spec.cut_every * setup.spec.dt,
      setup.spec.adaptivity.enabled ? "on" : "off");
  std::printf("  %-40s %8s %10s %10s %10s %10s\n", "[per call]", "calls", "median us", "p99 us",
              "mean us", "per s");
  std::vector<double> idle, probing, refit, query, cut_steps, other_steps, cut_update, force;
  std::vector<double> refining, coarsening;  // the steps that split or undid edges
  auto timed_step = [&](std::vector<double>& out) {
    const auto t = Clock::now();
    scene.step(inputs);
    out.push_back(since(t));
  };
  for (int n = 0; n < steps; ++n)
    timed_step(idle);
  row("step, idle", idle);

  // Probing: down onto the first cut-line point (liver, from above) or the medial meniscus's
  // anterior horn (knee, through the probe's portal), 6 mm past it, then a slow drag.
  const Vec3 target =
      name == "liver" ? setup.cut_target.front()
                      : find_landmark(setup.landmarks, "medial_meniscus_anterior_horn").position;
  const Vec3 a =
      name == "liver" ? Vec3(-Vec3::UnitZ()) : (target - g.entries[1].position).normalized();
  const Vec3 entry = target - 0.02 * a;
  const int tets_idle = scene.tissue().mesh().num_tets();
  for (int n = 0; n < 400; ++n) {
    const Real s = std::min(1.0, n / 300.0);
    inputs[probe] = at(entry + s * 0.026 * a, a);
    const int splits = scene.splits();
    const auto t = Clock::now();
    scene.step(inputs);
    if (scene.splits() != splits) refining.push_back(since(t));
  }
  const int tets_pressed = scene.tissue().mesh().num_tets();
  incise::sim::collide::SurfaceBvh bvh = scene.tissue().bvh();
  std::vector<incise::sim::collide::Contact> contacts;
  std::vector<int> overlaps;
  const Vec3 side = a.unitOrthogonal();
  for (int n = 0; n < steps; ++n) {
    const Vec3 tip = target + 0.006 * a + (0.005 * n / steps) * side;
    inputs[probe] = at(tip, a);
    timed_step(probing);
    const incise::sim::Points& x = scene.tissue().mesh().x;
    auto t = Clock::now();
    bvh.refit(x);
    refit.push_back(since(t));
    t = Clock::now();
    bvh.contacts(x, {tip, 0.0025}, contacts);
    bvh.overlapping_triangles(x, {tip - 0.25 * a, tip, 0.0025}, overlaps);
    query.push_back(since(t));
  }
  const int in_contact = scene.tool_view(probe_device).touching ? 1 : 0;
  // One call takes tens of nanoseconds: timed in batches of 1000.
  for (int batch = 0; batch < 200; ++batch) {
    const auto t = Clock::now();
    Real sum = 0;
    for (int n = 0; n < 1000; ++n)
      sum += scene.force_model(probe_device).force.x();
    force.push_back(since(t) / 1000);
    if (!std::isfinite(sum)) std::abort();
  }
  row("step, probing", probing);
  row("adapt: step that refines (probe lands)", refining);
  std::printf("  adapt: %d splits (%d refused), tets %d -> %d under the probe\n", scene.splits(),
              scene.splits_refused(), tets_idle, tets_pressed);
  row("collision: bvh refit", refit);
  row("collision: tip + shaft queries", query);
  row(in_contact != 0 ? "force_model (probe in contact)" : "force_model (probe NOT touching)",
      force);

  // Cutting: the probe lifted away slowly and the tissue left to settle, then the scalpel down
  // onto the marked line's start, slowly.
  const Vec3 pressed = inputs[probe].tip;
  const Vec3 home = rest.devices[probe].start.tip;
  int settle = 0;  // steps until no element is inverted (the scalpel would be refused)
  for (; settle < 500 || (settle < 50000 && scene.tissue().model().health().inverted_elements > 0);
       ++settle) {
    const Real s = std::min(1.0, settle / 500.0);
    inputs[probe] = at(pressed + s * (home - pressed), a);
    const int undone = scene.splits_undone();
    const auto t = Clock::now();
    scene.step(inputs);
    if (scene.splits_undone() != undone) coarsening.push_back(since(t));
  }
  std::printf("  probe lifted: %d steps until no inverted element (%d now)\n", settle,
              scene.tissue().model().health().inverted_elements);
  const Vec3 p0 = setup.cut_target.front(), p1 = setup.cut_target.back();
  const Vec3 down =
      name == "liver" ? Vec3(-Vec3::UnitZ()) : (p0 - g.entries[2].position).normalized();
  for (int n = 0; n < 600; ++n) {
    const Real s = std::min(1.0, n / 400.0);
    inputs[scalpel] = at(p0 - 0.02 * down + s * 0.025 * down, down);
    const int undone = scene.splits_undone();
    const auto t = Clock::now();
    scene.step(inputs);
    if (scene.splits_undone() != undone) coarsening.push_back(since(t));
  }
  row("adapt: step that coarsens (probe gone)", coarsening);
  std::printf("  adapt: %d of %d splits undone, tets %d\n", scene.splits_undone(), scene.splits(),
              scene.tissue().mesh().num_tets());
  const Real speed = 0.05;
  const int stroke =
      std::max(1, static_cast<int>(std::ceil((p1 - p0).norm() / (speed * setup.spec.dt))));
  int cuts = 0;
  scene.take_events();
  const int tets_before = scene.tissue().mesh().num_tets();
  int finite_until = stroke;
  for (int n = 0; n < stroke; ++n) {
    if (!scene.state_finite()) {
      finite_until = n;
      break;
    }
    const Real s = static_cast<Real>(n + 1) / stroke;
    inputs[scalpel] = at(p0 + s * (p1 - p0) + 0.005 * down, down);
    const bool cutter = scene.steps() % setup.spec.cut_every == 0;
    timed_step(cutter ? cut_steps : other_steps);
    // The cutter's own cost: its step minus the step before (the mesh and the model change along
    // the stroke, so a global median of the others would not do).
    if (cutter && !other_steps.empty() && n > 0) {
      cut_update.push_back(cut_steps.back() - other_steps.back());
    }
    for (const SceneEvent& e : scene.take_events())
      cuts += e.kind == EventKind::cut ? 1 : 0;
  }
  std::vector<double> all = cut_steps;
  all.insert(all.end(), other_steps.begin(), other_steps.end());
  row("step, cutting (all)", all);
  row("step, cutting, cutter runs", cut_steps);
  row("step, cutting, cutter idle", other_steps);
  row("cut update (cutter step - step before)", cut_update);
  std::printf(
      "  cut stroke: %d steps at %.2f m/s over %.1f mm, %d cut events, tets %d -> %d, "
      "cuts refused %d, finite %s\n",
      stroke, speed, 1e3 * (p1 - p0).norm(), cuts, tets_before, scene.tissue().mesh().num_tets(),
      scene.cuts_refused(), scene.state_finite() ? "yes" : "NO");
  if (finite_until < stroke || !scene.state_finite()) {
    std::printf(
        "  WARNING: the tissue went non-finite at stroke step %d of %d: the times after it "
        "are not representative\n",
        finite_until, stroke);
  }
  std::printf("  simulated time per wall time while cutting: %.3f (real time = 1)\n",
              setup.spec.dt / mean(all));
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> scenes = {"liver", "knee"};
  int steps = 2000;
  bool adaptivity = true;
  std::vector<std::string> args(argv + 1, argv + argc);
  if (const auto no = std::find(args.begin(), args.end(), "--no-adaptivity"); no != args.end()) {
    adaptivity = false;
    args.erase(no);
  }
  const auto usage = [] {
    std::fprintf(stderr,
                 "usage: bench_surgery [--scene liver|knee|both] [--steps N] [--no-adaptivity]\n");
    return 2;
  };
  if (args.size() % 2 != 0) return usage();
  for (std::size_t i = 0; i + 1 < args.size(); i += 2) {
    const std::string arg = args[i], value = args[i + 1];
    if (arg == "--scene" && (value == "liver" || value == "knee")) {
      scenes = {value};
    } else if (arg == "--scene" && value == "both") {
      scenes = {"liver", "knee"};
    } else if (arg == "--steps" && std::atoi(value.c_str()) > 0) {
      steps = std::atoi(value.c_str());
    } else {
      return usage();
    }
  }
  try {
    for (const std::string& scene : scenes)
      bench(scene, steps, adaptivity);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_surgery: %s\n", e.what());
    return 1;
  }
  return 0;
}
