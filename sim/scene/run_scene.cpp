#include "sim/scene/run_scene.h"

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "sim/scene/simulation.h"

namespace incise::sim {

RunResult run_scene(const Scene& scene) {
  Simulation simulation(scene);
  const std::int64_t steps = scene.solver.steps;
  const std::int64_t stride = (steps + kMaxTimedSteps - 1) / kMaxTimedSteps;
  std::vector<double> step_ms;
  step_ms.reserve(static_cast<std::size_t>(std::min(steps, kMaxTimedSteps)));

  RunResult result;
  for (std::int64_t n = 0; n < steps; ++n) {
    if (n % stride == 0) {
      const auto start = std::chrono::steady_clock::now();
      simulation.step();
      const auto end = std::chrono::steady_clock::now();
      step_ms.push_back(std::chrono::duration<double, std::milli>(end - start).count());
    } else {
      simulation.step();
    }
    if (!simulation.state_finite()) {
      result.finite = false;
      result.status = "not finite at step " + std::to_string(n + 1) +
                      ": a position or velocity became NaN or infinite; try a smaller solver.dt";
      break;
    }
  }

  const auto middle = step_ms.begin() + static_cast<std::ptrdiff_t>(step_ms.size() / 2);
  std::nth_element(step_ms.begin(), middle, step_ms.end());
  result.ms_per_step = *middle;
  if (step_ms.size() % 2 == 0) {
    result.ms_per_step = (result.ms_per_step + *std::max_element(step_ms.begin(), middle)) / 2;
  }
  const TetMesh& mesh = simulation.mesh();
  result.rest = mesh.rest;
  result.displacement = mesh.x - mesh.rest;
  result.final_positions = mesh.x;
  result.num_tets = mesh.num_tets();
  result.steps = simulation.steps_taken();
  result.max_speed = simulation.max_speed();
  return result;
}

}  // namespace incise::sim
