#pragma once
// The tangent dP = H[dF] of an isotropic hyperelastic material (H = d^2 Psi / dF^2, a symmetric
// operator on the 9 entries of F), written in the frame of F's signed SVD, where it splits into
// small blocks, and its positive semi-definite projection (negative eigenvalues clamped to 0).
//
// Why the frame: with F = U diag(s) V^T, U and V rotations, and D = U^T dF V, the quadratic form
// dF : H[dF] of an isotropic energy couples only (Teran et al., "Robust quasistatic finite
// elements and flesh simulation", SCA 2005, section 5; Smith et al., "Analytic eigensystems for
// isotropic distortion energies", TOG 2019):
//   - the diagonal D_00, D_11, D_22 among themselves (the 3 x 3 "stretch" block), and
//   - for each k the off-diagonal pair (D_ij, D_ji), (i, j) = (k + 1, k + 2) mod 3 (a 2 x 2
//     block: the twist and flip modes in the plane normal to axis k).
// dF -> D is orthogonal on the 9 entries (Frobenius), so clamping the eigenvalues of each block is
// exactly the eigen-clamping of the 9 x 9 H, i.e. the nearest positive semi-definite tangent in
// the Frobenius norm, and it leaves H unchanged wherever H is already positive semi-definite.
// The cost is one 3 x 3 SVD per element and, where the stretch block is not positive definite, a
// 3 x 3 symmetric eigensolve, against a 9 x 9 eigensolve. The element stiffness G^T H G (G the
// shape-function gradients) is then positive semi-definite too.
//
// Signed SVD: U and V are rotations (det +1), so s_2 is negative for an inverted element; the
// blocks are still those of H (isotropy, e.g. cof(U S V^T) = U cof(S) V^T, needs rotations, not
// reflections), and the projection makes a tangent that an implicit step can use where H itself
// has negative curvature.
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <cmath>

#include "sim/core/types.h"

namespace incise::sim {

// Whether a model's K is the exact Hessian of its energy or its positive semi-definite projection
// (above). Exact: the static Newton solve (quadratic convergence at the equilibrium; its line
// search copes with an indefinite K) and the tests that compare K with finite differences.
// Projected: implicit time stepping, whose one linearisation per step needs M + h D + h^2 K
// positive definite for CG to solve it.
enum class Tangent { exact, projected };

// F = u diag(s) v^T with u, v rotations and s_0 >= s_1 >= |s_2| (s_2 < 0 when det F < 0).
struct SignedSvd {
  Mat3 u = Mat3::Identity();
  Mat3 v = Mat3::Identity();
  Vec3 s = Vec3::Ones();
};

// Eigen's JacobiSVD: accurate also for repeated singular values (F = I at rest, or uniform
// compression), where the closed-form eigenvectors of F^T F (computeDirect, about 5 times faster)
// lose half the digits: measured 9e-10 reconstruction error at F = 0.8 R. It costs about 0.7 us,
// most of a projected linearisation (measured 0.7 to 0.8 us per tet against 0.04 for the exact).
inline SignedSvd signed_svd(const Mat3& f) {
  const Eigen::JacobiSVD<Mat3> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  SignedSvd out{svd.matrixU(), svd.matrixV(), svd.singularValues()};
  // Reflections move to the smallest singular value, where they cost the least.
  if (out.u.determinant() < 0) {
    out.u.col(2) *= -1;
    out.s(2) *= -1;
  }
  if (out.v.determinant() < 0) {
    out.v.col(2) *= -1;
    out.s(2) *= -1;
  }
  return out;
}

// H in the SVD frame: out(D) has diagonal stretch * diag(D) and, for pair k = (i, j),
// (out_ij, out_ji) = [[pair_a(k), pair_b(k)], [pair_b(k), pair_c(k)]] (D_ij, D_ji).
struct ProjectedTangent {
  Mat3 u = Mat3::Identity();
  Mat3 v = Mat3::Identity();
  Mat3 stretch = Mat3::Zero();  // symmetric
  Vec3 pair_a = Vec3::Zero();
  Vec3 pair_b = Vec3::Zero();
  Vec3 pair_c = Vec3::Zero();

  // dP = u out(u^T dF v) v^T.
  Mat3 apply(const Mat3& d_deformation) const {
    const Mat3 d = u.transpose() * d_deformation * v;
    Mat3 out;
    out.diagonal() = stretch * d.diagonal();
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;
      out(i, j) = pair_a(k) * d(i, j) + pair_b(k) * d(j, i);
      out(j, i) = pair_b(k) * d(i, j) + pair_c(k) * d(j, i);
    }
    return u * out * v.transpose();
  }

  // Clamps every block's negative eigenvalues to 0.
  void clamp_to_positive_semidefinite() {
    for (int k = 0; k < 3; ++k)
      clamp_pair(pair_a(k), pair_b(k), pair_c(k));
    // Positive leading minors (Sylvester) prove the usual, positive definite case without an
    // eigensolve.
    const Real minor2 = stretch(0, 0) * stretch(1, 1) - stretch(0, 1) * stretch(1, 0);
    if (stretch(0, 0) > 0 && minor2 > 0 && stretch.determinant() > 0) return;
    const Eigen::SelfAdjointEigenSolver<Mat3> eigen(stretch);
    if (eigen.eigenvalues().minCoeff() < 0) {
      stretch = eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0).asDiagonal() *
                eigen.eigenvectors().transpose();
    }
  }

 private:
  // [[a, b], [b, c]] has eigenvalues m -+ r (m = (a + c) / 2, r = sqrt(((a - c) / 2)^2 + b^2));
  // with one of each sign, (H - (m - r) I) / (2 r) projects onto the positive eigenvector, so the
  // clamped block is (m + r) times that projector.
  static void clamp_pair(Real& a, Real& b, Real& c) {
    const Real m = (a + c) / 2;
    const Real r = std::hypot((a - c) / 2, b);
    if (m - r >= 0) return;
    if (m + r <= 0) {
      a = b = c = 0;
      return;
    }
    const Real low = m - r, scale = (m + r) / (2 * r);
    a = scale * (a - low);
    b = scale * b;
    c = scale * (c - low);
  }
};

}  // namespace incise::sim
