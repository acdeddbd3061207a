#include "sim/models/rotation_extraction.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

namespace incise::sim {

namespace {
// F is dimensionless (I at rest): column lengths below this are round-off, not a direction.
constexpr Real kTinyLength = 1e-12;
// sigma_2^2 / sigma_1^2 below this: F is flat to a line, the fast polar path has no second column.
constexpr Real kTinyStretch = 1e-12;
// |F^T F - I|^2 below this: F is a rotation stretched by at most ~5%, Newton-Schulz's ground.
constexpr Real kNearRotation = 1e-2;
}  // namespace

QrRotation qr_rotation(const Mat3& deformation) {
  const Vec3 f1 = deformation.col(0);
  const Vec3 f2 = deformation.col(1);
  const Real length1 = f1.norm();
  QrRotation result;
  if (length1 > kTinyLength) {
    const Vec3 r1 = f1 / length1;
    const Vec3 in_plane = f2 - r1.dot(f2) * r1;
    const Real length2 = in_plane.norm();
    if (length2 > kTinyLength * (1 + f2.norm())) {
      const Vec3 r2 = in_plane / length2;
      result.rotation.col(0) = r1;
      result.rotation.col(1) = r2;
      result.rotation.col(2) = r1.cross(r2);
      result.upper = result.rotation.transpose() * deformation;
      // Exactly upper triangular: the entries below the diagonal are round-off.
      result.upper(1, 0) = result.upper(2, 0) = result.upper(2, 1) = 0;
      return result;
    }
  }
  result.rotation = polar_rotation(deformation);
  result.upper = result.rotation.transpose() * deformation;
  result.degenerate = true;
  return result;
}

Mat3 polar_rotation(const Mat3& deformation) {
  // V and Sigma^2 from the closed-form eigen solver of F^T F (a few hundred flops; Jacobi SVD
  // iterates, and on a deformed organ it was 80% of a step). The two largest singular values'
  // columns of U are F v / sigma, made orthonormal; the last is their cross product, so U and V
  // are rotations and an inverted F keeps a negative last singular value. When the second
  // singular value is tiny (a tet flat to a line or a point) those columns mean nothing: Jacobi.
  const Mat3 c = deformation.transpose() * deformation;
  if (deformation.determinant() > 0 && (c - Mat3::Identity()).squaredNorm() < kNearRotation) {
    // Within a few percent of a rotation (a tissue at rest or nearly): Newton-Schulz,
    // R <- R (3 I - R^T R) / 2, converges quadratically from F to its polar rotation.
    Mat3 r = deformation;
    for (int i = 0; i < 6; ++i) {
      const Mat3 e = Mat3::Identity() - r.transpose() * r;
      if (e.squaredNorm() < 1e-30) break;
      r = r * (Mat3::Identity() + Real(0.5) * e);
    }
    return r;
  }
  Eigen::SelfAdjointEigenSolver<Mat3> eigen;
  eigen.computeDirect(c);
  const Vec3 lambda = eigen.eigenvalues();  // ascending
  if (lambda.allFinite() && lambda(1) > kTinyStretch * lambda(2) && lambda(2) > 0) {
    Mat3 v;
    v.col(0) = eigen.eigenvectors().col(2);
    v.col(1) = eigen.eigenvectors().col(1);
    v.col(2) = v.col(0).cross(v.col(1));
    const Vec3 first = deformation * v.col(0);
    Vec3 second = deformation * v.col(1);
    const Real sigma = first.norm();
    Mat3 u;
    u.col(0) = first / sigma;
    second -= u.col(0).dot(second) * u.col(0);
    if (second.norm() > 1e-6 * sigma) {
      u.col(1) = second.normalized();
      u.col(2) = u.col(0).cross(u.col(1));
      if (u.allFinite()) return u * v.transpose();
    }
  }
  return polar_rotation_svd(deformation);
}

Mat3 polar_rotation_svd(const Mat3& deformation) {
  const Eigen::JacobiSVD<Mat3> svd(deformation, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 u = svd.matrixU();
  Mat3 v = svd.matrixV();
  // Flipping the last column of U or V (the one of the smallest singular value) negates that
  // singular value instead, which keeps F = U Sigma V^T.
  if (u.determinant() < 0) u.col(2) *= -1;
  if (v.determinant() < 0) v.col(2) *= -1;
  return u * v.transpose();
}

}  // namespace incise::sim
