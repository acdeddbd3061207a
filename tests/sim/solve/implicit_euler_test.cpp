#include "sim/solve/implicit_euler.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "sim/mesh/box_mesher.h"
#include "sim/solve/stable_time_step.h"
#include "test_models.h"

namespace incise::sim {
namespace {

const Vec3 kNoGravity = Vec3::Zero();
const Points kNoForces;
const Prescribed kNothingPrescribed{};

ImplicitEulerSettings tight(LinearSolver solver) {
  ImplicitEulerSettings settings;
  settings.linear.solver = solver;
  settings.linear.cg = CgSettings{1e-13, 2000};
  return settings;
}

Prescribed hold_bottom(const TetMesh& mesh) {
  Prescribed held{AxisMask::Zero(mesh.num_nodes(), 3), mesh.rest};
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 2) == 0) held.mask.row(i).setOnes();
  }
  return held;
}

TEST(ImplicitEuler, UndampedOscillatorLosesEnergyByTheClosedFormFactor) {
  // Backward Euler on x'' = -omega^2 x scales (omega x, v) by a rotation and 1 / sqrt(1 +
  // (omega h)^2): the energy falls by exactly 1 / (1 + (omega h)^2) per step.
  const Real m = 0.5, k = 200;
  const Real omega = std::sqrt(k / m);
  const Real explicit_limit = 2 / omega;
  for (const Real factor : {10.0, 100.0}) {
    for (const LinearSolver solver :
         {LinearSolver::matrix_free_cg, LinearSolver::assembled_cg, LinearSolver::assembled_ldlt}) {
      const Real h = factor * explicit_limit;
      testing::LinearModel model = testing::make_oscillator(m, k);
      Points x(1, 3), v(1, 3);
      x << 0.01, -0.02, 0.005;
      v << 0.3, 0, -0.1;
      ImplicitEuler integrator(tight(solver));
      Real energy = testing::total_energy(model, x, v);
      for (int n = 0; n < 5; ++n) {
        const ImplicitStepReport report =
            integrator.step(h, kNoGravity, kNoForces, kNothingPrescribed, model, x, v);
        ASSERT_TRUE(report.finite && report.converged);
        const Real next = testing::total_energy(model, x, v);
        EXPECT_LT(next, energy);
        EXPECT_NEAR(next / energy, 1 / (1 + (omega * h) * (omega * h)), 1e-9)
            << "factor " << factor << " solver " << static_cast<int>(solver);
        energy = next;
      }
    }
  }
}

// The reference step: the dense solve of (M + h D + h^2 K) dv = h (f0 - h K v0) on the free
// coordinates, with the held ones' known dv on the right-hand side.
void reference_step(const testing::LinearModel& model, Real alpha, Real beta, Real h,
                    const Vec3& gravity, const Prescribed& held, Points& x, Points& v) {
  const Eigen::Index dofs = x.size();
  const Eigen::MatrixXd k = Eigen::MatrixXd(model.stiffness());
  VecX mass(dofs);
  for (Eigen::Index d = 0; d < dofs; ++d)
    mass(d) = model.masses()(d / 3);
  const Eigen::MatrixXd d_matrix = alpha * Eigen::MatrixXd(mass.asDiagonal()) + beta * k;
  const Eigen::MatrixXd a = Eigen::MatrixXd(mass.asDiagonal()) + h * d_matrix + h * h * k;
  Eigen::Map<VecX> xv(x.data(), dofs), vv(v.data(), dofs);
  const Eigen::Map<const VecX> rest(model.rest().data(), dofs);
  VecX g(dofs);
  for (Eigen::Index d = 0; d < dofs; ++d)
    g(d) = mass(d) * gravity(d % 3);
  const VecX f0 = -k * (xv - rest) - d_matrix * vv + g;
  VecX rhs = h * (f0 - h * k * vv);
  VecX dv = VecX::Zero(dofs);
  std::vector<int> free;
  for (Eigen::Index d = 0; d < dofs; ++d) {
    if (held.mask.data()[d] != 0) {
      dv(d) = (held.position.data()[d] - xv(d)) / h - vv(d);
    } else {
      free.push_back(static_cast<int>(d));
    }
  }
  rhs -= a * dv;
  Eigen::MatrixXd a_ff(free.size(), free.size());
  VecX rhs_f(free.size());
  for (std::size_t i = 0; i < free.size(); ++i) {
    rhs_f(i) = rhs(free[i]);
    for (std::size_t j = 0; j < free.size(); ++j)
      a_ff(i, j) = a(free[i], free[j]);
  }
  const VecX dv_f = a_ff.ldlt().solve(rhs_f);
  for (std::size_t i = 0; i < free.size(); ++i)
    dv(free[i]) = dv_f(i);
  vv += dv;
  xv += h * vv;
  for (Eigen::Index d = 0; d < dofs; ++d) {
    if (held.mask.data()[d] != 0) xv(d) = held.position.data()[d];
  }
}

TEST(ImplicitEuler, TheThreeLinearSolversGiveTheReferenceStep) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  const Real alpha = 3, beta = 0.01;
  testing::LinearModel model = testing::make_linear_tet_model(mesh, 5e3, 0.45, 1000, alpha, beta);
  Prescribed held = hold_bottom(mesh);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (held.mask(i, 0) != 0) held.position(i, 0) += 1e-3;  // the support moves sideways
  }
  Points x0 = mesh.rest, v0 = Points::Zero(mesh.num_nodes(), 3);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    x0.row(i) += 5e-4 * Vec3(std::sin(2 * i), std::cos(i), std::sin(i + 1)).transpose();
    v0.row(i) = 0.01 * Vec3(std::cos(5 * i), 0.2, -std::sin(i)).transpose();
  }
  const Real h = 20 * stable_time_step(mesh, 5e3, 0.45, 1000);
  const Vec3 gravity(0, 0, -9.81);
  Points x_ref = x0, v_ref = v0;
  reference_step(model, alpha, beta, h, gravity, held, x_ref, v_ref);
  const Real scale_x = (x_ref - x0).norm(), scale_v = v_ref.norm();
  for (const LinearSolver solver :
       {LinearSolver::matrix_free_cg, LinearSolver::assembled_cg, LinearSolver::assembled_ldlt}) {
    Points x = x0, v = v0;
    ImplicitEuler integrator(tight(solver));
    const ImplicitStepReport report = integrator.step(h, gravity, kNoForces, held, model, x, v);
    EXPECT_TRUE(report.converged && report.finite);
    EXPECT_LE(report.relative_residual, 1e-13);
    EXPECT_LT((x - x_ref).norm(), 1e-9 * scale_x) << static_cast<int>(solver);
    EXPECT_LT((v - v_ref).norm(), 1e-9 * scale_v) << static_cast<int>(solver);
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      if (held.mask(i, 0) != 0) {
        EXPECT_EQ(row3(x, i), row3(held.position, i));
      }
    }
    if (solver == LinearSolver::assembled_ldlt) {
      EXPECT_LE(report.iterations, 30);
    }
  }
}

TEST(ImplicitEuler, StableAt10And100TimesTheExplicitLimitAndSettlesToTheStaticAnswer) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  const Real E = 5e3, nu = 0.3, rho = 1000;
  testing::LinearModel model = testing::make_linear_tet_model(mesh, E, nu, rho);
  const Prescribed held = hold_bottom(mesh);
  const Vec3 gravity(0, 0, -9.81);
  // The static answer under gravity by a direct solve of K_ff u_f = (M g)_f.
  const Eigen::Index dofs = 3 * mesh.num_nodes();
  std::vector<int> free;
  for (Eigen::Index d = 0; d < dofs; ++d) {
    if (held.mask.data()[d] == 0) free.push_back(static_cast<int>(d));
  }
  const Eigen::MatrixXd k = Eigen::MatrixXd(model.stiffness());
  Eigen::MatrixXd k_ff(free.size(), free.size());
  VecX load(free.size());
  for (std::size_t i = 0; i < free.size(); ++i) {
    load(i) = model.masses()(free[i] / 3) * gravity(free[i] % 3);
    for (std::size_t j = 0; j < free.size(); ++j)
      k_ff(i, j) = k(free[i], free[j]);
  }
  const VecX u_f = k_ff.ldlt().solve(load);
  Points x_static = mesh.rest;
  for (std::size_t i = 0; i < free.size(); ++i)
    x_static.data()[free[i]] += u_f(i);
  const Real sag = u_f.cwiseAbs().maxCoeff();

  for (const Real factor : {10.0, 100.0}) {
    const Real h = factor * stable_time_step(mesh, E, nu, rho) / kExplicitSafety;
    Points x = mesh.rest, v = Points::Zero(mesh.num_nodes(), 3);
    ImplicitEuler integrator;  // default: matrix-free CG, tolerance 1e-6
    Real peak = 0;
    int total_iterations = 0;
    const int steps = factor == 10 ? 3000 : 300;
    for (int n = 0; n < steps; ++n) {
      const ImplicitStepReport report = integrator.step(h, gravity, kNoForces, held, model, x, v);
      ASSERT_TRUE(report.finite && report.converged);
      total_iterations += report.iterations;
      peak = std::max(peak, (x - mesh.rest).cwiseAbs().maxCoeff());
    }
    // No overshoot beyond the dynamic peak of a suddenly applied load (twice the static sag).
    EXPECT_LT(peak, 2 * sag * 1.001) << factor;
    EXPECT_LT((x - x_static).cwiseAbs().maxCoeff(), 1e-4 * sag) << factor;
    std::printf("implicit Euler at %.0fx the explicit limit: %.1f CG iterations per step\n", factor,
                static_cast<double>(total_iterations) / steps);
  }
}

TEST(ImplicitEuler, WarmStartReusesTheLastSolution) {
  // Repeating a step from the same state: the warm start is already the answer (to the
  // tolerance), so CG takes no iteration; without it CG starts from zero.
  const TetMesh mesh = make_box_mesh(Vec3(0.04, 0.02, 0.02), Vec3i(4, 2, 2));
  testing::LinearModel model = testing::make_linear_tet_model(mesh, 5e3, 0.45, 1000);
  const Prescribed held = hold_bottom(mesh);
  for (const bool warm_start : {false, true}) {
    ImplicitEulerSettings settings;
    settings.warm_start = warm_start;
    ImplicitEuler integrator(settings);
    Points x = mesh.rest, v = Points::Zero(mesh.num_nodes(), 3);
    const ImplicitStepReport first =
        integrator.step(1e-2, Vec3(0, 0, -9.81), kNoForces, held, model, x, v);
    x = mesh.rest;
    v.setZero();
    const ImplicitStepReport again =
        integrator.step(1e-2, Vec3(0, 0, -9.81), kNoForces, held, model, x, v);
    EXPECT_GT(first.iterations, 10);
    EXPECT_TRUE(again.converged);
    EXPECT_EQ(again.iterations, warm_start ? 0 : first.iterations);
    integrator.reset();  // forgets it
    x = mesh.rest;
    v.setZero();
    EXPECT_EQ(integrator.step(1e-2, Vec3(0, 0, -9.81), kNoForces, held, model, x, v).iterations,
              first.iterations);
  }
}

TEST(ImplicitEuler, NonFiniteForcesLeaveTheStateAndReport) {
  testing::LinearModel model = testing::make_oscillator(1, 1);
  Points x(1, 3), v = Points::Zero(1, 3);
  x << 0.1, std::numeric_limits<Real>::infinity(), 0;
  const Points x0 = x;
  ImplicitEuler integrator;
  const ImplicitStepReport report =
      integrator.step(0.1, kNoGravity, kNoForces, kNothingPrescribed, model, x, v);
  EXPECT_FALSE(report.finite);
  EXPECT_FALSE(report.converged);
  EXPECT_EQ(x, x0);
  EXPECT_EQ(v, Points::Zero(1, 3));
}

TEST(ImplicitEuler, IterationCapIsReportedAsNotConverged) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  testing::LinearModel model = testing::make_linear_tet_model(mesh, 5e3, 0.3, 1000);
  ImplicitEulerSettings settings;
  settings.linear.cg = CgSettings{1e-12, 2};
  ImplicitEuler integrator(settings);
  Points x = mesh.rest, v = Points::Zero(mesh.num_nodes(), 3);
  const ImplicitStepReport report =
      integrator.step(0.05, Vec3(0, 0, -9.81), kNoForces, hold_bottom(mesh), model, x, v);
  EXPECT_EQ(report.iterations, 2);
  EXPECT_FALSE(report.converged);
  EXPECT_GT(report.relative_residual, 1e-12);
  EXPECT_TRUE(report.finite);
  EXPECT_THROW(ImplicitEuler(ImplicitEulerSettings{
                   {LinearSolver::matrix_free_cg, Preconditioner::jacobi, CgSettings{0, 10}}}),
               std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim
