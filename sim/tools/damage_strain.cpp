#include "sim/tools/damage_strain.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/models/lanes.h"

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

namespace {

using namespace lanes;

// largest_symmetric_eigenvalue of four matrices, in lanes: the same steps, branches as selects.
// c00 .. c22 are the upper triangle.
INCISE_LANES Lanes largest_eigenvalues(Lanes c00, Lanes c01, Lanes c02, Lanes c11, Lanes c12,
                                       Lanes c22) {
  const Lanes mean = (c00 + c11 + c22) / 3;
  const Lanes d00 = c00 - mean, d11 = c11 - mean, d22 = c22 - mean;
  const Lanes p2 =
      (d00 * d00 + d11 * d11 + d22 * d22 + 2 * (c01 * c01 + c02 * c02 + c12 * c12)) / 6;
  const LaneMask spread = p2 > 0;  // else a multiple of I (or NaN, which the caller handles)
  const Lanes p = lanes_sqrt(select(spread, p2, splat(1)));
  const Lanes inverse_p = 1 / p;
  const Lanes b00 = d00 * inverse_p, b11 = d11 * inverse_p, b22 = d22 * inverse_p;
  const Lanes b01 = c01 * inverse_p, b02 = c02 * inverse_p, b12 = c12 * inverse_p;
  const Lanes det =
      b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
  Lanes r = det / 2;
  r = select(r < -1, splat(-1), select(r > 1, splat(1), r));
  const Lanes s = lanes_sqrt((1 + r) / 6);
  Lanes t =
      Real(0.5) + s * (1 + s * (Real(-0.3275065811320345) +
                                s * (Real(0.2214314501936702) - s * Real(0.09749196520142875))));
  for (int step = 0; step < 2; ++step) {
    const Lanes g = (4 * t * t - 3) * t - r;
    const Lanes slope = 12 * t * t - 3;
    const Lanes denominator = 2 * slope * slope - 24 * t * g;
    const LaneMask taken = denominator > 0;
    t -= select(taken, 2 * g * slope / select(taken, denominator, splat(1)), splat(0));
  }
  return select(spread, mean + 2 * p * t, mean);
}

// Entry (i, j) of the four lanes' Dm^-1.
INCISE_LANES Lanes rest_entry(const Mat3* const (&m)[4], int i, int j) {
  return Lanes{(*m[0])(i, j), (*m[1])(i, j), (*m[2])(i, j), (*m[3])(i, j)};
}

// What a lane without a tracked slot reads for Dm^-1.
const Mat3 kUnusedInverse = Mat3::Identity();

}  // namespace

[[gnu::target_clones("arch=x86-64-v3", "default")]] void max_principal_green_strains(
    int count, const int* tets, const Real* x, const Mat3* rest_inverse, const char* tracked,
    Real* strain) {
  for (int base = 0; base < count; base += kLaneWidth) {
    int node[4][4];
    const Mat3* inverse[4];
    LaneMask live;
    for (int l = 0; l < 4; ++l) {
      // A slot past the end or untracked reads node 0 and the identity, and is dropped below.
      const int s = base + l;
      const bool is_live = s < count && tracked[s] != 0;
      live[l] = is_live ? -1 : 0;
      for (int c = 0; c < 4; ++c)
        node[l][c] = is_live ? tets[4 * s + c] : 0;
      inverse[l] = is_live ? &rest_inverse[s] : &kUnusedInverse;
    }
    const int filled = std::min(kLaneWidth, count - base);
    if (!any(live)) {  // nothing tracked (the dead tail of a cut or refined mesh): read nothing
      for (int l = 0; l < filled; ++l)
        strain[base + l] = 0;
      continue;
    }
    Lanes ds[3][4];  // [k][i]: Ds(i, k)
    edge_lanes(x, node, ds);
    Lanes f[3][3];  // F = Ds Dm^-1
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        f[i][j] = ds[0][i] * rest_entry(inverse, 0, j) + ds[1][i] * rest_entry(inverse, 1, j) +
                  ds[2][i] * rest_entry(inverse, 2, j);
    // C = F^T F, its upper triangle.
    const auto column_dot = [&](int a, int b) {
      return f[0][a] * f[0][b] + f[1][a] * f[1][b] + f[2][a] * f[2][b];
    };
    const Lanes c00 = column_dot(0, 0), c01 = column_dot(0, 1), c02 = column_dot(0, 2);
    const Lanes c11 = column_dot(1, 1), c12 = column_dot(1, 2), c22 = column_dot(2, 2);
    // Finite entries: x * 0 is 0 exactly for finite x, NaN for infinities and NaN.
    const LaneMask finite = (c00 * 0 == 0) & (c01 * 0 == 0) & (c02 * 0 == 0) & (c11 * 0 == 0) &
                            (c12 * 0 == 0) & (c22 * 0 == 0);
    const Lanes e = (largest_eigenvalues(c00, c01, c02, c11, c12, c22) - 1) / 2;
    const Lanes result =
        select(live, select(finite, e, splat(std::numeric_limits<Real>::quiet_NaN())), splat(0));
    for (int l = 0; l < filled; ++l)
      strain[base + l] = result[l];
  }
}

}  // namespace incise::sim::tools
