#include "sim/tools/damage_strain.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace incise::sim::tools {

Real rest_edge_inverse(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Mat3& inverse) {
  Mat3 dm;
  dm << b - a, c - a, d - a;
  const Real volume = dm.determinant() / Real(6);
  if (volume > 0) inverse = dm.inverse();
  return volume;
}

Real largest_symmetric_eigenvalue(const Mat3& a) {
  const Real mean = (a(0, 0) + a(1, 1) + a(2, 2)) / 3;
  const Real d00 = a(0, 0) - mean, d11 = a(1, 1) - mean, d22 = a(2, 2) - mean;
  const Real d01 = a(0, 1), d02 = a(0, 2), d12 = a(1, 2);
  const Real p2 = (d00 * d00 + d11 * d11 + d22 * d22 + 2 * (d01 * d01 + d02 * d02 + d12 * d12)) / 6;
  if (std::isnan(p2)) return std::numeric_limits<Real>::quiet_NaN();
  if (!(p2 > 0)) return mean;  // a multiple of I
  // r = det(D / p) / 2, with D scaled before its cubes are formed: p^3 underflows for p below
  // about 1e-103 (and overflows above 1e102) where p itself is fine.
  const Real p = std::sqrt(p2);
  const Real inverse_p = 1 / p;
  const Real b00 = d00 * inverse_p, b11 = d11 * inverse_p, b22 = d22 * inverse_p;
  const Real b01 = d01 * inverse_p, b02 = d02 * inverse_p, b12 = d12 * inverse_p;
  const Real det =
      b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
  const Real r = std::clamp(det / 2, Real(-1), Real(1));
  // t = 1/2 + delta with 6 delta^2 + 4 delta^3 = 1 + r: delta is s - s^2/3 + ... in s =
  // sqrt((1 + r) / 6); the cubic below is a least-squares fit of it on [0, sqrt(1/3)] (within
  // 4e-5), and two Halley steps (cubic convergence) take it to round-off. Branch-free but for
  // the double root (s = 0), where t = 1/2 is exact and the step would be 0 / 0.
  const Real s = std::sqrt((1 + r) / 6);
  Real t =
      Real(0.5) + s * (1 + s * (Real(-0.3275065811320345) +
                                s * (Real(0.2214314501936702) - s * Real(0.09749196520142875))));
  for (int step = 0; step < 2; ++step) {
    const Real g = (4 * t * t - 3) * t - r;
    const Real slope = 12 * t * t - 3;
    const Real denominator = 2 * slope * slope - 24 * t * g;
    if (denominator > 0) t -= 2 * g * slope / denominator;
  }
  return mean + 2 * p * t;
}

Real max_principal_green_strain(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                const Mat3& rest_inverse) {
  Mat3 ds;
  ds << b - a, c - a, d - a;
  const Mat3 f = ds * rest_inverse;
  // C = F^T F: symmetric positive semi-definite.
  Mat3 c_right;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j)
      c_right(i, j) = c_right(j, i) = f.col(i).dot(f.col(j));
  if (!c_right.allFinite()) return std::numeric_limits<Real>::quiet_NaN();
  return (largest_symmetric_eigenvalue(c_right) - Real(1)) / Real(2);
}

}  // namespace incise::sim::tools
