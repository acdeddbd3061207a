#include "sim/tools/damage_target.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "sim/collide/triangle_geometry.h"

namespace incise::sim::tools {
namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument("MarkedTarget: " + what);
}

Real distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 w = collide::closest_point_barycentric(p, a, b, c);
  return (p - (w[0] * a + w[1] * b + w[2] * c)).norm();
}

}  // namespace

void validate_target(const MarkedTarget& target) {
  if (target.empty()) return;
  if (target.line.rows() < 2)
    fail("the marked line needs at least 2 points, got " + std::to_string(target.line.rows()));
  if (!target.line.allFinite()) fail("the marked line holds a non-finite coordinate");
  for (int k = 0; k + 1 < target.line.rows(); ++k) {
    if (target.line.row(k) == target.line.row(k + 1))
      fail("segment " + std::to_string(k) + " of the marked line has zero length");
  }
  if (!target.depth_direction.allFinite() || target.depth_direction.norm() == 0)
    fail("depth_direction must be finite and non-zero");
  if (!std::isfinite(target.depth) || target.depth <= 0)
    fail("depth must be finite and > 0, got " + std::to_string(target.depth) + " m");
  if (!std::isfinite(target.half_width) || target.half_width <= 0)
    fail("half_width must be finite and > 0, got " + std::to_string(target.half_width) + " m");
}

Real distance_to_target(const MarkedTarget& target, const Vec3& point) {
  const Vec3 down = target.depth_direction.normalized() * target.depth;
  Real best = std::numeric_limits<Real>::infinity();
  for (int k = 0; k + 1 < target.line.rows(); ++k) {
    const Vec3 p = row3(target.line, k);
    const Vec3 q = row3(target.line, k + 1);
    best = std::min(best, distance_to_triangle(point, p, q, q + down));
    best = std::min(best, distance_to_triangle(point, p, q + down, p + down));
  }
  return best;
}

}  // namespace incise::sim::tools
