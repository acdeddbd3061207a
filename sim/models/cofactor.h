#pragma once

#include "sim/core/types.h"

namespace incise::sim {

// cof F = J F^-T = d(det F)/dF, columns f2 x f3, f3 x f1, f1 x f2; defined for every F, also
// singular ones, which is why the volume terms use it in place of F^-T.
inline Mat3 cofactor(const Mat3& f) {
  Mat3 c;
  c.col(0) = f.col(1).cross(f.col(2));
  c.col(1) = f.col(2).cross(f.col(0));
  c.col(2) = f.col(0).cross(f.col(1));
  return c;
}

// The change of cof F for a change df of F.
inline Mat3 cofactor_differential(const Mat3& f, const Mat3& df) {
  Mat3 dc;
  dc.col(0) = df.col(1).cross(f.col(2)) + f.col(1).cross(df.col(2));
  dc.col(1) = df.col(2).cross(f.col(0)) + f.col(2).cross(df.col(0));
  dc.col(2) = df.col(0).cross(f.col(1)) + f.col(0).cross(df.col(1));
  return dc;
}

}  // namespace incise::sim
