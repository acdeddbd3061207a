#include "sim/solve/static_solver.h"

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <cmath>

#include "sim/mesh/box_mesher.h"
#include "sim/scene/scene_run.h"
#include "test_models.h"

namespace incise::sim {
namespace {

const Points kNoForces;

TEST(StaticSolver, LinearNetworkEqualsADirectSparseSolve) {
  const TetMesh mesh = make_box_mesh(Vec3(0.06, 0.02, 0.02), Vec3i(6, 2, 2));
  testing::LinearModel model = testing::make_linear_tet_model(mesh, 5e3, 0.4, 1000);
  // Clamped at x = 0, the x = L face pulled down by 2 mm, a load on one node, and gravity.
  Prescribed held{AxisMask::Zero(mesh.num_nodes(), 3), mesh.rest};
  Points load = Points::Zero(mesh.num_nodes(), 3);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 0) == 0) held.mask.row(i).setOnes();
    if (mesh.rest(i, 0) > 0.0599) {
      held.mask(i, 2) = 1;
      held.position(i, 2) -= 2e-3;
    }
  }
  load(20, 1) = 1e-3;
  const Vec3 gravity(0, 0, -9.81);

  // Direct: K_ff u_f = (load + M g)_f - K_fp u_p.
  const Eigen::Index dofs = 3 * mesh.num_nodes();
  VecX u_p = VecX::Zero(dofs), rhs(dofs);
  std::vector<int> free_index(dofs, -1);
  int num_free = 0;
  for (Eigen::Index d = 0; d < dofs; ++d) {
    rhs(d) = load.data()[d] + model.masses()(d / 3) * gravity(d % 3);
    if (held.mask.data()[d] != 0) {
      u_p(d) = held.position.data()[d] - mesh.rest.data()[d];
    } else {
      free_index[d] = num_free++;
    }
  }
  rhs -= model.stiffness() * u_p;
  std::vector<Eigen::Triplet<Real>> kff;
  VecX rhs_f(num_free);
  for (int j = 0; j < model.stiffness().outerSize(); ++j) {
    for (testing::SparseMatrix::InnerIterator it(model.stiffness(), j); it; ++it) {
      if (free_index[it.row()] >= 0 && free_index[it.col()] >= 0) {
        kff.emplace_back(free_index[it.row()], free_index[it.col()], it.value());
      }
    }
  }
  for (Eigen::Index d = 0; d < dofs; ++d) {
    if (free_index[d] >= 0) rhs_f(free_index[d]) = rhs(d);
  }
  testing::SparseMatrix k_ff(num_free, num_free);
  k_ff.setFromTriplets(kff.begin(), kff.end());
  const VecX u_f = Eigen::SimplicialLDLT<testing::SparseMatrix>(k_ff).solve(rhs_f);
  Points expected = mesh.rest;
  for (Eigen::Index d = 0; d < dofs; ++d) {
    expected.data()[d] += free_index[d] >= 0 ? u_f(free_index[d]) : u_p(d);
  }
  const Real scale = (expected - mesh.rest).cwiseAbs().maxCoeff();

  for (const LinearSolver solver :
       {LinearSolver::matrix_free_cg, LinearSolver::assembled_cg, LinearSolver::assembled_ldlt}) {
    StaticSettings settings;
    settings.tolerance = 1e-10;
    settings.linear.solver = solver;
    StaticSolver statics(settings);
    Points x = mesh.rest;
    const StaticReport report = statics.solve(gravity, load, held, model, x);
    EXPECT_TRUE(report.converged) << static_cast<int>(solver);
    EXPECT_LE(report.relative_residual, 1e-10);
    EXPECT_LE(report.iterations, 4);  // linear: one Newton step up to the inner tolerance
    EXPECT_LT((x - expected).cwiseAbs().maxCoeff(), 1e-8 * scale) << static_cast<int>(solver);
    for (Eigen::Index d = 0; d < dofs; ++d) {
      if (held.mask.data()[d] != 0) {
        EXPECT_EQ(x.data()[d], held.position.data()[d]);
      }
    }
  }
}

// A chain of n springs along x, node 0 clamped, every node held in y and z, a tip load F. Each
// spring carries F, so every extension solves k1 e + k3 e^3 = F and x_i = i (L + e).
struct Chain {
  static constexpr int kSprings = 8;
  static constexpr Real kLength = 0.01, kK1 = 100, kK3 = 4e7, kLoad = 5;
  Points rest = Points::Zero(kSprings + 1, 3);
  Edges edges = Edges(kSprings, 2);
  Prescribed held{AxisMask::Zero(kSprings + 1, 3), Points::Zero(kSprings + 1, 3)};
  Points load = Points::Zero(kSprings + 1, 3);
  Chain() {
    for (int i = 0; i <= kSprings; ++i) {
      rest(i, 0) = i * kLength;
      held.mask(i, 1) = held.mask(i, 2) = 1;
    }
    for (int s = 0; s < kSprings; ++s)
      edges.row(s) << s, s + 1;
    held.mask(0, 0) = 1;
    held.position = rest;
    load(kSprings, 0) = kLoad;
  }
  Real extension() const {  // Newton on the scalar cubic, to round-off
    Real e = 0;
    for (int it = 0; it < 100; ++it)
      e -= (kK1 * e + kK3 * e * e * e - kLoad) / (kK1 + 3 * kK3 * e * e);
    return e;
  }
};

TEST(StaticSolver, NonlinearChainConvergesQuadraticallyToTheClosedForm) {
  const Chain chain;
  testing::NonlinearSprings model(chain.rest, chain.edges, VecX::Ones(Chain::kSprings + 1),
                                  Chain::kK1, Chain::kK3);
  const Real e = chain.extension();
  ASSERT_GT(Chain::kK3 * e * e * e, Chain::kK1 * e);  // the cubic term dominates: nonlinear
  StaticSettings settings;
  settings.tolerance = 1e-12;
  StaticSolver statics(settings);
  Points x = chain.rest;
  const StaticReport report = statics.solve(Vec3::Zero(), chain.load, chain.held, model, x);
  ASSERT_TRUE(report.converged);
  EXPECT_LE(report.iterations, 20);
  for (int i = 0; i <= Chain::kSprings; ++i) {
    EXPECT_NEAR(x(i, 0), i * (Chain::kLength + e), 1e-12) << i;
    EXPECT_EQ(x(i, 1), 0);
  }
  // Quadratic convergence: once the residual is small, each iteration squares it (up to a
  // constant): r_k+1 <= C r_k^2 while r_k^2 is above round-off, and from 1e-3 to 1e-12 takes at
  // most 3 iterations.
  const auto& history = report.residual_history;
  int small_from = -1;
  for (std::size_t k = 0; k < history.size(); ++k) {
    if (history[k] < 1e-3 && small_from < 0) small_from = static_cast<int>(k);
  }
  ASSERT_GE(small_from, 0);
  EXPECT_LE(static_cast<int>(history.size()) - 1 - small_from, 3);
  for (std::size_t k = small_from; k + 1 < history.size() && history[k] > 1e-7; ++k) {
    EXPECT_LE(history[k + 1], 100 * history[k] * history[k] + 1e-14) << k;
  }
}

// The QR corotational tangent omits the change of R (corotational_fem.h), so Newton's direction
// need not reduce the residual norm; it is a descent direction of the total potential, which the
// line search also accepts. A cantilever bent by a fifth of its length must then converge, to a
// minimum of the potential (no direction lowers it).
TEST(StaticSolver, ApproximateCorotationalTangentStillConvergesToTheMinimum) {
  const TetMesh mesh = make_box_mesh(Vec3(0.1, 0.0125, 0.0125), Vec3i(16, 2, 2));
  Scene scene;
  scene.material = {MaterialModel::corotational, 3000, 0.3, 1000, 0};
  auto model = make_model(scene, mesh);
  Prescribed held{AxisMask::Zero(mesh.num_nodes(), 3), mesh.rest};
  Points load = Points::Zero(mesh.num_nodes(), 3);
  int tip_nodes = 0;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 0) < 1e-9) held.mask.row(i).setOnes();
    tip_nodes += mesh.rest(i, 0) > 0.1 - 1e-9 ? 1 : 0;
  }
  // About 20% of the length by Euler-Bernoulli (I = h^4 / 12): P = 0.2 L 3 E I / L^3.
  const Real second_moment = std::pow(0.0125, 4) / 12;
  const Real total_load = 0.2 * 3 * 3000 * second_moment / (0.1 * 0.1);
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 0) > 0.1 - 1e-9) load(i, 2) = -total_load / tip_nodes;
  }
  StaticSettings settings;
  settings.max_iterations = 200;
  StaticSolver solver(settings);
  Points x = mesh.rest;
  const StaticReport report = solver.solve(Vec3::Zero(), load, held, *model, x);
  ASSERT_TRUE(report.finite);
  EXPECT_TRUE(report.converged) << report.relative_residual << " after " << report.iterations;
  Real tip = 0;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (mesh.rest(i, 0) > 0.1 - 1e-9) tip += (mesh.rest(i, 2) - x(i, 2)) / tip_nodes;
  }
  EXPECT_GT(tip, 0.01);  // bent down by centimetres, not stuck near the start
  // A minimum: small moves of the free coordinates in random directions raise the potential.
  const auto potential = [&](const Points& at) {
    return model->potential_energy(at) - load.cwiseProduct(at).sum();
  };
  const Real at_solution = potential(x);
  std::srand(7);
  for (int trial = 0; trial < 5; ++trial) {
    Points direction = Points::Random(mesh.num_nodes(), 3);
    for (int i = 0; i < mesh.num_nodes(); ++i) {
      if (held.mask(i, 0) != 0) direction.row(i).setZero();
    }
    const Points moved = x + 1e-5 * direction;
    EXPECT_GT(potential(moved), at_solution) << "trial " << trial;
  }
}

TEST(StaticSolver, ReportsNonConvergenceAtAnImpossibleCap) {
  const Chain chain;
  testing::NonlinearSprings model(chain.rest, chain.edges, VecX::Ones(Chain::kSprings + 1),
                                  Chain::kK1, Chain::kK3);
  for (const int cap : {0, 2}) {
    StaticSettings settings;
    settings.tolerance = 1e-12;
    settings.max_iterations = cap;
    StaticSolver statics(settings);
    Points x = chain.rest;
    const StaticReport report = statics.solve(Vec3::Zero(), chain.load, chain.held, model, x);
    EXPECT_FALSE(report.converged);
    EXPECT_EQ(report.iterations, cap);
    EXPECT_GT(report.relative_residual, 1e-12);
    EXPECT_TRUE(report.finite);
    EXPECT_TRUE(x.allFinite());
    EXPECT_EQ(report.residual_history.size(), static_cast<std::size_t>(cap) + 1);
  }
  EXPECT_THROW(StaticSolver(StaticSettings{0, 10}), std::invalid_argument);
}

TEST(StaticSolver, AlreadyBalancedIsConvergedWithoutIterations) {
  const Chain chain;
  testing::NonlinearSprings model(chain.rest, chain.edges, VecX::Ones(Chain::kSprings + 1),
                                  Chain::kK1, Chain::kK3);
  StaticSolver statics;
  Points x = chain.rest;
  const StaticReport report = statics.solve(Vec3::Zero(), kNoForces, chain.held, model, x);
  EXPECT_TRUE(report.converged);
  EXPECT_EQ(report.iterations, 0);
  EXPECT_EQ(x, chain.rest);
}

}  // namespace
}  // namespace incise::sim
