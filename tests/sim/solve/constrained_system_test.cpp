#include "sim/solve/constrained_system.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "sim/mesh/box_mesher.h"
#include "sim/solve/free_coordinates.h"
#include "test_models.h"

namespace incise::sim {
namespace {

TEST(ConstrainedSystem, AssembledMatrixIsScaledMassPlusStiffnessWithIdentityOnHeldRows) {
  const TetMesh mesh = make_box_mesh(Vec3(0.02, 0.02, 0.02), Vec3i(2, 2, 2));
  testing::LinearModel model = testing::make_linear_tet_model(mesh, 1e4, 0.3, 1000);
  Prescribed held{AxisMask::Zero(mesh.num_nodes(), 3), mesh.rest};
  held.mask(0, 0) = held.mask(4, 2) = 1;
  Points free;
  free_coordinates(held, model.masses(), free);
  const Real a = 2, c = 1e-3;
  ConstrainedSystem system;
  LinearSolveSettings settings;
  settings.solver = LinearSolver::assembled_cg;
  ASSERT_TRUE(system.prepare(model, a, 0, c, free, settings));
  EXPECT_TRUE(system.pattern_rebuilt());
  const Eigen::MatrixXd assembled(system.matrix());
  const Eigen::MatrixXd k(model.stiffness());
  for (Eigen::Index i = 0; i < assembled.rows(); ++i) {
    for (Eigen::Index j = 0; j < assembled.cols(); ++j) {
      Real expected = c * k(i, j) + (i == j ? a * model.masses()(i / 3) : 0);
      if (free.data()[i] == 0 || free.data()[j] == 0) expected = i == j ? 1 : 0;
      ASSERT_NEAR(assembled(i, j), expected, 1e-12 * k.cwiseAbs().maxCoeff()) << i << ", " << j;
    }
  }
  // Same model, other scales: the pattern is reused, only values change.
  ASSERT_TRUE(system.prepare(model, 1, 0, 2e-3, free, settings));
  EXPECT_FALSE(system.pattern_rebuilt());
  EXPECT_NEAR(system.matrix().coeff(10, 10), model.masses()(3) + 2e-3 * k(10, 10), 1e-12);
}

TEST(ConstrainedSystem, SolvesAgreeAcrossVariantsAndPreconditioners) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  testing::LinearModel model = testing::make_linear_tet_model(mesh, 1e4, 0.45, 1000, 1, 1e-3);
  Prescribed held{AxisMask::Zero(mesh.num_nodes(), 3), mesh.rest};
  held.mask.row(0).setOnes();
  held.mask.row(7).setOnes();
  Points free;
  free_coordinates(held, model.masses(), free);
  Points rhs(mesh.num_nodes(), 3);
  for (int i = 0; i < mesh.num_nodes(); ++i)
    rhs.row(i) << std::sin(i), std::cos(2 * i), 0.3;
  Points reference;
  for (const auto& [solver, preconditioner] :
       {std::pair{LinearSolver::assembled_ldlt, Preconditioner::jacobi},
        std::pair{LinearSolver::matrix_free_cg, Preconditioner::none},
        std::pair{LinearSolver::matrix_free_cg, Preconditioner::mass},
        std::pair{LinearSolver::matrix_free_cg, Preconditioner::jacobi},
        std::pair{LinearSolver::assembled_cg, Preconditioner::jacobi}}) {
    ConstrainedSystem system;
    const LinearSolveSettings settings{solver, preconditioner, CgSettings{1e-13, 5000}};
    ASSERT_TRUE(system.prepare(model, 1, 0.01, 1e-4, free, settings));
    Points y = Points::Zero(mesh.num_nodes(), 3);
    const CgReport report = system.solve(rhs, y);
    EXPECT_TRUE(report.converged);
    EXPECT_EQ(y.row(0), Eigen::RowVector3d::Zero());
    // A y = rhs on the free coordinates.
    Points ay(mesh.num_nodes(), 3);
    system.apply_unconstrained(y, ay);
    EXPECT_LT((ay - rhs).cwiseProduct(free).norm(), 1e-12 * rhs.norm());
    if (reference.size() == 0) {
      reference = y;
    } else {
      EXPECT_LT((y - reference).norm(), 1e-10 * reference.norm());
    }
  }
}

TEST(ConjugateGradient, ZeroRightHandSideAndIterationCap) {
  testing::LinearModel model = testing::make_oscillator(1, 4);
  Points free = Points::Ones(1, 3);
  ConstrainedSystem system;
  ASSERT_TRUE(system.prepare(model, 1, 0, 1, free, LinearSolveSettings{}));
  Points y = Points::Constant(1, 3, 7.0);
  const CgReport zero = system.solve(Points::Zero(1, 3), y);
  EXPECT_TRUE(zero.converged);
  EXPECT_EQ(zero.iterations, 0);
  EXPECT_EQ(y, Points::Zero(1, 3));
  // A = 5 I: Jacobi-preconditioned CG solves it in one iteration.
  Points rhs(1, 3);
  rhs << 5, 10, -5;
  const CgReport one = system.solve(rhs, y);
  EXPECT_EQ(one.iterations, 1);
  EXPECT_TRUE(row3(y, 0).isApprox(Vec3(1, 2, -1), 1e-14));
}

}  // namespace
}  // namespace incise::sim
