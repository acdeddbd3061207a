#pragma once
// Four doubles as one value, and the moves between lanes and points that the vectorised per-element
// kernels share (corotational_batch.cpp, mass_spring_model.cpp, sim/tools/damage_strain.cpp). For
// kernels' .cpp files only: the helpers are always inlined into their callers, which are compiled
// once per instruction set (GCC's target_clones), so each copy uses that set's registers.
#include <cstdint>
#include <cstring>

#include "sim/core/types.h"

// Four doubles as one value: GCC's vector extension, so that the arithmetic below reads like the
// scalar kernel's while compiling to one SIMD instruction per operation. Passing such values
// between functions changes the ABI without AVX; every helper here is always inlined into the
// kernels, which are the only functions that take them, so the note does not apply.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace incise::sim::lanes {

using Lanes = Real __attribute__((vector_size(4 * sizeof(Real))));
using LaneMask = std::int64_t __attribute__((vector_size(4 * sizeof(Real))));
inline constexpr int kLaneWidth = 4;

#define INCISE_LANES [[gnu::always_inline]] inline

INCISE_LANES Lanes load(const Real* p) {
  Lanes v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
INCISE_LANES void store(Real* p, Lanes v) {
  std::memcpy(p, &v, sizeof v);
}
INCISE_LANES Lanes splat(Real a) {
  return Lanes{a, a, a, a};
}
INCISE_LANES Lanes lanes_sqrt(Lanes a) {
  Lanes r;
  for (int l = 0; l < 4; ++l)
    r[l] = __builtin_sqrt(a[l]);
  return r;
}
INCISE_LANES Lanes select(LaneMask m, Lanes a, Lanes b) {
  return m ? a : b;
}
INCISE_LANES bool all(LaneMask m) {
  return (m[0] & m[1] & m[2] & m[3]) != 0;
}
INCISE_LANES bool any(LaneMask m) {
  return (m[0] | m[1] | m[2] | m[3]) != 0;
}

using Pair = Real __attribute__((vector_size(2 * sizeof(Real))));

// (x, y, z, 0) of the point at p: two loads, never past p[2].
INCISE_LANES Lanes point_at(const Real* p) {
  Pair xy;
  std::memcpy(&xy, p, sizeof xy);
  const Pair z0 = {p[2], 0};
  return __builtin_shufflevector(xy, z0, 0, 1, 2, 3);
}

// p[0..2] += the first three entries of a.
INCISE_LANES void add_point(Real* p, Lanes a) {
  Pair xy;
  std::memcpy(&xy, p, sizeof xy);
  xy += __builtin_shufflevector(a, a, 0, 1);
  std::memcpy(p, &xy, sizeof xy);
  p[2] += a[2];
}

// The 4x4 transpose: row i of r holds entry i of a, b, c and d (rows nobody reads cost nothing,
// the function being inlined).
INCISE_LANES void transpose(Lanes a, Lanes b, Lanes c, Lanes d, Lanes (&r)[4]) {
  const Lanes ab02 = __builtin_shufflevector(a, b, 0, 4, 2, 6);
  const Lanes ab13 = __builtin_shufflevector(a, b, 1, 5, 3, 7);
  const Lanes cd02 = __builtin_shufflevector(c, d, 0, 4, 2, 6);
  const Lanes cd13 = __builtin_shufflevector(c, d, 1, 5, 3, 7);
  r[0] = __builtin_shufflevector(ab02, cd02, 0, 1, 4, 5);
  r[1] = __builtin_shufflevector(ab13, cd13, 0, 1, 4, 5);
  r[2] = __builtin_shufflevector(ab02, cd02, 2, 3, 6, 7);
  r[3] = __builtin_shufflevector(ab13, cd13, 2, 3, 6, 7);
}

// The edge matrices Ds = [x1 - x0, x2 - x0, x3 - x0] of four tets: node[l] holds lane l's four
// node indices into x (#nodes by 3, row-major), and ds[k][i] is Ds(i, k) of the four tets (row 3
// unused). Each lane's edges are formed as (x, y, z, 0) points and transposed into lanes.
INCISE_LANES void edge_lanes(const Real* x, const int (&node)[4][4], Lanes (&ds)[3][4]) {
  Lanes edge[3][4];  // [k][lane]
  for (int l = 0; l < 4; ++l) {
    const Lanes x0 = point_at(x + 3 * node[l][0]);
    for (int k = 0; k < 3; ++k)
      edge[k][l] = point_at(x + 3 * node[l][k + 1]) - x0;
  }
  for (int k = 0; k < 3; ++k)
    transpose(edge[k][0], edge[k][1], edge[k][2], edge[k][3], ds[k]);
}

// How many lanes of m are set.
INCISE_LANES int count(LaneMask m) {
  return static_cast<int>(-(m[0] + m[1] + m[2] + m[3]));
}

}  // namespace incise::sim::lanes
