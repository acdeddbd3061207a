#include "sim/remesh/time_step_floor.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace incise::sim::remesh {
namespace {

void check(const char* name, Real value, Real wave_speed, Real safety) {
  if (!(value > 0 && std::isfinite(value))) {
    throw std::invalid_argument(std::string(name) + " must be > 0 and finite, got " +
                                std::to_string(value));
  }
  if (!(wave_speed > 0 && std::isfinite(wave_speed))) {
    throw std::invalid_argument("wave speed must be > 0 and finite, got " +
                                std::to_string(wave_speed));
  }
  if (!(safety > 0 && safety <= 1)) {
    throw std::invalid_argument("time step safety factor must be in (0, 1], got " +
                                std::to_string(safety));
  }
}

}  // namespace

Real l_min_for_dt_min(Real dt_min, Real wave_speed, Real safety) {
  check("dt_min", dt_min, wave_speed, safety);
  return dt_min * wave_speed / safety;
}

Real dt_min_for_l_min(Real l_min, Real wave_speed, Real safety) {
  check("l_min", l_min, wave_speed, safety);
  return safety * l_min / wave_speed;
}

}  // namespace incise::sim::remesh
