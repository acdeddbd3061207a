#include "sim/solve/symplectic_euler.h"

namespace incise::sim {

void symplectic_euler_step(Real dt, const Vec3& gravity, const VecX& inv_mass,
                           const Prescribed& prescribed, const Points& f, Points& x, Points& v) {
  const bool any_prescribed = prescribed.mask.rows() > 0;
  for (Eigen::Index i = 0; i < x.rows(); ++i) {
    const Real w = inv_mass(i);
    for (int a = 0; a < 3; ++a) {
      if (any_prescribed && prescribed.mask(i, a) != 0) {
        const Real target = prescribed.position(i, a);
        v(i, a) = (target - x(i, a)) / dt;
        x(i, a) = target;
        continue;
      }
      if (w != 0) v(i, a) += dt * (f(i, a) * w + gravity(a));
      x(i, a) += dt * v(i, a);
    }
  }
}

}  // namespace incise::sim
