#include "sim/collide/tool_shapes.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace incise::sim::collide {

JawPair make_jaw_pair(const Vec3& pivot, const Vec3& direction, const Vec3& opening_normal,
                      Real opening_angle, Real jaw_length, Real jaw_radius) {
  const Real axis_length = direction.norm();
  if (!(axis_length > 0) || !std::isfinite(axis_length)) {
    throw std::invalid_argument("make_jaw_pair: direction must be a finite non-zero vector");
  }
  const Vec3 d = direction / axis_length;
  const Vec3 side = opening_normal - opening_normal.dot(d) * d;
  const Real side_length = side.norm();
  if (!(side_length > 1e-12 * opening_normal.norm()) || !std::isfinite(side_length)) {
    throw std::invalid_argument(
        "make_jaw_pair: opening_normal must be finite and not parallel to direction");
  }
  if (!(opening_angle >= 0 && opening_angle < std::numbers::pi)) {
    throw std::invalid_argument("make_jaw_pair: opening_angle must be in [0, pi), got " +
                                std::to_string(opening_angle));
  }
  if (!(jaw_length > 0) || !(jaw_radius > 0)) {
    throw std::invalid_argument("make_jaw_pair: jaw_length and jaw_radius must be > 0, got " +
                                std::to_string(jaw_length) + " and " + std::to_string(jaw_radius));
  }
  const Vec3 u = side / side_length;
  const Real half = opening_angle / 2;
  JawPair pair;
  for (int k = 0; k < 2; ++k) {
    const Real sign = k == 0 ? 1 : -1;
    pair.jaws[k] = Capsule{
        pivot, pivot + jaw_length * (std::cos(half) * d + sign * std::sin(half) * u), jaw_radius};
  }
  return pair;
}

}  // namespace incise::sim::collide
