// Hard cases: a tet pushed through its opposite face, a flattened and a collapsed tet, nu = 0.499,
// a node yanked far away. No NaN in any model; inverted and degenerate tets are counted; the models
// built to cope (linear, corotational, Neo-Hookean, mass-spring with its volume term) push an
// inverted tet back to its rest volume.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Sparse>

#include <cmath>

#include "model_fixtures.h"
#include "sim/mesh/box_mesher.h"

namespace incise::sim::testing {
namespace {

constexpr Real kEdge = 0.02;  // [m]

TetMesh corner_tet() {
  return test_meshes()[1].mesh;  // (0,0,0), (L,0,0), (0,L,0), (0,0,L)
}

// The models that promise a restoring force for an inverted tet: St Venant-Kirchhoff has mirrored
// rest states and the plain mass-spring system has no notion of orientation (their headers).
bool restores_inversion(const std::string& name) {
  return name != "stvk" && name != "mss";
}

// d V / d x_i for the tet (a, b, c, d), as #4 by 3.
Points volume_gradient(const Points& x) {
  const Vec3 a = row3(x, 0), b = row3(x, 1), c = row3(x, 2), d = row3(x, 3);
  Points g(4, 3);
  g.row(1) = ((c - a).cross(d - a) / 6).transpose();
  g.row(2) = ((d - a).cross(b - a) / 6).transpose();
  g.row(3) = ((b - a).cross(c - a) / 6).transpose();
  g.row(0) = -(g.row(1) + g.row(2) + g.row(3));
  return g;
}

Real signed_volume_of(const Points& x) {
  return signed_volume(row3(x, 0), row3(x, 1), row3(x, 2), row3(x, 3));
}

// The largest eigenvalue of the model's K at x [N/m].
Real largest_stiffness(Model& model, const Points& x) {
  model.prepare_stiffness(x);
  std::vector<Eigen::Triplet<Real>> triplets;
  model.add_stiffness_triplets(triplets);
  Eigen::SparseMatrix<Real> k(3 * x.rows(), 3 * x.rows());
  k.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::MatrixXd dense(k);
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues().maxCoeff();
}

TEST(HardCases, TetPushedThroughItsOppositeFace) {
  const TetMesh mesh = corner_tet();
  const Real rest_volume = signed_volume_of(mesh.rest);
  Points inverted = mesh.rest;
  inverted.row(3) = Eigen::RowVector3d(0.2, 0.2, -0.3) * kEdge;  // through the face (0, 1, 2)
  ASSERT_LT(signed_volume_of(inverted), 0);
  const Points zero = Points::Zero(4, 3);
  for (const ModelFactory& factory : all_models()) {
    SCOPED_TRACE(factory.name);
    auto model = factory.make(mesh, test_materials());
    const Points f = forces(*model, inverted, zero);
    ASSERT_TRUE(f.allFinite());
    EXPECT_TRUE(std::isfinite(model->potential_energy(inverted)));
    EXPECT_EQ(model->health().inverted_elements, 1);
    if (!restores_inversion(factory.name)) continue;
    // The force raises the signed volume...
    EXPECT_GT(flat(volume_gradient(inverted)).dot(flat(f)), 0);
    // ...and following it (a damped gradient flow, steps below the stability limit and at most 1%
    // of the edge) brings the tet back to its rest volume within 1%.
    const Real step = 0.5 / largest_stiffness(*model, mesh.rest);
    Points x = inverted;
    for (int iteration = 0; iteration < 20000; ++iteration) {
      Points move = step * forces(*model, x, zero);
      const Real length = move.norm();
      if (length > 0.01 * kEdge) move *= 0.01 * kEdge / length;
      x += move;
      if (length < 1e-10 * kEdge) break;
    }
    // Back to (nearly) zero energy with a positive volume. Linear FEM's zero-energy states include
    // the linearised rotations x = (I + W) X, W antisymmetric, which inflate the volume by
    // O(|W|^2) (Physically Realistic FEM's ghost forces), so only the rotation-invariant models
    // must come back to the rest volume.
    EXPECT_LT(model->potential_energy(x), 1e-6 * model->potential_energy(inverted));
    EXPECT_GT(signed_volume_of(x), 0);
    if (factory.rotation_invariant) {
      EXPECT_NEAR(signed_volume_of(x) / rest_volume, 1, 0.01);
    }
    forces(*model, x, zero);
    EXPECT_EQ(model->health().inverted_elements, 0);
  }
}

TEST(HardCases, FlattenedAndCollapsedTetsAreCountedWithoutNaN) {
  const TetMesh mesh = corner_tet();
  Points flat_tet = mesh.rest;
  flat_tet.row(3) = Eigen::RowVector3d(0.3, 0.3, 0) * kEdge;  // in the plane of the opposite face
  Points point = Points::Zero(4, 3);
  point.rowwise() += Eigen::RowVector3d(0.01, 0.01, 0.01);  // all four nodes at one point
  const Points v = random_points(4, 0.1, 3);
  for (const ModelFactory& factory : all_models()) {
    SCOPED_TRACE(factory.name);
    auto model = factory.make(mesh, test_materials());
    for (const Points& x : {flat_tet, point}) {
      ASSERT_TRUE(forces(*model, x, v).allFinite());
      EXPECT_GE(model->health().degenerate_elements, 1);
      EXPECT_EQ(model->health().inverted_elements, 1);  // det F = 0 counts as inverted
      EXPECT_TRUE(std::isfinite(model->potential_energy(x)));
      model->prepare_stiffness(x);
      Points out = Points::Zero(4, 3);
      model->add_stiffness_times(random_points(4, 1, 5), out);
      model->add_damping_times(random_points(4, 1, 6), out);
      EXPECT_TRUE(out.allFinite());
    }
  }
}

TEST(HardCases, NearlyIncompressibleMaterialStaysFiniteAndConsistent) {
  const TetMesh mesh = test_meshes()[0].mesh;
  const Real size = mesh_size(mesh);
  const Points x = rigidly_moved(mesh.rest, random_rotation(9), Vec3::Zero()) +
                   random_points(mesh.num_nodes(), 0.01 * size, 10);
  const Points zero = Points::Zero(mesh.num_nodes(), 3);
  for (const ModelFactory& factory : all_models()) {
    SCOPED_TRACE(factory.name);
    auto model = factory.make(mesh, test_materials(0.499));
    const Points f = forces(*model, x, zero);
    ASSERT_TRUE(f.allFinite());
    const Points dx = random_points(mesh.num_nodes(), size, 11);
    const Real h = 1e-7;
    const Real slope =
        (model->potential_energy(x + h * dx) - model->potential_energy(x - h * dx)) / (2 * h);
    EXPECT_NEAR(slope, -flat(f).dot(flat(dx)), 1e-6 * flat(f).norm() * flat(dx).norm());
  }
}

TEST(HardCases, NodeYankedFiveBodyLengthsAwayGivesFiniteForces) {
  const TetMesh mesh = test_meshes()[0].mesh;
  Points x = mesh.rest;
  x.row(0) += Eigen::RowVector3d(5, 0, 0) * mesh_size(mesh);
  for (const ModelFactory& factory : all_models()) {
    SCOPED_TRACE(factory.name);
    auto model = factory.make(mesh, test_materials());
    const Points f = forces(*model, x, Points::Zero(x.rows(), 3));
    ASSERT_TRUE(f.allFinite());
    // The yanked node is pulled back towards the body (against the yank).
    EXPECT_LT(f(0, 0), 0);
  }
}

}  // namespace
}  // namespace incise::sim::testing
