#include "sim/solve/stable_time_step.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace incise::sim {
namespace {

void check_safety(Real safety) {
  if (!(safety > 0 && safety <= 1)) {
    throw std::invalid_argument("time step safety factor must be in (0, 1], got " +
                                std::to_string(safety));
  }
}

}  // namespace

ElementLengths element_lengths(const Points& points, const Tets& tets) {
  if (tets.rows() == 0) throw std::invalid_argument("element lengths of an empty tet set");
  ElementLengths lengths{std::numeric_limits<Real>::infinity(),
                         std::numeric_limits<Real>::infinity()};
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    Vec3 p[4];
    for (int k = 0; k < 4; ++k)
      p[k] = row3(points, tets(t, k));
    Real longest_edge = 0;
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) {
        const Real edge = (p[b] - p[a]).norm();
        lengths.min_edge = std::min(lengths.min_edge, edge);
        longest_edge = std::max(longest_edge, edge);
      }
    }
    const Real volume = std::abs(signed_volume(p[0], p[1], p[2], p[3]));
    // Relative to the element's own size, so that the test does not depend on the length unit.
    if (!(volume > 1e-12 * longest_edge * longest_edge * longest_edge)) {
      throw std::invalid_argument("tet " + std::to_string(t) + " has (near) zero volume " +
                                  std::to_string(volume) + " m^3; no stable time step");
    }
    // altitude over face k (opposite vertex k) = 3 V / area(face k)
    for (int k = 0; k < 4; ++k) {
      const Vec3& a = p[(k + 1) % 4];
      const Vec3& b = p[(k + 2) % 4];
      const Vec3& c = p[(k + 3) % 4];
      const Real area = Real(0.5) * (b - a).cross(c - a).norm();
      lengths.min_altitude = std::min(lengths.min_altitude, 3 * volume / area);
    }
  }
  return lengths;
}

Real p_wave_speed(Real youngs_modulus, Real poisson_ratio, Real density) {
  if (!(youngs_modulus > 0) || !(poisson_ratio > -1 && poisson_ratio < 0.5) || !(density > 0)) {
    throw std::invalid_argument("wave speed needs E > 0, -1 < nu < 0.5, density > 0; got E = " +
                                std::to_string(youngs_modulus) +
                                ", nu = " + std::to_string(poisson_ratio) +
                                ", density = " + std::to_string(density));
  }
  const Real nu = poisson_ratio;
  return std::sqrt(youngs_modulus * (1 - nu) / (density * (1 + nu) * (1 - 2 * nu)));
}

Real stable_time_step(const TetMesh& mesh, Real youngs_modulus, Real poisson_ratio, Real density,
                      Real safety) {
  check_safety(safety);
  const Real c = p_wave_speed(youngs_modulus, poisson_ratio, density);
  return safety * element_lengths(mesh.x, mesh.tets).min_altitude / c;
}

Real time_step_floor(Real l_floor, Real youngs_modulus, Real poisson_ratio, Real density,
                     Real safety) {
  check_safety(safety);
  if (!(l_floor > 0)) throw std::invalid_argument("length floor must be > 0");
  return safety * l_floor / p_wave_speed(youngs_modulus, poisson_ratio, density);
}

Real length_floor(Real dt_min, Real youngs_modulus, Real poisson_ratio, Real density, Real safety) {
  check_safety(safety);
  if (!(dt_min > 0)) throw std::invalid_argument("dt_min must be > 0");
  return dt_min * p_wave_speed(youngs_modulus, poisson_ratio, density) / safety;
}

}  // namespace incise::sim
