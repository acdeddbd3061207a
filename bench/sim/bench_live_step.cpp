// Times one live-session tick of a block scene with a probe: the sub-steps of one 2 ms tick of
// the block as a surgical scene (make_block_surgery, the runtime every live session runs), as the
// server's session thread runs them. Prints the median and 95th percentile tick time and the
// real-time factor (tick length / tick time; >= 1 keeps up).
//   bench_live_step [SCENE.json [TICKS]]   (default: sim/scenes/palpation.json, 2000 ticks)
// The probe is pressed 6 mm below touching the centre of the block's top face and held, after a
// settling phase that is not timed.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "sim/io/scene_json.h"
#include "sim/surgery/scene_presets.h"
#include "sim/surgery/surgical_scene.h"

namespace {

using namespace incise::sim;
using namespace incise::sim::surgery;

constexpr Real kTick = 0.002;  // [s], the server's tick

int run(const std::string& scene_file, int ticks) {
  const Scene scene = read_scene_file(scene_file);
  const Real radius = scene.tool.value_or(SphereTool{}).radius;
  SurgicalSceneSpec spec = make_block_surgery(scene).spec;
  const auto sub_steps = static_cast<int>(std::ceil(kTick / spec.dt - 1e-9));
  spec.dt = kTick / sub_steps;  // as the server shortens it (server/live/surgery_world.h)
  SurgicalScene block(spec);
  const Vec3 size = scene.mesh.box.size;
  const Vec3 top_centre(size.x() / 2, size.y() / 2, size.z());
  const Vec3 pressed = top_centre + Vec3(0, 0, radius - 0.006);

  std::vector<ToolInput> input(1);
  input[0].orientation = Eigen::Quaternion<Real>(0, 1, 0, 0);  // pointing down
  const auto tick = [&](const Vec3& tip) {
    for (int s = 0; s < sub_steps; ++s) {
      input[0].tip = tip;
      block.step(input);
    }
  };
  // Lower the tool from just above the surface over 0.2 s, then let the tissue settle for 0.5 s.
  const int ramp_ticks = static_cast<int>(0.2 / kTick);
  const Vec3 above = top_centre + Vec3(0, 0, radius);
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
  if (!block.state_finite()) {
    std::fprintf(stderr, "the state is not finite\n");
    return 1;
  }
  std::sort(micros.begin(), micros.end());
  const double median = micros[micros.size() / 2];
  const double p95 = micros[micros.size() * 95 / 100];
  const TetMesh& mesh = block.tissue().mesh();
  const Vec3 force = block.force_model(0).force;
  std::printf("scene %s: %d nodes, %d tets, %d surface nodes, dt %g s, %d sub-steps per tick\n",
              scene_file.c_str(), mesh.num_nodes(), mesh.num_tets(),
              static_cast<int>(block.tissue().surface().nodes.size()), spec.dt, sub_steps);
  std::printf("probe pressed 6 mm: force on the hand (%.4f, %.4f, %.4f) N\n", force.x(), force.y(),
              force.z());
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
