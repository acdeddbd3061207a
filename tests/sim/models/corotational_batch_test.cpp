// The vectorised corotational kernel (corotational_batch.h) against the per-tet one
// (CorotationalKernel, add_forces_scalar): equal to round-off over the test meshes, through
// rotations that grow step by step (the warm start), sudden half turns (the scalar fallback),
// inverted tets and damping; and the warm start converging without the fallback once warm. The
// laws (net force and torque zero, no force from a rigid motion, forces = -grad E) run on the
// vectorised kernel in model_laws_test.cpp, since CorotationalFem::add_forces is it.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "model_fixtures.h"
#include "sim/models/corotational_fem.h"

namespace incise::sim::testing {
namespace {

struct Case {
  RotationExtraction extraction;
  int mesh;
};

class CorotationalBatchTest : public ::testing::TestWithParam<Case> {
 protected:
  void SetUp() override {
    mesh_ = test_meshes()[static_cast<std::size_t>(GetParam().mesh)].mesh;
    model_ = std::make_unique<CorotationalFem>(mesh_, test_materials(), GetParam().extraction);
    size_ = mesh_size(mesh_);
  }

  // Batch and scalar forces at (x, v) agree to round-off relative to the force scale; the
  // element health agrees exactly.
  void expect_equal_forces(const Points& x, const Points& v, const std::string& what) {
    Points batch = Points::Zero(x.rows(), 3);
    Points scalar = Points::Zero(x.rows(), 3);
    model_->add_forces(x, v, batch);
    const ModelHealth batch_health = model_->health();
    model_->add_forces_scalar(x, v, scalar);
    const ModelHealth scalar_health = model_->health();
    const Real scale = scalar.norm() + 1e-9;
    EXPECT_LE((batch - scalar).norm(), 1e-9 * scale)
        << what << ": |batch - scalar| " << (batch - scalar).norm() << " of " << scale;
    EXPECT_EQ(batch_health.inverted_elements, scalar_health.inverted_elements) << what;
    EXPECT_EQ(batch_health.degenerate_elements, scalar_health.degenerate_elements) << what;
  }

  TetMesh mesh_;
  std::unique_ptr<CorotationalFem> model_;
  Real size_ = 0;
};

Mat3 about_axis(const Vec3& axis, Real angle) {
  return Eigen::AngleAxis<Real>(angle, axis.normalized()).toRotationMatrix();
}

TEST_P(CorotationalBatchTest, EqualsTheScalarKernelThroughAGrowingRotation) {
  // 60 steps to 3 rad about a skew axis with a deformation of up to 8 % riding along, and
  // velocities for the damping: each step starts from the last one's rotations.
  const Points noise = random_points(mesh_.num_nodes(), 0.08 * size_, 7);
  const Points v = random_points(mesh_.num_nodes(), 0.3, 8);
  for (int step = 0; step <= 60; ++step) {
    const Real angle = 0.05 * step;
    const Points x =
        rigidly_moved(mesh_.rest, about_axis(Vec3(1, 2, -0.5), angle), Vec3(0.01, 0, -0.02)) +
        std::sin(0.2 * step) * noise;
    expect_equal_forces(x, v, "step " + std::to_string(step));
  }
}

TEST_P(CorotationalBatchTest, EqualsTheScalarKernelAfterAHalfTurnAndWhenInverted) {
  const Points v = random_points(mesh_.num_nodes(), 0.3, 3);
  // A cold start at a half turn: no Newton ascent from the identity (a saddle), the fallback.
  expect_equal_forces(
      rigidly_moved(mesh_.rest, about_axis(Vec3(0, 0, 1), M_PI - 1e-3), Vec3::Zero()), v,
      "half turn");
  // Inverted: mirrored through a plane (every tet's det F < 0), then squashed flat to a plane.
  Points mirrored = mesh_.rest;
  mirrored.col(2) *= -0.7;
  expect_equal_forces(mirrored, v, "mirrored");
  Points flat = mesh_.rest;
  flat.col(1).setConstant(0.01);
  expect_equal_forces(flat, v, "flat");
  // Random positions: many tets inverted, some nearly flat.
  for (unsigned seed = 0; seed < 5; ++seed) {
    expect_equal_forces(random_points(mesh_.num_nodes(), size_, 40 + seed), v,
                        "random " + std::to_string(seed));
  }
}

// Polar only: QR's rotation is closed form, it has no warm start.
TEST(CorotationalBatch, AWarmStartConvergesWithoutTheScalarFallback) {
  for (const NamedMesh& named : test_meshes()) {
    const TetMesh& mesh = named.mesh;
    CorotationalFem model(mesh, test_materials(), RotationExtraction::polar);
    const Points v = Points::Zero(mesh.num_nodes(), 3);
    const Points noise = random_points(mesh.num_nodes(), 0.04 * mesh_size(mesh), 9);
    Points f = Points::Zero(mesh.num_nodes(), 3);
    for (int step = 0; step < 40; ++step) {
      const Points x =
          rigidly_moved(mesh.rest, about_axis(Vec3(-1, 1, 3), 0.02 * step), Vec3::Zero()) + noise;
      model.add_forces(x, v, f);
      EXPECT_EQ(model.batch().last_fallbacks(), 0) << named.name << " step " << step;
      // Warm: a step of 0.02 rad takes at most three iterations (quadratic convergence).
      if (step > 0) {
        EXPECT_LE(model.batch().last_newton_iterations(), 3) << named.name;
      }
    }
  }
}

TEST(CorotationalBatch, ARebuildOntoFewerSlotsLeavesNoStaleElementsInThePadding) {
  // The box's slots, then one tet: slots 1-3 of the four-tet block are padding that held box
  // elements (with box node numbers, beyond the single tet's nodes).
  const std::vector<NamedMesh> meshes = test_meshes();
  CorotationalFem model(meshes[0].mesh, test_materials(), RotationExtraction::polar);
  const TetMesh& single = meshes[1].mesh;
  ASSERT_EQ(single.num_tets(), 1);
  model.update_topology(single);
  const Points x = single.rest + random_points(single.num_nodes(), 0.01, 5);
  const Points v = Points::Zero(single.num_nodes(), 3);
  Points batch = Points::Zero(single.num_nodes(), 3);
  Points scalar = Points::Zero(single.num_nodes(), 3);
  model.add_forces(x, v, batch);
  model.add_forces_scalar(x, v, scalar);
  EXPECT_LE((batch - scalar).norm(), 1e-9 * scalar.norm());
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  return std::string(info.param.extraction == RotationExtraction::polar ? "polar" : "qr") + "_" +
         test_meshes()[static_cast<std::size_t>(info.param.mesh)].name;
}

INSTANTIATE_TEST_SUITE_P(
    Meshes, CorotationalBatchTest,
    ::testing::Values(Case{RotationExtraction::polar, 0}, Case{RotationExtraction::polar, 1},
                      Case{RotationExtraction::polar, 2}, Case{RotationExtraction::polar, 3},
                      Case{RotationExtraction::qr, 0}, Case{RotationExtraction::qr, 1},
                      Case{RotationExtraction::qr, 2}, Case{RotationExtraction::qr, 3}),
    case_name);

}  // namespace
}  // namespace incise::sim::testing
