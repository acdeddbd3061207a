// Closed forms of Joshi et al. (uniaxial compression with free lateral faces): the Neo-Hookean
// model against its equations 4 and 15, the linear model against equation 9.
#include <gtest/gtest.h>

#include <cmath>

#include "model_fixtures.h"
#include "sim/mesh/box_mesher.h"
#include "sim/models/linear_fem.h"
#include "sim/models/neo_hookean_fem.h"

#include "tests/sim/closed_forms.h"

namespace incise::sim::testing {
namespace {

// Joshi et al.'s brain parameters (lambda = 9310.3, mu = 1034.5), as E and nu by its eqs. 1 and 2.
constexpr Real kLambda = 9310.3;
constexpr Real kMu = 1034.5;
ElementMaterial brain() {
  return {kMu * (3 * kLambda + 2 * kMu) / (kLambda + kMu), kLambda / (2 * kLambda + 2 * kMu), 1040,
          0};
}

// Joshi et al. eq. 4, S = mu (I - C^-1) + lambda J (J - 1) C^-1, written independently of the
// kernel.
Mat3 equation_4(const Mat3& f) {
  const Mat3 c_inv = (f.transpose() * f).inverse();
  const Real j = f.determinant();
  return kMu * (Mat3::Identity() - c_inv) + kLambda * j * (j - 1) * c_inv;
}

TEST(NeoHookeanClosedForm, FirstPiolaIsFTimesEquation4) {
  const Lame lame{kMu, kLambda};
  const NeoHookeanKernel kernel;
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    const Points noise = random_points(3, 0.2, seed);
    Mat3 f = random_rotation(seed) * (Mat3::Identity() + Mat3(noise));
    ASSERT_GT(f.determinant(), kernel.extension_below);
    const Mat3 expected = f * equation_4(f);
    EXPECT_LT((kernel.stress(f, lame).first_piola - expected).norm(), 1e-10 * expected.norm());
  }
}

// A box compressed homogeneously along x by lambda_1 with lateral stretch lambda_2: a homogeneous
// F is exact on linear tets, so the closed form must hold node by node. Every node off the two
// loaded faces (interior, lateral faces) feels no force: the lateral faces are traction-free.
// The loaded face at x = d carries -P11 times its rest area.
void expect_uniaxial_state(Model& model, const TetMesh& mesh, Real l1, Real l2, Real p11) {
  const Real d0 = mesh.rest.col(0).maxCoeff();
  const Real area = mesh.rest.col(1).maxCoeff() * mesh.rest.col(2).maxCoeff();
  const Mat3 f = Vec3(l1, l2, l2).asDiagonal();
  const Points x = rigidly_moved(mesh.rest, f, Vec3::Zero());
  const Points force = forces(model, x, Points::Zero(x.rows(), 3));
  const Real face_force = std::abs(p11) * area;
  Vec3 far_face = Vec3::Zero();
  Vec3 near_face = Vec3::Zero();
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Real xi = mesh.rest(i, 0);
    if (xi == 0) {
      near_face += row3(force, i);
    } else if (xi == d0) {
      far_face += row3(force, i);
    } else {
      EXPECT_LT(force.row(i).norm(), 1e-9 * face_force) << "node " << i;
    }
  }
  EXPECT_NEAR(far_face.x(), -p11 * area, 1e-9 * face_force);
  EXPECT_NEAR(near_face.x(), p11 * area, 1e-9 * face_force);
  EXPECT_LT(far_face.tail<2>().norm(), 1e-9 * face_force);
}

TEST(NeoHookeanClosedForm, UniaxialCompressionMatchesEquation15) {
  const TetMesh mesh = make_box_mesh(Vec3(0.1, 0.08, 0.06), Vec3i(3, 3, 2));
  NeoHookeanFem model(mesh, {brain()});
  for (Real compression : {0.01, 0.05, 0.10, 0.20}) {
    const Real l1 = 1 - compression;
    const Real l2 = sim::test::neo_hookean_lateral_stretch(l1, kMu, kLambda);
    EXPECT_GT(l2, 1);  // compressible: the block bulges
    const Mat3 f = Vec3(l1, l2, l2).asDiagonal();
    const Mat3 s = equation_4(f);
    EXPECT_LT(std::abs(s(1, 1)), 1e-9 * std::abs(s(0, 0)));  // eq. 14 holds at eq. 15's lambda_2
    SCOPED_TRACE(compression);
    expect_uniaxial_state(model, mesh, l1, l2, l1 * s(0, 0));
  }
}

TEST(LinearClosedForm, UniaxialCompressionMatchesEquation9) {
  const TetMesh mesh = make_box_mesh(Vec3(0.1, 0.08, 0.06), Vec3i(3, 3, 2));
  const ElementMaterial material = brain();
  LinearFem model(mesh, {material});
  for (Real compression : {0.01, 0.05, 0.10, 0.20}) {
    const Real strain = -compression;
    // Eq. 9: Delta l / l0 = -nu Delta d / d0; the stress is then E strain along x only.
    const Real l2 = 1 - material.poisson_ratio * strain;
    SCOPED_TRACE(compression);
    expect_uniaxial_state(model, mesh, 1 + strain, l2, material.youngs_modulus * strain);
  }
}

}  // namespace
}  // namespace incise::sim::testing
