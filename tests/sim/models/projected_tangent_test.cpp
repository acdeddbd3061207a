// The positive semi-definite tangent projection (sim/models/projected_tangent.h) of the St
// Venant-Kirchhoff and Neo-Hookean kernels: it is the eigen-clamping of the exact 9 x 9 dP/dF,
// so it equals the exact tangent where that is positive semi-definite, the element stiffness is
// positive semi-definite in every state (inverted ones too), and the forces are not touched.
#include "sim/models/projected_tangent.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "sim/mesh/tet_mesh.h"
#include "sim/models/neo_hookean_fem.h"
#include "sim/models/stvk_fem.h"
#include "sim/models/tet_elements.h"

namespace incise::sim {
namespace {

using Mat9 = Eigen::Matrix<Real, 9, 9>;
using Mat12 = Eigen::Matrix<Real, 12, 12>;

const Lame kLame = lame_from_youngs(3000, 0.3);

Mat3 rotation_about(const Vec3& axis, Real angle) {
  return Eigen::AngleAxis<Real>(angle, axis.normalized()).toRotationMatrix();
}

// Deformation gradients: rest, stretched, compressed, sheared, flat, and inverted ones, each
// rotated on both sides so that the SVD frame is not the identity.
struct NamedState {
  std::string name;
  Mat3 deformation;
};
std::vector<NamedState> states() {
  const Mat3 r1 = rotation_about(Vec3(1, 2, 3), 0.7);
  const Mat3 r2 = rotation_about(Vec3(-2, 1, 0.5), 1.9);
  Mat3 shear = Mat3::Identity();
  shear(0, 1) = 0.8;
  shear(1, 2) = -0.4;
  return {
      {"rest", Mat3::Identity()},
      {"stretched", r1 * Vec3(1.2, 1.1, 1.15).asDiagonal() * r2},
      {"compressed 5%", r1 * Vec3(0.95, 0.95, 0.95).asDiagonal() * r2},
      {"uniaxial 30%", r1 * Vec3(0.7, 1.05, 1.05).asDiagonal() * r2},
      {"uniaxial 60%", r1 * Vec3(1.1, 0.4, 1.1).asDiagonal() * r2},
      {"sheared", r1 * shear},
      {"flat", r1 * Vec3(1, 0.9, 0).asDiagonal() * r2},
      {"inverted", r1 * Vec3(1.1, 0.9, -0.3).asDiagonal() * r2},
      {"inverted twice", r1 * Vec3(-0.8, -0.5, 1.2).asDiagonal() * r2},
      {"repeated singular values", r1 * Vec3(0.8, 0.8, 0.8).asDiagonal()},
  };
}

// The 9 x 9 matrix of dF -> dP (column-major vec of F), from the kernel's linearisation.
template <class Kernel>
Mat9 tangent_matrix(const Kernel& kernel, const Mat3& deformation) {
  const auto state = kernel.linearize(deformation, kLame);
  Mat9 h;
  for (int c = 0; c < 9; ++c) {
    Mat3 df = Mat3::Zero();
    df(c % 3, c / 3) = 1;
    h.col(c) = kernel.stress_differential(state, df, kLame).reshaped();
  }
  return h;
}

Mat9 clamped(const Mat9& h) {
  const Eigen::SelfAdjointEigenSolver<Mat9> eigen(h);
  return eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0).asDiagonal() *
         eigen.eigenvectors().transpose();
}

Real smallest_eigenvalue(const Mat9& h) {
  return Eigen::SelfAdjointEigenSolver<Mat9>(h, Eigen::EigenvaluesOnly).eigenvalues()(0);
}

template <class Kernel>
void expect_projection_is_the_clamped_hessian(Kernel exact) {
  Kernel projected = exact;
  projected.tangent = Tangent::projected;
  for (const auto& [name, f] : states()) {
    SCOPED_TRACE(name);
    const Mat9 h = tangent_matrix(exact, f);
    const Mat9 p = tangent_matrix(projected, f);
    const Real scale = h.norm();
    ASSERT_LT((h - h.transpose()).norm(), 1e-12 * scale);  // exact Hessian: symmetric
    EXPECT_LT((p - p.transpose()).norm(), 1e-12 * scale);
    // The block-wise projection is the nearest positive semi-definite matrix, as a brute-force
    // 9 x 9 eigen-clamping.
    EXPECT_LT((p - clamped(h)).norm(), 1e-10 * scale);
    EXPECT_GE(smallest_eigenvalue(p), -1e-12 * scale);
    if (smallest_eigenvalue(h) >= 0) {
      EXPECT_LT((p - h).norm(), 1e-12 * scale);
    }
  }
}

TEST(ProjectedTangent, NeoHookeanIsTheEigenClampedHessian) {
  expect_projection_is_the_clamped_hessian(NeoHookeanKernel{});
}

TEST(ProjectedTangent, StVenantKirchhoffIsTheEigenClampedHessian) {
  expect_projection_is_the_clamped_hessian(StVenantKirchhoffKernel{});
}

// Where the projection matters: the exact Hessians are indefinite at these states, so the test
// above compared something other than two copies of the exact tangent.
TEST(ProjectedTangent, ExactHessiansAreIndefiniteUnderCompressionAndInversion) {
  const NeoHookeanKernel neo_hookean;
  const StVenantKirchhoffKernel stvk;
  for (const auto& [name, f] : states()) {
    SCOPED_TRACE(name);
    const Real nh = smallest_eigenvalue(tangent_matrix(neo_hookean, f)) / kLame.mu;
    const Real sk = smallest_eigenvalue(tangent_matrix(stvk, f)) / kLame.mu;
    if (name == "stretched") {
      EXPECT_GT(nh, 0);
      EXPECT_GT(sk, 0);
    }
    if (name == "compressed 5%") {
      // The Neo-Hookean twist mode: mu + w s with w = lambda (J - 1) - mu / J, here -0.31 mu.
      const Real j = 0.95 * 0.95 * 0.95;
      const Real w = kLame.lambda * (j - 1) - kLame.mu / j;
      EXPECT_NEAR(nh, (kLame.mu + w * 0.95) / kLame.mu, 1e-10);
      EXPECT_LT(sk, 0);
    }
    if (name == "inverted" || name == "uniaxial 60%") {
      EXPECT_LT(nh, 0);
      EXPECT_LT(sk, 0);
    }
  }
}

TEST(ProjectedTangent, SignedSvdHasRotationsAndCarriesTheSignOfDetF) {
  for (const auto& [name, f] : states()) {
    SCOPED_TRACE(name);
    const SignedSvd svd = signed_svd(f);
    EXPECT_NEAR(svd.u.determinant(), 1, 1e-12);
    EXPECT_NEAR(svd.v.determinant(), 1, 1e-12);
    EXPECT_LT((svd.u * svd.s.asDiagonal() * svd.v.transpose() - f).norm(), 1e-12);
    EXPECT_NEAR(svd.s.prod(), f.determinant(), 1e-12);
    EXPECT_GE(svd.s(0), svd.s(1));
    EXPECT_GE(svd.s(1), std::abs(svd.s(2)));
  }
}

// The same over random F: general, nearly repeated singular values (near I, where the eigenvectors
// of F^T F are ill-determined), and nearly flat tets or tets collapsed onto a line.
TEST(ProjectedTangent, SignedSvdReconstructsRandomDeformations) {
  std::srand(7);
  for (int n = 0; n < 4000; ++n) {
    const Real scale[] = {1, 1e-9, 1e-3, 1};
    Mat3 f = Mat3::Identity() + scale[n % 4] * Mat3::Random();
    if (n % 4 == 2) f.col(2) = f.col(0) * 0.5 + f.col(1) * 0.3 + 1e-7 * Vec3::Random();  // flat
    if (n % 4 == 3 && n % 8 == 7) f.col(1) = 2 * f.col(0), f.col(2) = -f.col(0);         // a line
    const SignedSvd svd = signed_svd(f);
    ASSERT_NEAR(svd.u.determinant(), 1, 1e-12) << f;
    ASSERT_NEAR(svd.v.determinant(), 1, 1e-12) << f;
    ASSERT_LT((svd.u.transpose() * svd.u - Mat3::Identity()).norm(), 1e-12) << f;
    ASSERT_LT((svd.v.transpose() * svd.v - Mat3::Identity()).norm(), 1e-12) << f;
    ASSERT_LT((svd.u * svd.s.asDiagonal() * svd.v.transpose() - f).norm(), 1e-12 * f.norm()) << f;
    ASSERT_GE(svd.s(0), svd.s(1));
    ASSERT_GE(svd.s(1), std::abs(svd.s(2)) - 1e-12);
  }
}

// One right-corner tet as a model: the 12 x 12 K from add_stiffness_triplets at x.
TetMesh corner_tet() {
  Points rest(4, 3);
  rest << 0, 0, 0, 0.01, 0, 0, 0, 0.01, 0, 0, 0, 0.01;
  Tets tets(1, 4);
  tets << 0, 1, 2, 3;
  return make_tet_mesh(rest, tets);
}

Mat12 element_stiffness(Model& model, const Points& x) {
  model.prepare_stiffness(x);
  std::vector<Eigen::Triplet<Real>> triplets;
  model.add_stiffness_triplets(triplets);
  Mat12 k = Mat12::Zero();
  for (const auto& t : triplets)
    k(t.row(), t.col()) += t.value();
  return k;
}

Points deformed(const TetMesh& mesh, const Mat3& f) {
  return (mesh.rest * f.transpose()).eval();
}

using Factory = std::unique_ptr<Model> (*)(const TetMesh&, Tangent);
std::unique_ptr<Model> make_neo_hookean(const TetMesh& mesh, Tangent tangent) {
  return std::make_unique<NeoHookeanFem>(mesh, std::vector<ElementMaterial>{{3000, 0.3, 1000, 0}},
                                         0.1, tangent);
}
std::unique_ptr<Model> make_stvk(const TetMesh& mesh, Tangent tangent) {
  return std::make_unique<StVenantKirchhoffFem>(
      mesh, std::vector<ElementMaterial>{{3000, 0.3, 1000, 0}}, tangent);
}

TEST(ProjectedTangent, ElementStiffnessIsExactWherePositiveAndPositiveWhereInverted) {
  const TetMesh mesh = corner_tet();
  const Mat3 r = rotation_about(Vec3(1, -1, 2), 0.9);
  for (const Factory make : {Factory{make_neo_hookean}, Factory{make_stvk}}) {
    auto exact = make(mesh, Tangent::exact);
    auto projected = make(mesh, Tangent::projected);
    SCOPED_TRACE(std::string(exact->name()));
    // Stretched: every block of the exact Hessian is positive, so the two K are the same.
    const Points stretched = deformed(mesh, r * Vec3(1.2, 1.1, 1.15).asDiagonal());
    const Mat12 k_exact = element_stiffness(*exact, stretched);
    EXPECT_LT((element_stiffness(*projected, stretched) - k_exact).norm(), 1e-12 * k_exact.norm());
    // Inverted: the exact K has a negative eigenvalue, the projected one none.
    const Points inverted = deformed(mesh, r * Vec3(1.1, 0.9, -0.3).asDiagonal());
    const Mat12 k_inverted = element_stiffness(*exact, inverted);
    const Mat12 k_projected = element_stiffness(*projected, inverted);
    const Real scale = k_inverted.norm();
    EXPECT_LT(Eigen::SelfAdjointEigenSolver<Mat12>(k_inverted).eigenvalues()(0), -1e-3 * scale);
    EXPECT_GE(Eigen::SelfAdjointEigenSolver<Mat12>(k_projected).eigenvalues()(0), -1e-9 * scale);
    // The projection changes K only: forces and energy are those of the exact model.
    const Points v = Points::Zero(4, 3);
    Points f_exact = Points::Zero(4, 3), f_projected = Points::Zero(4, 3);
    exact->add_forces(inverted, v, f_exact);
    projected->add_forces(inverted, v, f_projected);
    EXPECT_EQ(f_exact, f_projected);
    EXPECT_EQ(exact->potential_energy(inverted), projected->potential_energy(inverted));
  }
}

}  // namespace
}  // namespace incise::sim
