#include "sim/tools/damage_strain.h"

#include <limits>

#include <Eigen/Eigenvalues>

namespace incise::sim::tools {

Real rest_edge_inverse(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Mat3& inverse) {
  Mat3 dm;
  dm << b - a, c - a, d - a;
  const Real volume = dm.determinant() / Real(6);
  if (volume > 0) inverse = dm.inverse();
  return volume;
}

Real max_principal_green_strain(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                const Mat3& rest_inverse) {
  Mat3 ds;
  ds << b - a, c - a, d - a;
  const Mat3 f = ds * rest_inverse;
  const Mat3 c_right = f.transpose() * f;
  if (!c_right.allFinite()) return std::numeric_limits<Real>::quiet_NaN();
  // The closed-form 3x3 solver: no iteration, no allocation; its eigenvalues come sorted
  // ascending. C = F^T F is symmetric positive semi-definite, well inside its accurate range.
  Eigen::SelfAdjointEigenSolver<Mat3> eigen;
  eigen.computeDirect(c_right, Eigen::EigenvaluesOnly);
  return (eigen.eigenvalues()(2) - Real(1)) / Real(2);
}

}  // namespace incise::sim::tools
