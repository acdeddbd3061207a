#pragma once
// Which coordinates the solvers may move. Every solver in sim/solve/ honours the same rule, so
// that a scene behaves alike whichever integrator it names.

#include "sim/core/types.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim {

// Throws std::invalid_argument unless prescribed is empty (mask with 0 rows) or its mask and
// position are both num_nodes by 3, and every prescribed position is finite.
void check_prescribed(const Prescribed& prescribed, int num_nodes);

// free(i, a) = 1 where coordinate a of node i is integrated, 0 where it is held: prescribed by
// the mask, or its node has no mass (a node outside every tet, which no force can accelerate).
//   prescribed  Dirichlet conditions (empty = none)
//   masses      #nodes lumped masses [kg]
//   free        #nodes by 3 output, 1 or 0; resized only if its size differs
void free_coordinates(const Prescribed& prescribed, const VecX& masses, Points& free);

// Whether coordinate a of node i is prescribed.
inline bool is_prescribed(const Prescribed& prescribed, Eigen::Index i, int a) {
  return prescribed.mask.rows() > 0 && prescribed.mask(i, a) != 0;
}

// Whether every entry is finite (no NaN, no infinity).
inline bool all_finite(const Points& points) {
  return points.allFinite();
}

}  // namespace incise::sim
