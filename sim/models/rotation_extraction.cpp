#include "sim/models/rotation_extraction.h"

#include <Eigen/SVD>

namespace incise::sim {

namespace {
// F is dimensionless (I at rest): column lengths below this are round-off, not a direction.
constexpr Real kTinyLength = 1e-12;
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
