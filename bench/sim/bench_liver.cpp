// The liver benchmark: a liver-like organ of about 6k tets (Paloc 2006's liver: 1,576 nodes,
// 5,983 tets, E 4 kPa, nu 0.475, density 1050 kg/m^3) with Paloc 2006's mass-spring model, its
// flat side held, probed by a scripted tool that presses into the upper surface and strokes
// along it; steps per second with every node integrated and with the active region, and the
// active run's error against the full one in the probed region. One core.
//   bench_liver [steps] [cell_size m] [wake_force N] [sleep_speed m/s]
// The tool is force-driven (a load of 0.05 N spread over the surface nodes within 1 cm of its
// path point), so both runs see the same input.
#include <cstdio>
#include <cstdlib>

#include "sim/mesh/cgal/implicit_shape.h"
#include "sim/mesh/cgal/mesh_generation.h"
#include "sim/solve/stable_time_step.h"
#include "tests/sim/solve/poke_fixture.h"

using namespace incise::sim;
using namespace incise::sim::testing;

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::atoi(argv[1]) : 4000;
  const Real cell_size = argc > 2 ? std::atof(argv[2]) : 0.016;
  const Real wake = argc > 3 ? std::atof(argv[3]) : 5e-5;
  const Real sleep_speed = argc > 4 ? std::atof(argv[4]) : 1e-4;

  const Real length = 0.2;  // [m]
  const LobedOrgan liver = liver_like_organ(Vec3::Zero(), length);
  MeshingCriteria criteria;
  criteria.cell_size = cell_size;
  criteria.facet_size = cell_size;
  criteria.facet_distance = cell_size / 8;
  PokeSetup setup;
  setup.mesh = mesh_implicit(liver, implicit_extent(liver), criteria);
  setup.mesh.labels.setZero();
  // The flat (visceral) side rests on the abdomen: held.
  Real top = -1e9;
  for (int i = 0; i < setup.mesh.num_nodes(); ++i) {
    if (setup.mesh.rest(i, 2) < liver.flat_side_z + 1e-4) setup.fixed.push_back(i);
    top = std::max(top, setup.mesh.rest(i, 2));
  }
  setup.dt = stable_time_step(setup.mesh, kYoungs, 0.3, kDensity);

  // The tool's path: across the upper surface along x, from -L/4 to +L/4 over the first half of
  // the run, then lifted. Its load goes to the surface nodes within 1 cm of the path point's
  // (x, y) among those in the top 2 cm.
  const auto tool_point = [&](int step) {
    const Real s = std::min(1.0, 2.0 * step / steps);
    return Vec3(-length / 4 + s * length / 2, 0.0, top);
  };
  std::vector<int> upper;
  for (int i = 0; i < setup.mesh.num_nodes(); ++i) {
    if (setup.mesh.rest(i, 2) > top - 0.02) upper.push_back(i);
  }
  const LoadAt load = [&](int step, Points& f) {
    if (2 * step >= steps) return;
    const Vec3 p = tool_point(step);
    std::vector<int> under;
    for (const int i : upper) {
      const Vec3 q = row3(setup.mesh.rest, i);
      if (std::hypot(q.x() - p.x(), q.y() - p.y()) < 0.01) under.push_back(i);
    }
    for (const int i : under)
      f(i, 2) -= 0.05 / static_cast<Real>(under.size());
  };
  std::vector<int> region;  // within 3 cm of the path
  for (int i = 0; i < setup.mesh.num_nodes(); ++i) {
    const Vec3 q = row3(setup.mesh.rest, i);
    const Real dx = std::max({-length / 4 - q.x(), 0.0, q.x() - length / 4});
    if (std::hypot(dx, q.y()) < 0.03 && q.z() > top - 0.03) region.push_back(i);
  }

  ActiveRegionSettings settings;
  settings.wake_force = wake;
  settings.sleep_force = wake / 4;
  settings.sleep_speed = sleep_speed;
  settings.sleep_frames = 20;
  std::printf(
      "liver-like organ %.0f cm: %d nodes, %d tets (Paloc 2006: 1,576 / 5,983); dt = %.3g "
      "ms; %d steps\n",
      100 * length, setup.mesh.num_nodes(), setup.mesh.num_tets(), 1e3 * setup.dt, steps);
  const RunRecord full = full_run(setup, steps, region, load);
  const RunRecord active = active_run(setup, settings, steps, region, load);
  const RegionError e = region_error(active, full, setup.mesh.rest, region);
  long long active_tets = 0;
  int peak = 0;
  for (const ActiveRegionMetrics& m : active.metrics) {
    active_tets += m.active_tets;
    peak = std::max(peak, m.active_tets);
  }
  std::printf("full:   %.0f steps/s\n", steps / full.seconds);
  std::printf("active: %.0f steps/s (%.1fx); active tets mean %.0f, peak %d\n",
              steps / active.seconds, full.seconds / active.seconds, double(active_tets) / steps,
              peak);
  Real full_probing = 0, active_probing = 0;
  for (int s = 0; s < steps / 2; ++s) {
    full_probing += full.step_seconds[s];
    active_probing += active.step_seconds[s];
  }
  std::printf("while probing (first half): full %.0f steps/s, active %.0f steps/s\n",
              (steps / 2) / full_probing, (steps / 2) / active_probing);
  std::printf("probed region (%zu nodes): peak displacement %.3g mm, max error %.3g mm (%.2f%%)\n",
              region.size(), 1e3 * e.peak_displacement, 1e3 * e.max_error,
              100 * e.max_error / e.peak_displacement);
  return 0;
}
