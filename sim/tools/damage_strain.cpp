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

namespace {

using namespace lanes;

// One matrix or four in lanes alike, for the steps below.
inline Real pick(bool m, Real a, Real b) {
  return m ? a : b;
}
INCISE_LANES Lanes pick(LaneMask m, Lanes a, Lanes b) {
  return select(m, a, b);
}
inline Real root(Real a) {
  return std::sqrt(a);
}
INCISE_LANES Lanes root(Lanes a) {
  return lanes_sqrt(a);
}

// largest_symmetric_eigenvalue's steps on the upper triangle (c00, c01, c02, c11, c12, c22), for
// one matrix (T = Real) or four (T = Lanes; max_principal_green_strains); its branches are picks.
// A NaN in gives the mean (the callers check first).
template <class T>
INCISE_LANES T largest_eigenvalue(T c00, T c01, T c02, T c11, T c12, T c22) {
  const T zero{};
  const T one = zero + 1;
  const T mean = (c00 + c11 + c22) / 3;
  const T d00 = c00 - mean, d11 = c11 - mean, d22 = c22 - mean;
  const T p2 = (d00 * d00 + d11 * d11 + d22 * d22 + 2 * (c01 * c01 + c02 * c02 + c12 * c12)) / 6;
  const auto spread = p2 > 0;  // else a multiple of I: the mean
  // r = det(D / p) / 2, with D scaled before its cubes are formed: p^3 underflows for p below
  // about 1e-103 (and overflows above 1e102) where p itself is fine.
  const T p = root(pick(spread, p2, one));
  const T inverse_p = 1 / p;
  const T b00 = d00 * inverse_p, b11 = d11 * inverse_p, b22 = d22 * inverse_p;
  const T b01 = c01 * inverse_p, b02 = c02 * inverse_p, b12 = c12 * inverse_p;
  const T det =
      b00 * (b11 * b22 - b12 * b12) - b01 * (b01 * b22 - b12 * b02) + b02 * (b01 * b12 - b11 * b02);
  T r = det / 2;
  r = pick(r < -1, zero - 1, pick(r > 1, one, r));
  // t = 1/2 + delta with 6 delta^2 + 4 delta^3 = 1 + r: delta is s - s^2/3 + ... in s =
  // sqrt((1 + r) / 6); the cubic below is a least-squares fit of it on [0, sqrt(1/3)] (within
  // 4e-5), and two Halley steps (cubic convergence) take it to round-off. Branch-free but for
  // the double root (s = 0), where t = 1/2 is exact and the step would be 0 / 0: no step there.
  const T s = root((1 + r) / 6);
  T t = Real(0.5) + s * (1 + s * (Real(-0.3275065811320345) +
                                  s * (Real(0.2214314501936702) - s * Real(0.09749196520142875))));
  for (int step = 0; step < 2; ++step) {
    const T g = (4 * t * t - 3) * t - r;
    const T slope = 12 * t * t - 3;
    const T denominator = 2 * slope * slope - 24 * t * g;
    const auto taken = denominator > 0;
    t -= pick(taken, 2 * g * slope / pick(taken, denominator, one), zero);
  }
  return pick(spread, mean + 2 * p * t, mean);
}

}  // namespace

Real largest_symmetric_eigenvalue(const Mat3& a) {
  const Real upper[6] = {a(0, 0), a(0, 1), a(0, 2), a(1, 1), a(1, 2), a(2, 2)};
  for (const Real entry : upper) {
    if (!std::isfinite(entry)) return std::numeric_limits<Real>::quiet_NaN();
  }
  return largest_eigenvalue(upper[0], upper[1], upper[2], upper[3], upper[4], upper[5]);
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
    const Lanes e = (largest_eigenvalue(c00, c01, c02, c11, c12, c22) - 1) / 2;
    const Lanes result =
        select(live, select(finite, e, splat(std::numeric_limits<Real>::quiet_NaN())), splat(0));
    for (int l = 0; l < filled; ++l)
      strain[base + l] = result[l];
  }
}

}  // namespace incise::sim::tools
