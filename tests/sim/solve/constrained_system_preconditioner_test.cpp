// ConstrainedSystem's solver and preconditioner variants on a corotational model (the case they
// were made for: a rotated stiffness that mixes each node's axes, Kelvin-Voigt damping inside the
// assembled matrix, held nodes): every valid combination solves the same system, the lagged
// incomplete Cholesky refactorises only when CG slows down, and block Jacobi against Jacobi.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "sim/mesh/box_mesher.h"
#include "sim/models/corotational_fem.h"
#include "sim/solve/constrained_system.h"
#include "sim/solve/free_coordinates.h"

namespace incise::sim {
namespace {

// A 4 x 2 x 2-cell bar, held on its x = 0 face, in a rotated, jittered state; damping
// beta = 2 ms (a Kelvin-Voigt time about a tenth of the step below).
struct Fixture {
  TetMesh mesh = make_box_mesh(Vec3(0.04, 0.02, 0.02), Vec3i(4, 2, 2));
  CorotationalFem model{mesh, {ElementMaterial{5e4, 0.45, 1000, 2e-3}}, RotationExtraction::qr};
  Points x;
  Points free;
  Points rhs;

  explicit Fixture(Real angle = 0.9) {
    std::mt19937 random(3);
    std::uniform_real_distribution<Real> jitter(-5e-4, 5e-4);
    x = mesh.rest;
    for (Eigen::Index d = 0; d < x.size(); ++d)
      x.data()[d] += jitter(random);
    const Mat3 rotation = Eigen::AngleAxisd(angle, Vec3(1, -2, 2).normalized()).toRotationMatrix();
    x = (x * rotation.transpose()).eval();
    model.prepare_stiffness(x);
    Prescribed held{AxisMask::Zero(mesh.num_nodes(), 3), mesh.rest};
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      if (mesh.rest(i, 0) == 0) held.mask.row(i).setOnes();
    }
    held.mask(mesh.num_nodes() - 1, 1) = 1;  // and one axis of the far corner
    free_coordinates(held, model.masses(), free);
    rhs.resize(mesh.num_nodes(), 3);
    for (int i = 0; i < mesh.num_nodes(); ++i)
      rhs.row(i) << std::sin(1.3 * i), std::cos(0.7 * i), 0.2 + 0.1 * std::sin(3.1 * i);
    rhs *= 1e-3;
  }
};

// Implicit Euler's A = M + h D + h^2 K at h = 10 ms: on the diagonal, h^2 K is about 270 and h D
// about 50 times the node masses, so A is far from diagonal and the preconditioner matters.
constexpr Real kStep = 1e-2;
constexpr Real kMass = 1, kDamping = kStep, kStiffness = kStep * kStep;

LinearSolveSettings settings_of(LinearSolver solver, Preconditioner preconditioner,
                                Real tolerance = 1e-13) {
  LinearSolveSettings settings;
  settings.solver = solver;
  settings.preconditioner = preconditioner;
  settings.cg = CgSettings{tolerance, 5000};
  return settings;
}

// ||(A y - rhs) on the free coordinates|| / ||rhs on the free coordinates||, with A applied
// through the model's operators (not the assembled matrix).
Real operator_residual(const ConstrainedSystem& system, const Fixture& f, const Points& y) {
  Points ay(y.rows(), 3);
  system.apply_unconstrained(y, ay);
  return (ay - f.rhs).cwiseProduct(f.free).norm() / f.rhs.cwiseProduct(f.free).norm();
}

struct Combination {
  LinearSolver solver;
  Preconditioner preconditioner;
  const char* name;
};

const std::vector<Combination>& valid_combinations() {
  static const std::vector<Combination> combinations = {
      {LinearSolver::assembled_ldlt, Preconditioner::jacobi, "assembled_ldlt"},
      {LinearSolver::matrix_free_cg, Preconditioner::none, "matrix_free_cg/none"},
      {LinearSolver::matrix_free_cg, Preconditioner::mass, "matrix_free_cg/mass"},
      {LinearSolver::matrix_free_cg, Preconditioner::jacobi, "matrix_free_cg/jacobi"},
      {LinearSolver::matrix_free_cg, Preconditioner::block_jacobi, "matrix_free_cg/block_jacobi"},
      {LinearSolver::assembled_cg, Preconditioner::jacobi, "assembled_cg/jacobi"},
      {LinearSolver::assembled_cg, Preconditioner::block_jacobi, "assembled_cg/block_jacobi"},
      {LinearSolver::assembled_cg, Preconditioner::incomplete_cholesky,
       "assembled_cg/incomplete_cholesky"},
  };
  return combinations;
}

TEST(Preconditioners, AssembledMatrixIsMassDampingAndStiffnessWithHeldIdentity) {
  const Fixture f;
  ConstrainedSystem system;
  ASSERT_TRUE(system.prepare(f.model, kMass, kDamping, kStiffness, f.free,
                             settings_of(LinearSolver::assembled_cg, Preconditioner::jacobi)));
  const Eigen::Index dofs = 3 * f.mesh.num_nodes();
  std::vector<Eigen::Triplet<Real>> k_triplets, d_triplets;
  f.model.add_stiffness_triplets(k_triplets);
  f.model.add_damping_triplets(d_triplets);
  Eigen::SparseMatrix<Real> k(dofs, dofs), d(dofs, dofs);
  k.setFromTriplets(k_triplets.begin(), k_triplets.end());
  d.setFromTriplets(d_triplets.begin(), d_triplets.end());
  Eigen::MatrixXd expected = kDamping * Eigen::MatrixXd(d) + kStiffness * Eigen::MatrixXd(k);
  for (Eigen::Index r = 0; r < dofs; ++r)
    expected(r, r) += kMass * f.model.masses()(r / 3);
  for (Eigen::Index r = 0; r < dofs; ++r) {
    if (f.free.data()[r] != 0) continue;
    expected.row(r).setZero();
    expected.col(r).setZero();
    expected(r, r) = 1;
  }
  const Eigen::MatrixXd assembled(system.matrix());
  EXPECT_LE((assembled - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff());
}

TEST(Preconditioners, EveryValidCombinationSolvesTheSameSystem) {
  const Fixture f;
  Points reference;
  for (const Combination& combination : valid_combinations()) {
    SCOPED_TRACE(combination.name);
    ConstrainedSystem system;
    ASSERT_TRUE(system.prepare(f.model, kMass, kDamping, kStiffness, f.free,
                               settings_of(combination.solver, combination.preconditioner)));
    Points y = Points::Zero(f.mesh.num_nodes(), 3);
    const CgReport report = system.solve(f.rhs, y);
    EXPECT_TRUE(report.converged) << report.relative_residual;
    EXPECT_FALSE(report.breakdown);
    // Held coordinates stay 0.
    EXPECT_EQ(y.cwiseProduct(Points::Ones(y.rows(), 3) - f.free).cwiseAbs().maxCoeff(), 0);
    EXPECT_LT(operator_residual(system, f, y), 1e-10);
    if (reference.size() == 0) {
      reference = y;  // LDLT
    } else {
      EXPECT_LT((y - reference).norm(), 1e-9 * reference.norm());
    }
  }
}

TEST(Preconditioners, IncompleteCholeskyNeedsTheAssembledCg) {
  const Fixture f;
  ConstrainedSystem system;
  EXPECT_THROW(system.prepare(
                   f.model, kMass, kDamping, kStiffness, f.free,
                   settings_of(LinearSolver::matrix_free_cg, Preconditioner::incomplete_cholesky)),
               std::invalid_argument);
  EXPECT_THROW(system.prepare(
                   f.model, kMass, kDamping, kStiffness, f.free,
                   settings_of(LinearSolver::assembled_ldlt, Preconditioner::incomplete_cholesky)),
               std::invalid_argument);
}

TEST(Preconditioners, LaggedIncompleteCholeskyIsKeptWhileTheMatrixDriftsSlowly) {
  const Fixture f;
  ConstrainedSystem system;
  const LinearSolveSettings settings =
      settings_of(LinearSolver::assembled_cg, Preconditioner::incomplete_cholesky, 1e-10);
  Real c = kStiffness;
  int first_iterations = 0;
  const int calls = 10;
  for (int call = 0; call < calls; ++call, c *= 1.01) {
    ASSERT_TRUE(system.prepare(f.model, kMass, kDamping, c, f.free, settings));
    Points y = Points::Zero(f.mesh.num_nodes(), 3);
    const CgReport report = system.solve(f.rhs, y);
    ASSERT_TRUE(report.converged) << "call " << call;
    EXPECT_LT(operator_residual(system, f, y), 1e-8) << "call " << call;
    if (call == 0) first_iterations = report.iterations;
    // The lag costs at most the refactor ratio in iterations (else it refactorises).
    EXPECT_LE(report.iterations, settings.refactor_ratio * first_iterations + 1) << "call " << call;
  }
  // A 10% drift of c over ten calls does not slow CG by half: one factorisation serves them all.
  EXPECT_EQ(system.factorisations(), 1);
}

TEST(Preconditioners, LaggedIncompleteCholeskyRefactorisesAfterASlowSolve) {
  const Fixture f;
  ConstrainedSystem system;
  const LinearSolveSettings settings =
      settings_of(LinearSolver::assembled_cg, Preconditioner::incomplete_cholesky, 1e-10);
  // A thousandfold smaller b and c: the mass term dominates at first (about 4 times the stiffness
  // on the diagonal), and a hundredfold c (then about 27 times the mass) is a different matrix,
  // not a multiple of the factorised one (CG does not notice a scaled preconditioner: a plain
  // c x 100 at kStiffness moved CG from 28 to 32 iterations only).
  const Real b = kDamping / 1000, c = kStiffness / 1000;
  Points y = Points::Zero(f.mesh.num_nodes(), 3);
  ASSERT_TRUE(system.prepare(f.model, kMass, b, c, f.free, settings));
  const CgReport baseline = system.solve(f.rhs, y);
  ASSERT_TRUE(baseline.converged);
  EXPECT_EQ(system.factorisations(), 1);

  // The big change: the prepare keeps the old factor (nothing has measured it yet) ...
  ASSERT_TRUE(system.prepare(f.model, kMass, b, 100 * c, f.free, settings));
  EXPECT_EQ(system.factorisations(), 1);
  y.setZero();
  const CgReport slow = system.solve(f.rhs, y);
  ASSERT_TRUE(slow.converged);  // a stale preconditioner is slower, never wrong
  EXPECT_LT(operator_residual(system, f, y), 1e-8);
  ASSERT_GT(slow.iterations, settings.refactor_ratio * baseline.iterations)
      << "the case does not slow CG enough to test the policy: baseline " << baseline.iterations
      << ", after the change " << slow.iterations;

  // ... and the slow solve asks for a new one at the next prepare, which brings the count back.
  ASSERT_TRUE(system.prepare(f.model, kMass, b, 100 * c, f.free, settings));
  EXPECT_EQ(system.factorisations(), 2);
  y.setZero();
  const CgReport refreshed = system.solve(f.rhs, y);
  ASSERT_TRUE(refreshed.converged);
  EXPECT_LT(operator_residual(system, f, y), 1e-8);
  EXPECT_LT(refreshed.iterations, slow.iterations);
  // Then it is kept again.
  ASSERT_TRUE(system.prepare(f.model, kMass, b, 100 * c, f.free, settings));
  EXPECT_EQ(system.factorisations(), 2);
  std::printf("incomplete Cholesky iterations: baseline %d, after c x 100 %d, refactorised %d\n",
              baseline.iterations, slow.iterations, refreshed.iterations);
}

TEST(Preconditioners, IncompleteCholeskyIsRefactorisedOnANewPattern) {
  Fixture f;
  ConstrainedSystem system;
  const LinearSolveSettings settings =
      settings_of(LinearSolver::assembled_cg, Preconditioner::incomplete_cholesky, 1e-10);
  ASSERT_TRUE(system.prepare(f.model, kMass, kDamping, kStiffness, f.free, settings));
  Points y = Points::Zero(f.mesh.num_nodes(), 3);
  ASSERT_TRUE(system.solve(f.rhs, y).converged);
  EXPECT_EQ(system.factorisations(), 1);
  // A cut (the last tet gone) changes the pattern: the old factor has the wrong structure.
  TetMesh cut = f.mesh;
  cut.tets.conservativeResize(f.mesh.num_tets() - 1, 4);
  cut.labels.conservativeResize(f.mesh.num_tets() - 1);
  f.model.update_topology(cut);
  f.model.prepare_stiffness(f.x);
  ASSERT_TRUE(system.prepare(f.model, kMass, kDamping, kStiffness, f.free, settings));
  EXPECT_TRUE(system.pattern_rebuilt());
  EXPECT_EQ(system.factorisations(), 2);
  y.setZero();
  ASSERT_TRUE(system.solve(f.rhs, y).converged);
  EXPECT_LT(operator_residual(system, f, y), 1e-8);
}

// The pattern is keyed by the model's address and topology revision. A new model built where the
// old one was (std::optional::emplace, or an allocator reusing the block) starts at revision 0
// again; with a different numbering of the same nodes its blocks go elsewhere, and the system must
// not fill the old pattern with them.
TEST(Preconditioners, NewModelAtTheSameAddressGetsItsOwnPattern) {
  const TetMesh mesh = make_box_mesh(Vec3(0.03, 0.02, 0.02), Vec3i(3, 2, 2));
  // The same box with its nodes numbered backwards: same sizes, other node pairs.
  const int n = mesh.num_nodes();
  TetMesh renumbered = mesh;
  for (int i = 0; i < n; ++i)
    renumbered.rest.row(n - 1 - i) = mesh.rest.row(i);
  renumbered.x = renumbered.rest;
  for (Eigen::Index d = 0; d < mesh.tets.size(); ++d)
    renumbered.tets.data()[d] = n - 1 - mesh.tets.data()[d];
  const std::vector<ElementMaterial> materials{ElementMaterial{5e4, 0.45, 1000, 2e-3}};
  std::optional<CorotationalFem> model;
  model.emplace(mesh, materials, RotationExtraction::qr);
  const Model* first = &*model;
  const std::uint64_t first_revision = model->topology_revision();
  const Points free = Points::Ones(n, 3);
  const LinearSolveSettings settings =
      settings_of(LinearSolver::assembled_cg, Preconditioner::jacobi);
  ConstrainedSystem system;
  ASSERT_TRUE(system.prepare(*model, kMass, kDamping, kStiffness, free, settings));

  model.emplace(renumbered, materials, RotationExtraction::qr);
  ASSERT_EQ(&*model, first);
  EXPECT_NE(model->topology_revision(), first_revision);  // unique per model, not per address
  ASSERT_TRUE(system.prepare(*model, kMass, kDamping, kStiffness, free, settings));
  // The assembled matrix against the new model's operator, column by column.
  const Eigen::MatrixXd assembled(system.matrix());
  Points unit = Points::Zero(n, 3), column(n, 3);
  Real error = 0;
  for (Eigen::Index j = 0; j < 3 * n; ++j) {
    unit.data()[j] = 1;
    system.apply_unconstrained(unit, column);
    unit.data()[j] = 0;
    error = std::max(
        error,
        (assembled.col(j) - Eigen::Map<const VecX>(column.data(), 3 * n)).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(error, 1e-12 * assembled.cwiseAbs().maxCoeff())
      << "the second model's blocks went into the first model's pattern";
}

// Iterations to 1e-10 of each CG variant at two orientations (the model rotated by 0 and by 0.9
// rad); printed for the report. Block Jacobi inverts each node's 3x3 diagonal block, which the
// rotation fills, so it is asserted to need no more iterations than Jacobi.
TEST(Preconditioners, BlockJacobiAgainstJacobiOnARotatedState) {
  for (const Real angle : {0.0, 0.9}) {
    const Fixture f(angle);
    int iterations[2][2] = {};  // [matrix-free, assembled][jacobi, block_jacobi]
    for (int assembled = 0; assembled < 2; ++assembled) {
      for (int block = 0; block < 2; ++block) {
        ConstrainedSystem system;
        ASSERT_TRUE(system.prepare(
            f.model, kMass, kDamping, kStiffness, f.free,
            settings_of(assembled ? LinearSolver::assembled_cg : LinearSolver::matrix_free_cg,
                        block ? Preconditioner::block_jacobi : Preconditioner::jacobi, 1e-10)));
        Points y = Points::Zero(f.mesh.num_nodes(), 3);
        const CgReport report = system.solve(f.rhs, y);
        ASSERT_TRUE(report.converged);
        iterations[assembled][block] = report.iterations;
      }
    }
    std::printf("angle %.1f: jacobi %d / %d, block_jacobi %d / %d (matrix-free / assembled)\n",
                angle, iterations[0][0], iterations[1][0], iterations[0][1], iterations[1][1]);
    // Matrix-free and assembled apply the same A and the same preconditioner.
    EXPECT_LE(std::abs(iterations[0][0] - iterations[1][0]), 2);
    EXPECT_LE(std::abs(iterations[0][1] - iterations[1][1]), 2);
    EXPECT_LE(iterations[1][1], iterations[1][0]) << "angle " << angle;
  }
}

}  // namespace
}  // namespace incise::sim
