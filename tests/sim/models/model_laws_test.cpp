// The laws every model obeys, over several meshes (a box, a single tet, a sliver, a jittered box):
// Newton's and Euler's laws, no force from rigid motions, forces = -grad E, K = -df/dx, K and D
// symmetric, triplets = add_stiffness_times.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Sparse>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>

#include "model_fixtures.h"
#include "sim/models/tet_elements.h"

namespace incise::sim::testing {
namespace {

class ModelLaws : public ::testing::TestWithParam<std::tuple<int, int>> {
 protected:
  void SetUp() override {
    factory_ = all_models()[static_cast<std::size_t>(std::get<0>(GetParam()))];
    mesh_ = test_meshes()[static_cast<std::size_t>(std::get<1>(GetParam()))].mesh;
    model_ = factory_.make(mesh_, test_materials());
    size_ = mesh_size(mesh_);
  }
  // A random state away from rest: rotated, shifted and deformed by up to 5% of the size
  // (small enough that no tet inverts, also the sliver, whose height is 2% of its size).
  Points deformed(unsigned seed, Real amount = 0.005) const {
    return rigidly_moved(mesh_.rest, random_rotation(seed), Vec3(0.1, -0.2, 0.05)) +
           random_points(mesh_.num_nodes(), amount * size_, seed + 1);
  }
  Points velocities(unsigned seed) const {
    return random_points(mesh_.num_nodes(), 0.5, seed);  // [m/s]
  }
  // max over tets of |F^T F - I| / 2.
  Real largest_strain(const Points& x) const {
    const TetElements elements = make_tet_elements(mesh_, test_materials());
    Real largest = 0;
    for (int t = 0; t < elements.num_tets(); ++t) {
      const Mat3 f =
          edge_matrix(x, elements.tets, t) * elements.rest_inverse[static_cast<std::size_t>(t)];
      largest = std::max(largest, (f.transpose() * f - Mat3::Identity()).norm() / 2);
    }
    return largest;
  }
  Points stiffness_times(const Points& dx) const {
    Points out = Points::Zero(dx.rows(), 3);
    model_->add_stiffness_times(dx, out);
    return out;
  }
  Points damping_times(const Points& dv) const {
    Points out = Points::Zero(dv.rows(), 3);
    model_->add_damping_times(dv, out);
    return out;
  }

  ModelFactory factory_;
  TetMesh mesh_;
  std::unique_ptr<Model> model_;
  Real size_ = 0;
};

TEST_P(ModelLaws, InternalForcesHaveZeroNetForceAndTorque) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Points x = deformed(seed);
    const Points f = forces(*model_, x, velocities(seed + 10));
    Vec3 net = Vec3::Zero();
    Vec3 torque = Vec3::Zero();       // about the origin, at the current positions
    Vec3 rest_torque = Vec3::Zero();  // the linearised law, at the rest positions
    Real force_scale = 0;
    Real torque_scale = 0;
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      const Vec3 fi = f.row(i).transpose();
      net += fi;
      torque += row3(x, static_cast<int>(i)).cross(fi);
      rest_torque += row3(mesh_.rest, static_cast<int>(i)).cross(fi);
      force_scale += fi.norm();
      torque_scale += x.row(i).norm() * fi.norm() + mesh_.rest.row(i).norm() * fi.norm();
    }
    ASSERT_GT(force_scale, 0);
    EXPECT_LT(net.norm(), 1e-12 * force_scale) << seed;
    if (factory_.rotation_invariant) {
      EXPECT_LT(torque.norm(), 1e-12 * torque_scale) << seed;
    } else {
      // Linear FEM: Euler's law holds only at the rest geometry (Physically Realistic FEM
      // section 3.1).
      EXPECT_LT(rest_torque.norm(), 1e-12 * torque_scale) << seed;
    }
  }
}

TEST_P(ModelLaws, RigidMotionOfTheRestShapeProducesNoForce) {
  const Real force_scale = 3000 * size_ * size_;  // E L^2: the force of a 100% strain
  const Points rest_velocity = Points::Zero(mesh_.num_nodes(), 3);
  // A translation with a translational velocity: no force for every model.
  Points shifted = mesh_.rest;
  shifted.rowwise() += Eigen::RowVector3d(0.3, -0.1, 0.2);
  Points drift(mesh_.num_nodes(), 3);
  drift.rowwise() = Eigen::RowVector3d(0.5, 0.2, -0.4);
  EXPECT_LT(forces(*model_, shifted, drift).norm(), 1e-10 * force_scale);
  if (!factory_.rotation_invariant) return;
  for (unsigned seed : {4u, 5u}) {
    const Mat3 rotation = random_rotation(seed);
    const Points x = rigidly_moved(mesh_.rest, rotation, Vec3(0.1, 0.2, -0.3));
    // A spin about an axis through the origin: v = w x x.
    const Vec3 spin(0.7, -1.1, 0.4);  // [rad/s]
    Points v(x.rows(), 3);
    for (Eigen::Index i = 0; i < x.rows(); ++i)
      v.row(i) = spin.cross(row3(x, static_cast<int>(i))).transpose();
    EXPECT_LT(forces(*model_, x, rest_velocity).norm(), 1e-10 * force_scale) << seed;
    EXPECT_LT(forces(*model_, x, v).norm(), 1e-10 * force_scale) << seed;
  }
}

TEST_P(ModelLaws, ForcesAreMinusTheEnergyGradient) {
  const Points zero = Points::Zero(mesh_.num_nodes(), 3);
  for (unsigned seed : {6u, 7u}) {
    const Points x = deformed(seed, 0.01);
    const Points f = forces(*model_, x, zero);
    for (unsigned direction = 0; direction < 3; ++direction) {
      const Points dx = random_points(x.rows(), size_, 100 * seed + direction);
      const Real h = 1e-6;
      const Real slope =
          (model_->potential_energy(x + h * dx) - model_->potential_energy(x - h * dx)) / (2 * h);
      const Real expected = -flat(f).dot(flat(dx));
      EXPECT_NEAR(slope, expected, 1e-6 * flat(f).norm() * flat(dx).norm()) << seed;
    }
  }
}

TEST_P(ModelLaws, StiffnessIsSymmetric) {
  const Points x = deformed(8, 0.02);
  model_->prepare_stiffness(x);
  const Points a = random_points(x.rows(), 1, 81);
  const Points b = random_points(x.rows(), 1, 82);
  const Real ab = flat(a).dot(flat(stiffness_times(b)));
  const Real ba = flat(b).dot(flat(stiffness_times(a)));
  EXPECT_NEAR(ab, ba, 1e-12 * (std::abs(ab) + std::abs(ba) + flat(stiffness_times(a)).norm()));
}

TEST_P(ModelLaws, TripletsReproduceStiffnessTimes) {
  const Points x = deformed(9, 0.02);
  model_->prepare_stiffness(x);
  std::vector<Eigen::Triplet<Real>> triplets;
  model_->add_stiffness_triplets(triplets);
  const Eigen::Index n = 3 * x.rows();
  Eigen::SparseMatrix<Real> k(n, n);
  k.setFromTriplets(triplets.begin(), triplets.end());
  for (unsigned seed : {91u, 92u}) {
    const Points dx = random_points(x.rows(), 1, seed);
    const VecX expected = flat(stiffness_times(dx));
    EXPECT_LT((k * flat(dx) - expected).norm(), 1e-12 * expected.norm()) << seed;
  }
}

TEST_P(ModelLaws, DampingIsTheVelocityDerivativeAndSymmetricPositive) {
  const Points x = deformed(10, 0.02);
  model_->prepare_stiffness(x);
  const Points v = velocities(101);
  const Points dv = velocities(102);
  // The damping force is linear in v: the difference quotient is exact up to round-off.
  const Real h = 1e-3;
  const Points expected =
      -(forces(*model_, x, v + h * dv) - forces(*model_, x, v - h * dv)) / (2 * h);
  const Points d_dv = damping_times(dv);
  EXPECT_LT((d_dv - expected).norm(), 1e-7 * (expected.norm() + 1e-12));
  const Points dw = velocities(103);
  const Real vw = flat(dv).dot(flat(damping_times(dw)));
  const Real wv = flat(dw).dot(flat(d_dv));
  EXPECT_NEAR(vw, wv, 1e-12 * d_dv.norm() * dw.norm());
  EXPECT_GE(flat(dv).dot(flat(d_dv)), -1e-12 * d_dv.norm() * dv.norm());
}

// The largest eigenvalue of the damping matrix D at x (dense: the test meshes are small).
Real largest_damping(Model& model, const Points& x) {
  model.prepare_stiffness(x);
  std::vector<Eigen::Triplet<Real>> triplets;
  model.add_damping_triplets(triplets);
  const auto n = 3 * x.rows();
  Eigen::SparseMatrix<Real> d(n, n);
  d.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::MatrixXd dense(d);
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .maxCoeff();
}

// A tet stretched tenfold (a sliver a cut left, pulled) must not become ~100 times stiffer in
// damping than at rest, or the explicit step the scene chose for its rest shape blows up: the
// FEM models scale beta by min(1, 3 / |F|_F^2), which bounds D by 3 times its rest value (the
// worst case, a uniaxial stretch; tet_fem_model.h).
TEST(ModelDamping, AStretchedStateStaysWithinThreeTimesItsRestValue) {
  for (const ModelFactory& factory : all_models()) {
    if (factory.name.rfind("mss", 0) == 0) continue;  // springs have their own damping
    for (const NamedMesh& named : test_meshes()) {
      SCOPED_TRACE(factory.name + " on " + named.name);
      const std::unique_ptr<Model> model = factory.make(named.mesh, test_materials());
      const Real at_rest = largest_damping(*model, named.mesh.rest);
      ASSERT_GT(at_rest, 0);
      for (const Vec3& stretch : {Vec3(10, 1, 1), Vec3(0.3, 6, 1), Vec3(4, 4, 4)}) {
        const Points x = rigidly_moved(named.mesh.rest * stretch.asDiagonal(), random_rotation(5),
                                       Vec3(0.1, -0.2, 0.05));
        EXPECT_LE(largest_damping(*model, x), 3 * at_rest * (1 + 1e-9)) << stretch.transpose();
      }
    }
  }
}

// soften_element: an FEM element's elastic and viscous forces scale by the factor exactly (the
// others' do not change), update_topology resets it; the mass-spring models cannot and say so.
TEST(ModelSoftening, ScalesOneElementsForcesAndIsResetByARebuild) {
  for (const ModelFactory& factory : all_models()) {
    SCOPED_TRACE(factory.name);
    const TetMesh mesh = test_meshes()[3].mesh;  // the jittered box
    const std::unique_ptr<Model> model = factory.make(mesh, test_materials());
    const Points x = rigidly_moved(mesh.rest, random_rotation(2), Vec3(0.01, 0, 0)) +
                     random_points(mesh.num_nodes(), 0.001, 3);
    const Points v = random_points(mesh.num_nodes(), 0.1, 4);
    const Points before = forces(*model, x, v);
    const bool can = model->soften_element(5, 0.25);
    EXPECT_EQ(can, factory.name.rfind("mss", 0) != 0);
    if (!can) {
      EXPECT_EQ(forces(*model, x, v), before);
      continue;
    }
    // Tet 5's own contribution, from a model of that tet alone.
    TetMesh one = mesh;
    one.tets = mesh.tets.row(5);
    one.labels = mesh.labels.segment(5, 1);
    const Points alone = forces(*factory.make(one, test_materials()), x, v);
    if (factory.name == "corotational_nodal_pressure") {
      // Not one element's scaling there: the softened tet also leaves its nodes' pressure
      // averages (nodal_pressure_fem.h), which moves its neighbours' forces.
      EXPECT_GT((forces(*model, x, v) - before).norm(), 1e-6 * before.norm());
    } else {
      EXPECT_LT((forces(*model, x, v) - (before - 0.75 * alone)).norm(), 1e-9 * before.norm());
    }
    model->update_topology(mesh);
    EXPECT_LT((forces(*model, x, v) - before).norm(), 1e-12 * before.norm());
    EXPECT_THROW(model->soften_element(-1, 0.5), std::invalid_argument);
    EXPECT_THROW(model->soften_element(0, 0), std::invalid_argument);
  }
}

// K dx against the central difference of the forces. Exact (to the difference's error) for every
// model but corotational FEM, whose K omits the change of the rotations (see corotational_fem.h):
// there it is exact at a rigidly moved rest shape and off by about the strain elsewhere.
TEST_P(ModelLaws, StiffnessIsMinusTheForceDerivative) {
  const Points zero = Points::Zero(mesh_.num_nodes(), 3);
  const bool corotational = factory_.name.rfind("corotational", 0) == 0;
  struct Case {
    Points x;
    Real tolerance;
  };
  std::vector<Case> cases;
  cases.push_back({rigidly_moved(mesh_.rest, random_rotation(11), Vec3(0.1, 0, 0)), 1e-6});
  // The omitted terms scale with the stress: allow 10 times the largest Green strain of a tet.
  const Points small = deformed(12, 1e-3);
  cases.push_back({small, corotational ? 10 * largest_strain(small) : 1e-6});
  if (!corotational) cases.push_back({deformed(13, 0.02), 1e-6});
  for (const Case& c : cases) {
    model_->prepare_stiffness(c.x);
    for (unsigned seed : {121u, 122u}) {
      const Points dx = random_points(c.x.rows(), size_, seed);
      const Real h = 1e-7;
      const Points expected =
          -(forces(*model_, c.x + h * dx, zero) - forces(*model_, c.x - h * dx, zero)) / (2 * h);
      const Points k_dx = stiffness_times(dx);
      EXPECT_LT((k_dx - expected).norm(), c.tolerance * expected.norm()) << seed;
    }
  }
}

std::string case_name(const ::testing::TestParamInfo<std::tuple<int, int>>& info) {
  return all_models()[static_cast<std::size_t>(std::get<0>(info.param))].name + "_" +
         test_meshes()[static_cast<std::size_t>(std::get<1>(info.param))].name;
}

INSTANTIATE_TEST_SUITE_P(AllModelsAllMeshes, ModelLaws,
                         ::testing::Combine(::testing::Range(0, 7), ::testing::Range(0, 4)),
                         case_name);

}  // namespace
}  // namespace incise::sim::testing
