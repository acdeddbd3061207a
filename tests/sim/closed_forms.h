#pragma once
// Closed forms the sim tests and benchmarks check against, written once.
#include <cmath>

#include "sim/core/types.h"

namespace incise::sim::test {

// Lame parameters from Young's modulus and Poisson's ratio (Joshi et al., eqs. 1-2 inverted).
struct LameParameters {
  Real mu = 0;
  Real lambda = 0;
};
inline LameParameters lame_parameters(Real youngs_modulus, Real poisson_ratio) {
  return {youngs_modulus / (2 * (1 + poisson_ratio)),
          youngs_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio))};
}

// Joshi et al., eq. 15: the lateral stretch l2 of the compressible Neo-Hookean (its eq. 4) under a
// uniaxial stretch l1 with traction-free sides. P22 = mu (l2 - 1 / l2) + lambda l1 l2 (J - 1) = 0
// with J = l1 l2^2 is a quadratic in l2^2, whose positive root this is.
inline Real neo_hookean_lateral_stretch(Real l1, Real mu, Real lambda) {
  const Real root = std::sqrt((mu - lambda * l1) * (mu - lambda * l1) + 4 * lambda * l1 * l1 * mu);
  return std::sqrt((-mu + lambda * l1 + root) / (2 * lambda * l1 * l1));
}

}  // namespace incise::sim::test
