// Steps per second with and without the active region for a local poke on a ~6k-tet box
// (12 x 12 x 8 cells, 5760 tets, bottom clamped, Paloc 2006's mass-spring model at the stable
// step), and the error of the active run against the full one in the poked region.
//   bench_active_region [steps] [pulse_steps] [poke_force N] [wake_force N] [sleep_speed m/s]
// (sleep_force = wake_force / 4, sleep_frames = 20)
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tests/sim/solve/poke_fixture.h"

using namespace incise::sim;
using namespace incise::sim::testing;

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 3000;
  const int pulse = argc > 2 ? std::atoi(argv[2]) : 20;
  const Real poke = argc > 3 ? std::atof(argv[3]) : 0.02;
  const Real wake = argc > 4 ? std::atof(argv[4]) : 1e-4;
  const Real sleep_speed = argc > 5 ? std::atof(argv[5]) : 2e-4;
  const PokeSetup setup = make_poke_setup(Vec3i(12, 12, 8));
  const std::vector<int> region = nodes_near(setup.mesh, setup.poked, 0.02);
  const LoadAt load = [&](int step, Points& f) {
    if (step < pulse) f(setup.poked, 2) = -poke;
  };
  ActiveRegionSettings settings;
  settings.wake_force = wake;
  settings.sleep_force = wake / 4;
  settings.sleep_speed = sleep_speed;
  settings.sleep_frames = 20;

  std::printf("mesh: %d nodes, %d tets; dt = %.3g s; %d steps; poke %.3g N for %d steps\n",
              setup.mesh.num_nodes(), setup.mesh.num_tets(), setup.dt, steps, poke, pulse);
  const RunRecord full = full_run(setup, steps, region, load);
  const RunRecord active = active_run(setup, settings, steps, region, load);
  const RegionError e = region_error(active, full, setup.mesh.rest, region);

  long long tet_steps = 0, eval_steps = 0;
  int peak_active = 0, rebuild_steps = 0, last_active_step = -1;
  for (std::size_t s = 0; s < active.metrics.size(); ++s) {
    const ActiveRegionMetrics& m = active.metrics[s];
    tet_steps += m.active_tets;
    eval_steps += m.evaluated_tets;
    peak_active = std::max(peak_active, m.active_tets);
    rebuild_steps += m.rebuilt ? 1 : 0;
    if (m.active_nodes > 0) last_active_step = static_cast<int>(s);
  }
  std::printf("full:   %.0f steps/s (%.3g s)\n", steps / full.seconds, full.seconds);
  std::printf("active: %.0f steps/s (%.3g s), speed-up %.1f\n", steps / active.seconds,
              active.seconds, full.seconds / active.seconds);
  std::printf("active tets: mean %.1f, peak %d of %d; evaluated (active + halo) mean %.1f\n",
              double(tet_steps) / steps, peak_active, setup.mesh.num_tets(),
              double(eval_steps) / steps);
  std::printf("steps with a rebuild: %d; last step with an active node: %d\n", rebuild_steps,
              last_active_step);
  Real full_phase = 0, active_phase = 0;
  for (int s = 0; s <= last_active_step; ++s) {
    full_phase += full.step_seconds[s];
    active_phase += active.step_seconds[s];
  }
  std::printf("while awake (steps 0-%d): full %.0f steps/s, active %.0f steps/s\n",
              last_active_step, (last_active_step + 1) / full_phase,
              (last_active_step + 1) / active_phase);
  std::printf(
      "poked region (%zu nodes within 2 cm): peak displacement %.4g m, max error %.4g m "
      "(%.2f%%)\n",
      region.size(), e.peak_displacement, e.max_error, 100 * e.max_error / e.peak_displacement);
  std::printf("final max |x_active - x_full| over all nodes: %.3g m\n",
              (active.final_x - full.final_x).rowwise().norm().maxCoeff());
  return 0;
}
