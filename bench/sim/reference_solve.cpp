#include "reference_solve.h"

#include <algorithm>
#include <chrono>

#include "sim/scene/node_selection.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/static_solver.h"

namespace incise::bench {

using sim::Points;
using sim::Real;

ReferenceResult reference_static_solve(const sim::Scene& scene, const sim::TetMesh& mesh,
                                       int increments, Real tolerance, sim::LinearSolver solver) {
  const auto start = std::chrono::steady_clock::now();
  auto model = sim::make_model(scene, mesh);
  const Eigen::Index n = mesh.num_nodes();
  const Real widen = sim::selection_tolerance(mesh.rest);

  // Constraints and loads resolved to nodes as scene_run.cpp does: later constraints win per axis,
  // a load is split equally over its nodes.
  sim::Prescribed prescribed;
  prescribed.mask = sim::AxisMask::Zero(n, 3);
  Points full_displacement = Points::Zero(n, 3);
  Points full_loads = Points::Zero(n, 3);
  for (const auto& constraint : scene.constraints) {
    for (const int i : sim::nodes_in_box(mesh.rest, constraint.where.box, widen)) {
      for (int a = 0; a < 3; ++a) {
        if (!constraint.axes[static_cast<std::size_t>(a)]) continue;
        prescribed.mask(i, a) = 1;
        full_displacement(i, a) = constraint.displacement(a);
      }
    }
  }
  for (const auto& load : scene.loads) {
    const auto nodes = sim::nodes_in_box(mesh.rest, load.where.box, widen);
    for (const int i : nodes) {
      full_loads.row(i) += (load.force / static_cast<Real>(nodes.size())).transpose();
    }
  }

  sim::StaticSettings settings;
  settings.tolerance = tolerance;
  // The corotational tangent leaves out the change of R (corotational_fem.h): Newton then
  // converges linearly, and needs more iterations than the default.
  settings.max_iterations = 60;
  settings.linear = {solver, sim::Preconditioner::jacobi, sim::CgSettings{1e-2, 5000}};
  sim::StaticSolver statics(settings);
  ReferenceResult result;
  result.converged = true;
  Points x = mesh.rest;
  for (int k = 1; k <= increments; ++k) {
    const Real share = Real(k) / Real(increments);
    prescribed.position = mesh.rest + share * full_displacement;
    const Points loads = share * full_loads;
    const auto report = statics.solve(share * scene.gravity, loads, prescribed, *model, x);
    result.converged = result.converged && report.converged;
    result.relative_residual = std::max(result.relative_residual, report.relative_residual);
  }
  result.displacement = x - mesh.rest;
  result.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace incise::bench
