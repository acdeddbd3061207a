#include "sim/tools/cutting_resistance.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/tools/tool_checks.h"

namespace incise::sim::tools {
namespace {

void check_non_negative(Real value, const char* what) {
  if (!(value >= 0 && std::isfinite(value))) {
    throw std::invalid_argument(std::string("cutting_resistance: ") + what +
                                " must be >= 0 and finite");
  }
}

}  // namespace

Vec3 cutting_resistance(Real toughness, Real depth, const Vec3& velocity, const Vec3& edge,
                        const CuttingResistanceSettings& settings) {
  check_non_negative(toughness, "the toughness");
  check_non_negative(depth, "the depth");
  checks::check_vector(velocity, "cutting_resistance", "the velocity");
  checks::check_vector(edge, "cutting_resistance", "the edge");
  if (!(std::abs(edge.norm() - 1) <= 1e-6)) {
    throw std::invalid_argument("cutting_resistance: the edge must be a unit vector");
  }
  if (!(settings.ramp_speed > 0 && std::isfinite(settings.ramp_speed))) {
    throw std::invalid_argument("cutting_resistance: ramp_speed must be > 0");
  }
  if (!(settings.max_force > 0 && std::isfinite(settings.max_force))) {
    throw std::invalid_argument("cutting_resistance: max_force must be > 0");
  }
  Vec3 across = velocity - velocity.dot(edge) * edge;
  // Twice: for a velocity nearly along the edge, the first pass leaves a part along it of the size
  // of its rounding, which would make F . v positive (if only by 1e-15 W).
  across -= across.dot(edge) * edge;
  const Real size = std::min(toughness * depth, settings.max_force);
  return -size * across / std::max(across.norm(), settings.ramp_speed);
}

}  // namespace incise::sim::tools
