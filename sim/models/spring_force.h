#pragma once

#include "sim/core/types.h"

namespace incise::sim {

// The force one spring-damper pair exerts on its first node.
struct SpringForce {
  Vec3 on_i = Vec3::Zero();  // force on node i [N]; node j receives -on_i
  bool degenerate = false;   // the nodes coincide, so the spring has no direction: no force
};

// A linear spring with a dashpot along it between nodes i and j (Paloc 2006, eq. 3):
//   r = x_j - x_i,  u = r / |r|,  f_i = (k (|r| - l0) + c (v_j - v_i) . u) u,  f_j = -f_i.
// A stretched spring (|r| > l0) pulls i towards j; the dashpot resists the rate of stretch only,
// so rigid motions produce no force.
//   xi, xj  positions [m];  vi, vj  velocities [m/s]
//   k  stiffness [N/m];  c  damping [N s/m];  rest_length  l0 [m], > 0
inline SpringForce spring_force(const Vec3& xi, const Vec3& xj, const Vec3& vi, const Vec3& vj,
                                Real k, Real c, Real rest_length) {
  const Vec3 r = xj - xi;
  const Real length = r.norm();
  // Below this the direction is round-off; 1e-12 of the rest length is far beneath any
  // physical compression.
  if (!(length > Real(1e-12) * rest_length)) return {Vec3::Zero(), true};
  const Vec3 u = r / length;
  const Real tension = k * (length - rest_length) + c * (vj - vi).dot(u);
  return {tension * u, false};
}

}  // namespace incise::sim
