// Scenes with every model and integrator (sim/scene/scene_run.h), against closed forms,
// CalculiX and each other.
#include "sim/scene/scene_run.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <string>

#include "calculix.h"
#include "sim/mesh/box_mesher.h"
#include "sim/scene/scene_error.h"
#include "sim/solve/stable_time_step.h"
#include "tests/sim/closed_forms.h"
#include "tests/support/temp_dir.h"

namespace incise::sim {
namespace {

constexpr Real kE = 3000;  // soft tissue [Pa]
constexpr Real kNu = 0.3;

Scene block_scene(MaterialModel model, Integrator integrator) {
  Scene scene;
  scene.mesh.box = {Vec3(0.02, 0.02, 0.02), Vec3i(3, 3, 3)};
  scene.material = {model, kE, kNu, 1000, 0.0};
  scene.solver = {integrator, 1.0, 1, 1e-10};
  return scene;
}

// The block compressed along z between z = 0 and the top, free to expand sideways: symmetry planes
// x = 0, y = 0 hold one coordinate each, the top moves down by `strain` of the height.
void compress(Scene& scene, Real strain) {
  const Real L = 0.02, eps = 1e-9;
  scene.constraints = {
      {{Box3(Vec3(-eps, -1, -1), Vec3(eps, 1, 1))}, {true, false, false}, Vec3::Zero()},
      {{Box3(Vec3(-1, -eps, -1), Vec3(1, eps, 1))}, {false, true, false}, Vec3::Zero()},
      {{Box3(Vec3(-1, -1, -eps), Vec3(1, 1, eps))}, {false, false, true}, Vec3::Zero()},
      {{Box3(Vec3(-1, -1, L - eps), Vec3(1, 1, L + eps))},
       {false, false, true},
       Vec3(0, 0, -strain * L)},
  };
}

TetMesh box_of(const Scene& scene) {
  return make_box_mesh(scene.mesh.box.size, scene.mesh.box.cells);
}

// Largest |u - expected| over the nodes, relative to the largest |expected|.
template <class Expected>
Real relative_error(const RunResult& r, Expected expected) {
  Real worst = 0, scale = 0;
  for (int i = 0; i < r.rest.rows(); ++i) {
    const Vec3 e = expected(row3(r.rest, i));
    worst = std::max(worst, (row3(r.displacement, i) - e).norm());
    scale = std::max(scale, e.norm());
  }
  return worst / scale;
}

// Linear elasticity, uniaxial compression with free lateral faces: u = (nu e x, nu e y, -e z).
// A homogeneous strain is exact on linear tets, so what is left is the solver's tolerance.
TEST(SceneRun, LinearBlockCompressionMatchesTheClosedForm) {
  for (const Real strain : {0.01, 0.05, 0.10, 0.20}) {
    Scene scene = block_scene(MaterialModel::linear, Integrator::static_equilibrium);
    compress(scene, strain);
    const auto result = run_scene_on(scene, box_of(scene));
    ASSERT_TRUE(result.converged) << strain;
    EXPECT_LT(relative_error(result,
                             [&](const Vec3& p) {
                               return Vec3(kNu * strain * p.x(), kNu * strain * p.y(),
                                           -strain * p.z());
                             }),
              1e-6)
        << strain;
  }
}

TEST(SceneRun, NeoHookeanBlockCompressionMatchesJoshiEq15) {
  for (const Real strain : {0.01, 0.05, 0.10, 0.20}) {
    Scene scene = block_scene(MaterialModel::neohookean, Integrator::static_equilibrium);
    scene.solver.steps = 4;  // load increments
    compress(scene, strain);
    const auto result = run_scene_on(scene, box_of(scene));
    ASSERT_TRUE(result.converged) << strain;
    const auto lame = test::lame_parameters(kE, kNu);
    const Real l2 = test::neo_hookean_lateral_stretch(1 - strain, lame.mu, lame.lambda);
    EXPECT_LT(relative_error(result,
                             [&](const Vec3& p) {
                               return Vec3((l2 - 1) * p.x(), (l2 - 1) * p.y(), -strain * p.z());
                             }),
              1e-6)
        << strain << " (lateral stretch " << l2 << ")";
  }
}

// A cantilever under a tip load: our linear static answer equals CalculiX's (C3D4, the same mesh)
// to the solvers' tolerance.
TEST(SceneRun, LinearCantileverEqualsCalculix) {
  Scene scene = block_scene(MaterialModel::linear, Integrator::static_equilibrium);
  scene.mesh.box = {Vec3(0.1, 0.02, 0.02), Vec3i(10, 2, 2)};
  const Real eps = 1e-9;
  scene.constraints = {
      {{Box3(Vec3(-eps, -1, -1), Vec3(eps, 1, 1))}, {true, true, true}, Vec3::Zero()}};
  scene.loads = {{{Box3(Vec3(0.1 - eps, -1, -1), Vec3(0.1 + eps, 1, 1))}, Vec3(0, 0, -0.01)}};
  const TetMesh mesh = box_of(scene);
  const auto ours = run_scene_on(scene, mesh);
  ASSERT_TRUE(ours.converged);

  reference::CalculixProblem problem;
  problem.mesh = &mesh;
  problem.youngs_modulus = kE;
  problem.poisson_ratio = kNu;
  problem.node_loads = Points::Zero(mesh.num_nodes(), 3);
  int tip = 0;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 0) < eps) problem.fixed_nodes.push_back(i);
    if (mesh.rest(i, 0) > 0.1 - eps) ++tip;
  }
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 0) > 0.1 - eps) problem.node_loads(i, 2) = -0.01 / tip;
  }
  const incise::test::TempDir dir{"incise-ccx"};
  const Points ccx = reference::solve_linear_static(problem, dir.path());
  const Real scale = ccx.rowwise().norm().maxCoeff();
  ASSERT_GT(scale, 0);
  EXPECT_LT((ours.displacement - ccx).rowwise().norm().maxCoeff() / scale, 1e-6);
}

// Our Neo-Hookean (Joshi et al., eq. 4) against CalculiX's NEO HOOKE (an isochoric-volumetric
// split, fitted to the same mu and bulk modulus) on the compressed block: at small strain both are
// linear elasticity and must agree; at larger strain the two energies part, by how much is printed
// (the README quotes it).
TEST(SceneRun, NeoHookeanAgreesWithCalculixAtSmallStrain) {
  for (const Real strain : {0.001, 0.05, 0.10, 0.20}) {
    Scene scene = block_scene(MaterialModel::neohookean, Integrator::static_equilibrium);
    scene.solver.steps = 4;
    compress(scene, strain);
    const TetMesh mesh = box_of(scene);
    const auto ours = run_scene_on(scene, mesh);
    ASSERT_TRUE(ours.converged) << strain;

    reference::CalculixProblem problem;
    problem.mesh = &mesh;
    problem.youngs_modulus = kE;
    problem.poisson_ratio = kNu;
    problem.material = reference::CalculixMaterial::neo_hooke;
    problem.increments = 4;
    const Real L = 0.02, eps = 1e-9;
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      if (mesh.rest(i, 0) < eps) problem.prescribed.push_back({i, 0, 0.0});
      if (mesh.rest(i, 1) < eps) problem.prescribed.push_back({i, 1, 0.0});
      if (mesh.rest(i, 2) < eps) problem.prescribed.push_back({i, 2, 0.0});
      if (mesh.rest(i, 2) > L - eps) problem.prescribed.push_back({i, 2, -strain * L});
    }
    const incise::test::TempDir dir{"incise-ccx-nh"};
    const Points ccx = reference::solve_linear_static(problem, dir.path());
    // Compare the lateral bulge, the part the two energies decide (the axial one is prescribed).
    const Real bulge_ours = ours.displacement.col(0).maxCoeff();
    const Real bulge_ccx = ccx.col(0).maxCoeff();
    const Real difference = std::abs(bulge_ours - bulge_ccx) / bulge_ccx;
    std::cout << "[ neo-hooke ] compression " << strain * 100 << "%: lateral bulge ours "
              << bulge_ours << " m, CalculiX " << bulge_ccx << " m, apart " << difference * 100
              << "%\n";
    if (strain <= 0.001) {
      EXPECT_LT(difference, 1e-3);
    }
  }
}

// A damped body under gravity, stepped by implicit Euler at ten times the explicit limit, comes to
// rest on the static answer.
TEST(SceneRun, ImplicitEulerAtTenTimesTheExplicitLimitSettlesOnTheStaticAnswer) {
  Scene scene = block_scene(MaterialModel::corotational, Integrator::implicit_euler);
  scene.material.damping = 0.05;
  scene.gravity = Vec3(0, 0, -9.81);
  const Real eps = 1e-9;
  scene.constraints = {
      {{Box3(Vec3(-1, -1, -eps), Vec3(1, 1, eps))}, {true, true, true}, Vec3::Zero()}};
  const TetMesh mesh = box_of(scene);
  const Real limit = stable_time_step(mesh, kE, kNu, 1000, 1.0);
  scene.solver.dt = 10 * limit;
  scene.solver.steps = static_cast<std::int64_t>(std::ceil(3.0 / scene.solver.dt));
  scene.solver.tolerance = 1e-8;
  const auto dynamic = run_scene_on(scene, mesh);
  ASSERT_TRUE(dynamic.finite);
  EXPECT_LT(dynamic.max_speed, 1e-4);

  scene.solver = {Integrator::static_equilibrium, 1.0, 1, 1e-10};
  const auto statics = run_scene_on(scene, mesh);
  ASSERT_TRUE(statics.converged);
  const Real sag = statics.displacement.rowwise().norm().maxCoeff();
  ASSERT_GT(sag, 0);
  EXPECT_LT((dynamic.displacement - statics.displacement).rowwise().norm().maxCoeff() / sag, 1e-2);
}

TEST(SceneRun, EveryModelAndIntegratorRunsTheSagFinite) {
  for (const auto model :
       {MaterialModel::mass_spring, MaterialModel::linear, MaterialModel::corotational,
        MaterialModel::corotational_polar, MaterialModel::stvk, MaterialModel::neohookean}) {
    for (const auto integrator : {Integrator::symplectic_euler, Integrator::central_difference,
                                  Integrator::adaptive_explicit, Integrator::implicit_euler}) {
      Scene scene = block_scene(model, integrator);
      scene.material.damping = 0.05;
      scene.gravity = Vec3(0, 0, -9.81);
      const Real eps = 1e-9;
      scene.constraints = {
          {{Box3(Vec3(-1, -1, -eps), Vec3(1, 1, eps))}, {true, true, true}, Vec3::Zero()}};
      const TetMesh mesh = box_of(scene);
      scene.solver.dt = 0.5 * stable_time_step(mesh, kE, kNu, 1000);
      scene.solver.steps = 200;
      const auto result = run_scene_on(scene, mesh);
      EXPECT_TRUE(result.finite) << static_cast<int>(model) << " " << static_cast<int>(integrator);
      // Gravity pulls the top down and nothing up.
      EXPECT_LT(result.displacement.col(2).minCoeff(), 0);
    }
  }
}

// The scene chooses the linear solver; all three reach the same equilibrium.
TEST(SceneRun, TheThreeLinearSolversAgree) {
  Scene scene = block_scene(MaterialModel::corotational_polar, Integrator::static_equilibrium);
  scene.gravity = Vec3(0, 0, -9.81);
  const Real eps = 1e-9;
  scene.constraints = {
      {{Box3(Vec3(-eps, -1, -1), Vec3(eps, 1, 1))}, {true, true, true}, Vec3::Zero()}};
  const TetMesh mesh = box_of(scene);
  scene.solver.linear_solver = LinearSolverChoice::cg;
  const auto cg = run_scene_on(scene, mesh);
  const Real sag = cg.displacement.rowwise().norm().maxCoeff();
  ASSERT_GT(sag, 0);
  for (const auto choice : {LinearSolverChoice::assembled_cg, LinearSolverChoice::ldlt}) {
    scene.solver.linear_solver = choice;
    const auto other = run_scene_on(scene, mesh);
    ASSERT_TRUE(other.converged) << static_cast<int>(choice);
    EXPECT_LT((other.displacement - cg.displacement).rowwise().norm().maxCoeff() / sag, 1e-6);
  }
}

// The mass-spring model's volume term (material.volume_stiffness) resists the volume change of a
// compressed block that springs alone let through: the block keeps more of its volume with it.
TEST(SceneRun, MassSpringVolumeTermKeepsTheVolume) {
  const auto volume_after = [](Real volume_stiffness) {
    Scene scene = block_scene(MaterialModel::mass_spring, Integrator::static_equilibrium);
    scene.material.volume_stiffness = volume_stiffness;
    scene.solver.tolerance = 1e-9;
    compress(scene, 0.1);
    const TetMesh mesh = box_of(scene);
    const auto result = run_scene_on(scene, mesh);
    EXPECT_TRUE(result.converged) << volume_stiffness;
    Real volume = 0;
    for (int t = 0; t < mesh.num_tets(); ++t) {
      Mat3 edges;
      for (int k = 0; k < 3; ++k) {
        edges.col(k) = row3(result.final_positions, mesh.tets(t, k + 1)) -
                       row3(result.final_positions, mesh.tets(t, 0));
      }
      volume += edges.determinant() / 6;
    }
    return volume / (0.02 * 0.02 * 0.02);
  };
  const Real springs_only = volume_after(0);
  const Real with_volume_term = volume_after(5);
  EXPECT_LT(springs_only, 0.97);  // a 10% compression loses volume with springs alone
  EXPECT_GT(with_volume_term, springs_only + 0.02);
  EXPECT_LT(with_volume_term, 1.0);
}

// The scene chooses the preconditioner; every choice reaches the same implicit trajectory (to the
// CG tolerance), and the incomplete Cholesky takes fewer CG iterations than Jacobi.
TEST(SceneRun, ThePreconditionersAgree) {
  Scene scene = block_scene(MaterialModel::corotational, Integrator::implicit_euler);
  scene.gravity = Vec3(0, 0, -9.81);
  scene.solver.dt = 0.01;
  scene.solver.steps = 10;
  scene.solver.tolerance = 1e-10;
  const Real eps = 1e-9;
  scene.constraints = {
      {{Box3(Vec3(-eps, -1, -1), Vec3(eps, 1, 1))}, {true, true, true}, Vec3::Zero()}};
  const TetMesh mesh = box_of(scene);
  scene.solver.linear_solver = LinearSolverChoice::cg;
  scene.solver.preconditioner = PreconditionerChoice::jacobi;
  const auto jacobi = run_scene_on(scene, mesh);
  ASSERT_TRUE(jacobi.converged);
  const Real sag = jacobi.displacement.rowwise().norm().maxCoeff();
  ASSERT_GT(sag, 0);
  std::int64_t incomplete_iterations = 0;
  for (const auto& [solver, preconditioner] :
       {std::pair{LinearSolverChoice::cg, PreconditionerChoice::block_jacobi},
        std::pair{LinearSolverChoice::assembled_cg, PreconditionerChoice::jacobi},
        std::pair{LinearSolverChoice::assembled_cg, PreconditionerChoice::automatic}}) {
    scene.solver.linear_solver = solver;
    scene.solver.preconditioner = preconditioner;
    const auto other = run_scene_on(scene, mesh);
    ASSERT_TRUE(other.converged) << static_cast<int>(preconditioner);
    EXPECT_LT((other.displacement - jacobi.displacement).rowwise().norm().maxCoeff() / sag, 1e-7);
    if (preconditioner == PreconditionerChoice::automatic) incomplete_iterations = other.iterations;
  }
  EXPECT_LT(incomplete_iterations, jacobi.iterations);
}

TEST(SceneRun, SelectionsThatPickNoNodeAreNamed) {
  Scene scene = block_scene(MaterialModel::linear, Integrator::static_equilibrium);
  scene.loads = {{{Box3(Vec3(1, 1, 1), Vec3(2, 2, 2))}, Vec3(0, 0, 1)}};
  try {
    run_scene_on(scene, box_of(scene));
    FAIL() << "expected a SceneError";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(), "loads[0].where.box: selects no node");
  }
}

}  // namespace
}  // namespace incise::sim
