#include "sim/remesh/size_field.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace incise::sim::remesh {
namespace {

constexpr Real kInfinity = std::numeric_limits<Real>::infinity();

void check_size(Real size) {
  if (!(size > 0 && std::isfinite(size))) {
    throw std::invalid_argument("target size must be > 0 and finite, got " + std::to_string(size));
  }
}

}  // namespace

SizeField box_size_field(const Box3& box, Real size) {
  check_size(size);
  if (box.isEmpty()) throw std::invalid_argument("size field box is empty");
  return [box, size](const Vec3& p) { return box.contains(p) ? size : kInfinity; };
}

SizeField sphere_size_field(const Vec3& center, Real radius, Real size) {
  check_size(size);
  if (!(radius > 0)) throw std::invalid_argument("size field radius must be > 0");
  return [center, radius, size](const Vec3& p) {
    return (p - center).squaredNorm() <= radius * radius ? size : kInfinity;
  };
}

RegionHint region_hint_of(const Box3& box) {
  if (box.isEmpty()) throw std::invalid_argument("region hint box is empty");
  return {box.center(), (box.max() - box.min()).norm() / 2};
}

RegionHint region_hint_of(const Vec3& center, Real radius) {
  if (!(radius >= 0 && std::isfinite(radius))) {
    throw std::invalid_argument("region hint radius must be >= 0 and finite, got " +
                                std::to_string(radius));
  }
  return {center, radius};
}

bool intersects(const RegionHint& hint, const Vec3& center, Real radius) {
  const Real reach = hint.radius + radius;
  return (center - hint.center).squaredNorm() <= reach * reach;
}

bool in_region(const SizeField& field, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return std::isfinite(field((a + b + c + d) / 4));
}

}  // namespace incise::sim::remesh
