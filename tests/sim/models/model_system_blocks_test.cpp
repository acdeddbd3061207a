// The assembly interface of the assembled solvers (model.h): add_damping_triplets against the
// damping operator, system_blocks/add_system_blocks against the triplets, the FEM models' 10-block
// override against the base-class default, and topology_revision. Every model a scene can name,
// on a rotated, jittered box with one inverted tet, after prepare_stiffness there.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "sim/mesh/box_mesher.h"
#include "sim/models/model.h"
#include "sim/scene/scene_run.h"
#include "sim/solve/block_sparse.h"

namespace incise::sim {
namespace {

// The models, as make_model builds them: stvk and Neo-Hookean with the projected tangent (time
// integrators) and with the exact Hessian (the static solver).
struct ModelCase {
  std::string name;
  MaterialModel model;
  Integrator integrator;
};

std::vector<ModelCase> model_cases() {
  return {
      {"mss", MaterialModel::mass_spring, Integrator::implicit_euler},
      {"linear", MaterialModel::linear, Integrator::implicit_euler},
      {"corotational", MaterialModel::corotational, Integrator::implicit_euler},
      {"corotational_polar", MaterialModel::corotational_polar, Integrator::implicit_euler},
      {"stvk_projected", MaterialModel::stvk, Integrator::implicit_euler},
      {"stvk_exact", MaterialModel::stvk, Integrator::static_equilibrium},
      {"neohookean_projected", MaterialModel::neohookean, Integrator::implicit_euler},
      {"neohookean_exact", MaterialModel::neohookean, Integrator::static_equilibrium},
  };
}

bool is_fem(MaterialModel model) {
  return model != MaterialModel::mass_spring;
}

// 3 x 2 x 1 cells: node (3, 0, 0), index 3, has odd grid parity and sits in the corner of one
// cell only, so it belongs to exactly one tet (the one cut off at that corner).
TetMesh test_box() {
  return make_box_mesh(Vec3(0.03, 0.02, 0.01), Vec3i(3, 2, 1));
}
constexpr int kLoneNode = 3;

std::unique_ptr<Model> make(const ModelCase& c, const TetMesh& mesh) {
  Scene scene;
  scene.material.model = c.model;
  scene.material.youngs_modulus = 2e4;
  scene.material.poisson_ratio = 0.4;
  scene.material.density = 1000;
  scene.material.damping = 0.3;
  scene.solver.integrator = c.integrator;
  return make_model(scene, mesh);
}

int tet_of(const TetMesh& mesh, int node) {
  int found = -1, count = 0;
  for (int t = 0; t < mesh.num_tets(); ++t) {
    for (int k = 0; k < 4; ++k) {
      if (mesh.tets(t, k) == node) {
        found = t;
        ++count;
      }
    }
  }
  EXPECT_EQ(count, 1) << "node " << node << " should be in exactly one tet";
  return found;
}

Real signed_volume(const Points& x, const TetMesh& mesh, int t) {
  const Vec3 x0 = x.row(mesh.tets(t, 0)).transpose();
  Mat3 edges;
  for (int k = 1; k < 4; ++k)
    edges.col(k - 1) = x.row(mesh.tets(t, k)).transpose() - x0;
  return edges.determinant() / 6;
}

// The rest shape jittered by 5% of a cell, rotated, with the lone node mirrored through the plane
// of the other three nodes of its tet: that tet (and only it) is inverted.
Points deformed_state(const TetMesh& mesh) {
  std::mt19937 random(11);
  std::uniform_real_distribution<Real> jitter(-5e-4, 5e-4);
  Points x = mesh.rest;
  for (Eigen::Index d = 0; d < x.size(); ++d)
    x.data()[d] += jitter(random);
  const Mat3 rotation =
      Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix().transpose();
  x = (x * rotation).eval();
  const int t = tet_of(mesh, kLoneNode);
  Vec3 others[3];
  int n = 0;
  for (int k = 0; k < 4; ++k) {
    if (mesh.tets(t, k) != kLoneNode) others[n++] = x.row(mesh.tets(t, k)).transpose();
  }
  const Vec3 normal = (others[1] - others[0]).cross(others[2] - others[0]).normalized();
  const Vec3 p = x.row(kLoneNode).transpose();
  x.row(kLoneNode) = (p - 2 * normal.dot(p - others[0]) * normal).transpose();
  return x;
}

Eigen::MatrixXd dense_from(const std::vector<Eigen::Triplet<Real>>& triplets, Eigen::Index dofs) {
  Eigen::SparseMatrix<Real> sparse(dofs, dofs);
  sparse.setFromTriplets(triplets.begin(), triplets.end());
  return Eigen::MatrixXd(sparse);
}

Eigen::MatrixXd damping_triplets(const Model& model, Eigen::Index dofs) {
  std::vector<Eigen::Triplet<Real>> triplets;
  model.add_damping_triplets(triplets);
  return dense_from(triplets, dofs);
}

Eigen::MatrixXd stiffness_triplets(const Model& model, Eigen::Index dofs) {
  std::vector<Eigen::Triplet<Real>> triplets;
  model.add_stiffness_triplets(triplets);
  return dense_from(triplets, dofs);
}

// The dense matrix of the blocks (pairs[k] = (i, j), values 9 per block, column-major): block k
// at (i, j) and, for i != j, its transpose at (j, i) (the rule of model.h).
Eigen::MatrixXd dense_from_blocks(const std::vector<std::pair<int, int>>& pairs,
                                  const std::vector<Real>& values, Eigen::Index dofs) {
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(dofs, dofs);
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [i, j] = pairs[k];
    const Mat3 block = Eigen::Map<const Mat3>(values.data() + 9 * k);
    dense.block<3, 3>(3 * i, 3 * j) += block;
    if (i != j) dense.block<3, 3>(3 * j, 3 * i) += block.transpose();
  }
  return dense;
}

// Every block into its own 9 values, untransposed (slots 9 k), or, with transposed, through the
// negative-slot path (BlockTarget then adds the transpose, which dense_from_blocks reads as the
// block of the swapped pair).
struct Assembled {
  std::vector<std::pair<int, int>> pairs;
  Eigen::MatrixXd matrix;
};

Assembled assemble_blocks(const Model& model, Real b, Real c, Eigen::Index dofs, bool base_class,
                          bool transposed) {
  Assembled out;
  if (base_class) {
    model.Model::system_blocks(out.pairs);
  } else {
    model.system_blocks(out.pairs);
  }
  std::vector<Real> values(9 * out.pairs.size(), Real(0));
  std::vector<int> slots(out.pairs.size());
  for (std::size_t k = 0; k < slots.size(); ++k)
    slots[k] = transposed ? -9 * static_cast<int>(k) - 1 : 9 * static_cast<int>(k);
  const BlockTarget target{values.data(), slots.data()};
  if (base_class) {
    model.Model::add_system_blocks(b, c, target);
  } else {
    model.add_system_blocks(b, c, target);
  }
  std::vector<std::pair<int, int>> stored = out.pairs;
  if (transposed) {
    for (auto& pair : stored)
      std::swap(pair.first, pair.second);
  }
  out.matrix = dense_from_blocks(stored, values, dofs);
  return out;
}

Real max_abs(const Eigen::MatrixXd& m) {
  return m.cwiseAbs().maxCoeff();
}

class SystemBlocks : public ::testing::TestWithParam<ModelCase> {
 protected:
  void SetUp() override {
    mesh_ = test_box();
    model_ = make(GetParam(), mesh_);
    x_ = deformed_state(mesh_);
    dofs_ = 3 * mesh_.num_nodes();
    model_->prepare_stiffness(x_);
  }

  TetMesh mesh_;
  std::unique_ptr<Model> model_;
  Points x_;
  Eigen::Index dofs_ = 0;
};

TEST_P(SystemBlocks, StateHasExactlyOneInvertedTet) {
  int inverted = 0;
  for (int t = 0; t < mesh_.num_tets(); ++t)
    inverted += signed_volume(x_, mesh_, t) <= 0 ? 1 : 0;
  EXPECT_EQ(inverted, 1);
  if (is_fem(GetParam().model)) {
    Points f = Points::Zero(mesh_.num_nodes(), 3);
    model_->add_forces(x_, Points::Zero(mesh_.num_nodes(), 3), f);
    EXPECT_EQ(model_->health().inverted_elements, 1);
    EXPECT_TRUE(f.allFinite());
  }
}

TEST_P(SystemBlocks, DampingTripletsAreTheDampingOperatorAndSymmetricPositiveSemiDefinite) {
  const Eigen::MatrixXd d = damping_triplets(*model_, dofs_);
  ASSERT_GT(max_abs(d), 0) << "damping > 0 must give a non-zero D";
  // Column j of the operator: D e_j.
  Eigen::MatrixXd op(dofs_, dofs_);
  Points unit = Points::Zero(mesh_.num_nodes(), 3);
  Points out(mesh_.num_nodes(), 3);
  for (Eigen::Index j = 0; j < dofs_; ++j) {
    unit.data()[j] = 1;
    out.setZero();
    model_->add_damping_times(unit, out);
    op.col(j) = Eigen::Map<const VecX>(out.data(), dofs_);
    unit.data()[j] = 0;
  }
  const Real scale = max_abs(op);
  EXPECT_LE(max_abs(d - op), 1e-12 * scale);
  EXPECT_LE(max_abs(d - d.transpose()), 1e-12 * scale);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(Real(0.5) * (d + d.transpose()));
  EXPECT_GE(eigen.eigenvalues().minCoeff(), -1e-10 * eigen.eigenvalues().maxCoeff());
}

TEST_P(SystemBlocks, BlocksAssembleDampingAndStiffnessScaled) {
  const Real b = 0.37, c = 1.9e-3;
  const Eigen::MatrixXd expected =
      b * damping_triplets(*model_, dofs_) + c * stiffness_triplets(*model_, dofs_);
  const Real scale = max_abs(expected);
  ASSERT_GT(scale, 0);
  for (const bool transposed : {false, true}) {
    const Assembled assembled = assemble_blocks(*model_, b, c, dofs_, false, transposed);
    EXPECT_LE(max_abs(assembled.matrix - expected), 1e-12 * scale) << "transposed " << transposed;
    for (const auto& [i, j] : assembled.pairs) {
      ASSERT_GE(std::min(i, j), 0);
      ASSERT_LT(std::max(i, j), mesh_.num_nodes());
    }
    if (is_fem(GetParam().model)) {
      EXPECT_EQ(assembled.pairs.size(), 10u * static_cast<std::size_t>(mesh_.num_tets()));
    }
  }
  // The scales act on their own terms: no damping, then no stiffness (c = 0 is not a solver's
  // case, but the blocks must still be linear in the two scales).
  EXPECT_LE(max_abs(assemble_blocks(*model_, 0, c, dofs_, false, false).matrix -
                    c * stiffness_triplets(*model_, dofs_)),
            1e-12 * scale);
  EXPECT_LE(max_abs(assemble_blocks(*model_, b, 0, dofs_, false, false).matrix -
                    b * damping_triplets(*model_, dofs_)),
            1e-12 * scale);
}

TEST_P(SystemBlocks, BlocksThroughSymmetricBlockMatrixGiveTheSameMatrix) {
  const Real b = 0.37, c = 1.9e-3;
  std::vector<std::pair<int, int>> pairs;
  model_->system_blocks(pairs);
  SymmetricBlockMatrix matrix;
  std::vector<int> slots;
  matrix.build(mesh_.num_nodes(), pairs, slots);
  model_->add_system_blocks(b, c, BlockTarget{matrix.values(), slots.data()});
  const Eigen::MatrixXd expected =
      b * damping_triplets(*model_, dofs_) + c * stiffness_triplets(*model_, dofs_);
  EXPECT_LE(max_abs(Eigen::MatrixXd(matrix.full()) - expected), 1e-12 * max_abs(expected));
}

TEST_P(SystemBlocks, BaseClassDefaultGivesTheSameMatrixAsTheOverride) {
  const Real b = 0.37, c = 1.9e-3;
  const Assembled fast = assemble_blocks(*model_, b, c, dofs_, false, false);
  const Assembled fallback = assemble_blocks(*model_, b, c, dofs_, true, false);
  EXPECT_LE(max_abs(fast.matrix - fallback.matrix), 1e-12 * max_abs(fast.matrix));
  // The default's blocks are on or below the block diagonal, one per triplet there.
  for (const auto& [i, j] : fallback.pairs)
    EXPECT_GE(i, j);
  // Through the transposed slots as well.
  const Assembled fallback_transposed = assemble_blocks(*model_, b, c, dofs_, true, true);
  EXPECT_LE(max_abs(fallback_transposed.matrix - fast.matrix), 1e-12 * max_abs(fast.matrix));
}

TEST_P(SystemBlocks, PatternIsStableUntilTopologyChangesAndRevisionMoves) {
  std::vector<std::pair<int, int>> first, again;
  model_->system_blocks(first);
  model_->prepare_stiffness(mesh_.rest);  // a new linearisation keeps the pattern
  model_->system_blocks(again);
  EXPECT_EQ(first, again);

  const std::uint64_t before = model_->topology_revision();
  // A cut: the mesh without its last two tets (same nodes).
  TetMesh cut = mesh_;
  cut.tets.conservativeResize(mesh_.num_tets() - 2, 4);
  cut.labels.conservativeResize(mesh_.num_tets() - 2);
  model_->update_topology(cut);
  const std::uint64_t after = model_->topology_revision();
  EXPECT_NE(after, before);
  model_->update_topology(cut);  // every update counts, even to the same tets
  EXPECT_NE(model_->topology_revision(), after);

  std::vector<std::pair<int, int>> pairs;
  model_->system_blocks(pairs);
  if (is_fem(GetParam().model)) {
    EXPECT_EQ(pairs.size(), 10u * static_cast<std::size_t>(cut.num_tets()));
  }
  // And the new blocks still give the new matrix.
  model_->prepare_stiffness(x_);
  const Real b = 0.5, c = 1e-3;
  const Eigen::MatrixXd expected =
      b * damping_triplets(*model_, dofs_) + c * stiffness_triplets(*model_, dofs_);
  EXPECT_LE(max_abs(assemble_blocks(*model_, b, c, dofs_, false, false).matrix - expected),
            1e-12 * max_abs(expected));
}

INSTANTIATE_TEST_SUITE_P(AllModels, SystemBlocks, ::testing::ValuesIn(model_cases()),
                         [](const ::testing::TestParamInfo<ModelCase>& info) {
                           return info.param.name;
                         });

}  // namespace
}  // namespace incise::sim
