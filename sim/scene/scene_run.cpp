#include "sim/scene/scene_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/models/corotational_fem.h"
#include "sim/models/linear_fem.h"
#include "sim/models/mass_spring_model.h"
#include "sim/models/neo_hookean_fem.h"
#include "sim/models/nodal_pressure_fem.h"
#include "sim/models/stvk_fem.h"
#include "sim/scene/node_selection.h"
#include "sim/scene/scene_error.h"
#include "sim/scene/scene_validation.h"
#include "sim/solve/adaptive_explicit.h"
#include "sim/solve/central_difference.h"
#include "sim/solve/implicit_euler.h"
#include "sim/solve/stable_time_step.h"
#include "sim/solve/static_solver.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim {
namespace {

std::vector<int> select(const TetMesh& mesh, const Selection& where, const std::string& path) {
  std::vector<int> nodes = nodes_in_box(mesh.rest, where.box, selection_tolerance(mesh.rest));
  if (nodes.empty()) throw SceneError(path + ".box", "selects no node");
  return nodes;
}

ElementMaterial to_element(const Material& m) {
  return {m.youngs_modulus, m.poisson_ratio, m.density, m.damping};
}

// Constraints and loads resolved to nodes: the full prescribed displacement and the full load.
struct Boundary {
  Prescribed prescribed;  // positions at the full displacement
  Points displacement;    // #nodes by 3, the full prescribed displacement
  Points loads;           // #nodes by 3 [N]
};

Boundary resolve_boundary(const Scene& scene, const TetMesh& mesh) {
  const Eigen::Index n = mesh.num_nodes();
  Boundary b;
  b.prescribed.mask = AxisMask::Zero(n, 3);
  b.prescribed.position = mesh.rest;
  b.displacement = Points::Zero(n, 3);
  b.loads = Points::Zero(n, 3);
  for (std::size_t c = 0; c < scene.constraints.size(); ++c) {
    const Constraint& constraint = scene.constraints[c];
    for (const int i :
         select(mesh, constraint.where, "constraints[" + std::to_string(c) + "].where")) {
      for (int a = 0; a < 3; ++a) {
        if (!constraint.axes[static_cast<std::size_t>(a)]) continue;
        b.prescribed.mask(i, a) = 1;
        b.displacement(i, a) = constraint.displacement(a);
      }
    }
  }
  for (std::size_t l = 0; l < scene.loads.size(); ++l) {
    const auto nodes = select(mesh, scene.loads[l].where, "loads[" + std::to_string(l) + "].where");
    const Vec3 share = scene.loads[l].force / static_cast<Real>(nodes.size());
    for (const int i : nodes)
      b.loads.row(i) += share.transpose();
  }
  return b;
}

LinearSolver linear_solver_of(LinearSolverChoice choice) {
  switch (choice) {
    case LinearSolverChoice::assembled_cg:
      return LinearSolver::assembled_cg;
    case LinearSolverChoice::ldlt:
      return LinearSolver::assembled_ldlt;
    case LinearSolverChoice::cg:
      break;
  }
  return LinearSolver::matrix_free_cg;
}

// The scene's preconditioner; automatic: the block incomplete Cholesky where there is an
// assembled matrix to factorise, Jacobi otherwise.
Preconditioner preconditioner_of(const SolverSettings& solver) {
  switch (solver.preconditioner) {
    case PreconditionerChoice::jacobi:
      return Preconditioner::jacobi;
    case PreconditionerChoice::block_jacobi:
      return Preconditioner::block_jacobi;
    case PreconditionerChoice::incomplete_cholesky:
      return Preconditioner::incomplete_cholesky;
    case PreconditionerChoice::automatic:
      break;
  }
  return solver.linear_solver == LinearSolverChoice::assembled_cg
             ? Preconditioner::incomplete_cholesky
             : Preconditioner::jacobi;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  const auto middle = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), middle, v.end());
  return *middle;
}

}  // namespace

std::vector<ElementMaterial> element_materials(const Scene& scene, const TetMesh& mesh) {
  const int max_label = mesh.labels.size() > 0 ? std::max(0, mesh.labels.maxCoeff()) : 0;
  std::vector<ElementMaterial> out(static_cast<std::size_t>(max_label) + 1,
                                   to_element(scene.material));
  for (const auto& [label, material] : scene.materials_by_label) {
    if (label <= max_label) out[static_cast<std::size_t>(label)] = to_element(material);
  }
  if (scene.material.model != MaterialModel::mass_spring) {
    // The scene's damping is a fraction, as for the mass-spring model: the FEM models' viscosity
    // is beta = damping * l_min / c, the time a wave takes across the mesh's smallest element, so
    // that damping 1 is about critical for the highest mode the mesh carries, and explicit steps
    // near the stable limit stay stable.
    const Real l_min = element_lengths(mesh.rest, mesh.tets).min_altitude;
    for (auto& m : out) {
      m.damping *= l_min / p_wave_speed(m.youngs_modulus, m.poisson_ratio, m.density);
    }
  }
  return out;
}

std::unique_ptr<Model> make_model(const Scene& scene, const TetMesh& mesh) {
  auto materials = element_materials(scene, mesh);
  // The static Newton solve keeps the exact Hessian, for quadratic convergence near the
  // equilibrium (its line search copes with an indefinite K); a time step takes one linearisation
  // and needs M + h D + h^2 K positive definite, which the exact Hessian is not once tets are
  // compressed hard or inverted (a yank released at 2 ms blew up to 1e14 body sizes with it).
  const Tangent tangent = scene.solver.integrator == Integrator::static_equilibrium
                              ? Tangent::exact
                              : Tangent::projected;
  try {
    switch (scene.material.model) {
      case MaterialModel::mass_spring:
        return std::make_unique<MassSpringModel>(mesh, std::move(materials),
                                                 scene.material.volume_stiffness);
      case MaterialModel::linear:
        return std::make_unique<LinearFem>(mesh, std::move(materials));
      case MaterialModel::corotational:
        return std::make_unique<CorotationalFem>(mesh, std::move(materials),
                                                 RotationExtraction::qr);
      case MaterialModel::corotational_polar:
        return std::make_unique<CorotationalFem>(mesh, std::move(materials),
                                                 RotationExtraction::polar);
      case MaterialModel::corotational_nodal_pressure:
        return std::make_unique<NodalPressureFem>(mesh, std::move(materials));
      case MaterialModel::stvk:
        return std::make_unique<StVenantKirchhoffFem>(mesh, std::move(materials), tangent);
      case MaterialModel::neohookean:
        return std::make_unique<NeoHookeanFem>(mesh, std::move(materials),
                                               NeoHookeanKernel{}.extension_below, tangent);
    }
  } catch (const std::invalid_argument& error) {
    throw SceneError("mesh", error.what());
  }
  throw SceneError("material.model", "not supported");
}

CheckedRun run_scene_checked(const Scene& scene, TetMesh mesh) {
  validate_scene(scene);
  if (mesh.num_tets() == 0) throw SceneError("mesh", "has no tetrahedra");
  auto model = make_model(scene, mesh);
  const Boundary boundary = resolve_boundary(scene, mesh);
  const Points no_loads;
  Points x = mesh.rest;
  Points v = Points::Zero(mesh.num_nodes(), 3);
  Prescribed prescribed = boundary.prescribed;
  Points loads = boundary.loads;
  const std::int64_t steps = scene.solver.steps;
  const Real dt = scene.solver.dt;
  const std::int64_t ramp = std::max<std::int64_t>(1, steps / 2);

  CheckedRun checked;
  RunResult& result = checked.result;
  const auto diagonal = [](const Points& p) {
    return (p.colwise().maxCoeff() - p.colwise().minCoeff()).norm();
  };
  const Real rest_diagonal = diagonal(mesh.rest);
  std::vector<double> step_ms;
  step_ms.reserve(static_cast<std::size_t>(std::min(steps, kMaxTimedSteps)));
  const std::int64_t stride = (steps + kMaxTimedSteps - 1) / kMaxTimedSteps;

  // Integrators, built once (they keep their work arrays between steps).
  CentralDifference central;
  std::optional<AdaptiveExplicit> adaptive;
  std::optional<ImplicitEuler> implicit;
  std::optional<StaticSolver> statics;
  VecX inv_mass;
  Points forces;
  switch (scene.solver.integrator) {
    case Integrator::symplectic_euler:
      inv_mass = (model->masses().array() > 0).select(model->masses().cwiseInverse(), 0.0);
      forces = Points::Zero(mesh.num_nodes(), 3);
      break;
    case Integrator::adaptive_explicit: {
      AdaptiveExplicitSettings s;
      s.dt_initial = dt;
      s.dt_max = dt;
      s.dt_min = std::min(dt, 1e-3 * dt);
      adaptive.emplace(s);
      break;
    }
    case Integrator::implicit_euler: {
      ImplicitEulerSettings s;
      s.linear.solver = linear_solver_of(scene.solver.linear_solver);
      s.linear.preconditioner = preconditioner_of(scene.solver);
      s.linear.cg.tolerance = scene.solver.tolerance;
      s.linear.cg.max_iterations = 10 * mesh.num_nodes() + 100;
      implicit.emplace(s);
      break;
    }
    case Integrator::static_equilibrium: {
      StaticSettings s;
      s.tolerance = scene.solver.tolerance;
      s.linear.solver = linear_solver_of(scene.solver.linear_solver);
      s.linear.preconditioner = preconditioner_of(scene.solver);
      statics.emplace(s);
      break;
    }
    case Integrator::central_difference:
      break;
  }

  Real worst_residual = 0;
  std::int64_t iterations = 0;
  bool converged = true;
  for (std::int64_t n = 0; n < steps && result.finite; ++n) {
    // How much of the boundary displacement (and, for a static solve, of the loads) applies.
    const bool is_static = scene.solver.integrator == Integrator::static_equilibrium;
    const Real share =
        is_static ? Real(n + 1) / Real(steps) : std::min<Real>(1, Real(n + 1) / Real(ramp));
    prescribed.position = mesh.rest + share * boundary.displacement;
    if (is_static) loads = share * boundary.loads;
    const auto start = std::chrono::steady_clock::now();
    switch (scene.solver.integrator) {
      case Integrator::symplectic_euler:
        forces = loads;
        model->add_forces(x, v, forces);
        symplectic_euler_step(dt, scene.gravity, inv_mass, prescribed, forces, x, v);
        result.finite = x.allFinite() && v.allFinite();
        break;
      case Integrator::central_difference: {
        const auto report = central.step(dt, scene.gravity, loads, prescribed, *model, x, v);
        result.finite = report.finite;
        break;
      }
      case Integrator::adaptive_explicit: {
        const auto report = adaptive->advance(dt, scene.gravity, loads, prescribed, *model, x, v);
        result.finite = report.finite;
        iterations += report.steps + report.rejected_steps;
        converged = converged && report.completed;
        break;
      }
      case Integrator::implicit_euler: {
        const auto report = implicit->step(dt, scene.gravity, loads, prescribed, *model, x, v);
        result.finite = report.finite;
        iterations += report.iterations;
        converged = converged && report.converged;
        worst_residual = std::max(worst_residual, report.relative_residual);
        break;
      }
      case Integrator::static_equilibrium: {
        const Vec3 gravity = share * scene.gravity;
        const auto report = statics->solve(gravity, loads, prescribed, *model, x);
        result.finite = report.finite;
        iterations += report.iterations;
        converged = converged && report.converged;
        worst_residual = std::max(worst_residual, report.relative_residual);
        break;
      }
    }
    if (n % stride == 0) {
      step_ms.push_back(
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
              .count());
    }
    ++result.steps;
    if (!continue_checked_run(n, result.finite ? diagonal(x) / rest_diagonal : 0, checked)) break;
  }
  if (!result.finite) --result.steps;  // the steps before the one that failed

  result.ms_per_step = median(std::move(step_ms));
  result.rest = mesh.rest;
  result.displacement = x - mesh.rest;
  result.num_tets = mesh.num_tets();
  result.max_speed = v.rowwise().norm().maxCoeff();
  result.converged = converged;
  result.iterations = iterations;
  result.relative_residual = worst_residual;
  const auto health = model->health();
  result.inverted_elements = health.inverted_elements;
  result.final_positions = x;
  result.status = checked.status;
  return checked;
}

RunResult run_scene_on(const Scene& scene, TetMesh mesh) {
  return run_scene_checked(scene, std::move(mesh)).result;
}

bool continue_checked_run(std::int64_t n, Real extent, CheckedRun& checked) {
  if (!checked.result.finite) {
    checked.stop = RunStop::not_finite;
    checked.status = "not finite at step " + std::to_string(n + 1) +
                     ": a position, velocity or solve became NaN or infinite";
    return false;
  }
  checked.peak_extent = std::max(checked.peak_extent, extent);
  if (extent <= kDivergedExtent) return true;
  checked.result.finite = false;
  checked.stop = RunStop::diverged;
  std::ostringstream status;
  status << std::setprecision(3) << "diverged at step " << n + 1 << ": the body is " << extent
         << " times its rest size (limit " << kDivergedExtent << "); try a smaller solver.dt";
  checked.status = status.str();
  return false;
}

}  // namespace incise::sim
