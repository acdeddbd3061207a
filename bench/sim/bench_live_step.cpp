// Times one live-session tick of a scene with a tool: the sub-steps of one 2 ms tick, each with
// the sphere contact, as the server's session thread runs them. Prints the median and 95th
// percentile tick time and the real-time factor (tick length / tick time; >= 1 keeps up).
//   bench_live_step [SCENE.json [TICKS]]   (default: sim/scenes/palpation.json, 2000 ticks)
// The tool is pressed 6 mm into the centre of the block's top face and held, after a settling
// phase that is not timed.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "sim/interact/tool_contact.h"
#include "sim/io/scene_json.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/scene/simulation.h"

namespace {

using namespace incise::sim;

constexpr Real kTick = 0.002;  // [s], the server's tick

int run(const std::string& scene_file, int ticks) {
  const Scene scene = read_scene_file(scene_file);
  const SphereTool tool = scene.tool.value_or(SphereTool{});
  Simulation simulation(scene);
  const BoundarySurface surface = boundary_surface(simulation.mesh());
  const auto sub_steps = static_cast<int>(std::lround(kTick / scene.solver.dt));
  if (sub_steps < 1 || std::abs(sub_steps * scene.solver.dt - kTick) > 1e-9 * kTick) {
    std::fprintf(stderr, "solver.dt = %g does not divide the %g s tick\n", scene.solver.dt, kTick);
    return 1;
  }
  const Vec3 size = scene.mesh.box.size;
  const Vec3 top_centre(size.x() / 2, size.y() / 2, size.z());
  const Vec3 pressed = top_centre + Vec3(0, 0, tool.radius - 0.006);

  Points contact_forces = Points::Zero(simulation.mesh().num_nodes(), 3);
  ToolContact contact;
  const auto tick = [&](const Vec3& centre) {
    for (int s = 0; s < sub_steps; ++s) {
      contact_forces.setZero();
      contact = apply_sphere_contact(tool, centre, surface, simulation.mesh().x, contact_forces);
      simulation.step(contact_forces);
    }
  };
  // Lower the tool from just above the surface over 0.2 s, then let the tissue settle for 0.5 s.
  const int ramp_ticks = static_cast<int>(0.2 / kTick);
  const Vec3 above = top_centre + Vec3(0, 0, tool.radius);
  for (int t = 1; t <= ramp_ticks; ++t)
    tick(above + (pressed - above) * t / ramp_ticks);
  for (int t = 0; t < static_cast<int>(0.5 / kTick); ++t)
    tick(pressed);

  std::vector<double> micros(static_cast<std::size_t>(ticks));
  for (auto& time : micros) {
    const auto start = std::chrono::steady_clock::now();
    tick(pressed);
    const auto stop = std::chrono::steady_clock::now();
    time = std::chrono::duration<double, std::micro>(stop - start).count();
  }
  if (!simulation.state_finite()) {
    std::fprintf(stderr, "the state is not finite\n");
    return 1;
  }
  std::sort(micros.begin(), micros.end());
  const double median = micros[micros.size() / 2];
  const double p95 = micros[micros.size() * 95 / 100];
  std::printf("scene %s: %d nodes, %d surface nodes, %d springs, dt %g s, %d sub-steps per tick\n",
              scene_file.c_str(), simulation.mesh().num_nodes(),
              static_cast<int>(surface.nodes.size()), simulation.model().num_springs(),
              scene.solver.dt, sub_steps);
  std::printf("tool: %d nodes in contact, force on tool (%.4f, %.4f, %.4f) N\n",
              contact.nodes_in_contact, contact.force_on_tool.x(), contact.force_on_tool.y(),
              contact.force_on_tool.z());
  std::printf(
      "tick of %.0f us over %d ticks: median %.1f us, p95 %.1f us, real-time factor %.2f "
      "(median), %.2f (p95)\n",
      kTick * 1e6, ticks, median, p95, kTick * 1e6 / median, kTick * 1e6 / p95);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string scene = argc > 1 ? argv[1] : INCISE_SCENES_DIR "/palpation.json";
    const int ticks = argc > 2 ? std::atoi(argv[2]) : 2000;
    if (ticks < 1) {
      std::fprintf(stderr, "TICKS must be a positive integer\n");
      return 2;
    }
    return run(scene, ticks);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "bench_live_step: %s\n", error.what());
    return 1;
  }
}
