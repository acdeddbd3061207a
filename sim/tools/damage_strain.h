#pragma once

// The strain kernel of the damage metrics: the largest principal Green strain of
// one linear tet. Green strain is used rather than a stress because it depends only on the
// motion, not on the model or its material: the same tissue threshold holds whichever model
// (mass-spring, corotational FEM, Neo-Hookean, condensed) moved the nodes.
//
//   F = Ds Dm^-1,  Ds = [x1 - x0, x2 - x0, x3 - x0],  Dm = the same over the rest positions
//   E = (F^T F - I) / 2,  e_max = the largest eigenvalue of E = (s_max^2 - 1) / 2
// with s_max the largest singular value of F (the largest stretch). A rigid motion gives
// e_max = 0; a uniaxial stretch by a factor l gives e_max = (l^2 - 1) / 2. Inverted tets need no
// special case: F^T F is defined for any F.

#include "sim/core/types.h"

namespace incise::sim::tools {

// Dm^-1 of the tet (a, b, c, d) at rest [1/m] into inverse, and its signed rest volume [m^3] as
// the result. Leaves inverse untouched and returns the (non-positive) volume when the tet is
// flat or inverted at rest; the caller rejects it.
Real rest_edge_inverse(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, Mat3& inverse);

// The largest eigenvalue of the symmetric 3x3 matrix a (its upper triangle is read), without
// trigonometry: with a = m I + D (m the mean of the diagonal), p^2 = tr(D^2) / 6 and r =
// det(D) / (2 p^3) in [-1, 1], it is m + 2 p t with t = cos(acos(r) / 3), the largest root of
// 4 t^3 - 3 t = r, from a fitted start and two Halley steps (no loop to converge, no trigonometry:
// about a third of Eigen's computeDirect). Near two equal largest eigenvalues it keeps half the
// digits, as every closed form from the invariants does. NaN or an infinity in, NaN out.
Real largest_symmetric_eigenvalue(const Mat3& a);

// The largest principal Green strain [-] of the tet whose current positions are (a, b, c, d),
// with rest_inverse = Dm^-1 from rest_edge_inverse. Allocates nothing. NaN in, NaN out.
Real max_principal_green_strain(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                                const Mat3& rest_inverse);

// max_principal_green_strain of tet slots 0 .. count - 1, four at a time in SIMD lanes (equal to
// the scalar function to round-off): slot s's nodes are tets[4 s .. 4 s + 3] into x (#nodes by 3,
// row-major), its Dm^-1 rest_inverse[s]. A slot with tracked[s] == 0 reads no node and gets 0.
// NaN where a tracked slot's positions are not finite. Allocates nothing.
void max_principal_green_strains(int count, const int* tets, const Real* x,
                                 const Mat3* rest_inverse, const char* tracked, Real* strain);

}  // namespace incise::sim::tools
