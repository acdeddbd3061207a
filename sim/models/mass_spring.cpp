#include "sim/models/mass_spring.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/mesh/tet_adjacency.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/models/spring_force.h"

namespace incise::sim {

MassSpring::MassSpring(const Points& rest, const Tets& tets, const MassSpringMaterial& material) {
  if (!(material.youngs_modulus > 0) || !(material.density > 0) || !(material.damping >= 0)) {
    throw std::invalid_argument("mass-spring material needs E > 0, density > 0, damping >= 0");
  }
  const VecX volumes = tet_volumes(rest, tets);
  for (Eigen::Index t = 0; t < volumes.size(); ++t) {
    if (!(volumes(t) > 0)) {
      throw std::invalid_argument("tet " + std::to_string(t) + " has non-positive rest volume " +
                                  std::to_string(volumes(t)));
    }
  }
  springs_ = unique_edges(tets);
  const TetEdgeIndices tet_springs = tet_edge_indices(tets, springs_);

  // Eq. 5 and the volume sums of eq. 6.
  masses_ = VecX::Zero(rest.rows());
  VecX edge_volume = VecX::Zero(springs_.rows());
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    for (int k = 0; k < 4; ++k)
      masses_(tets(t, k)) += material.density * volumes(t) / 4;
    for (int e = 0; e < 6; ++e)
      edge_volume(tet_springs(t, e)) += volumes(t);
  }

  rest_lengths_.resize(springs_.rows());
  stiffness_.resize(springs_.rows());
  damping_.resize(springs_.rows());
  for (Eigen::Index s = 0; s < springs_.rows(); ++s) {
    const int i = springs_(s, 0);
    const int j = springs_(s, 1);
    const Real length = (rest.row(j) - rest.row(i)).norm();
    rest_lengths_(s) = length;
    stiffness_(s) = material.youngs_modulus * edge_volume(s) / (length * length);  // eq. 6
    damping_(s) =
        material.damping * 2 * std::sqrt(stiffness_(s) * (masses_(i) + masses_(j)));  // eq. 7
  }
}

int MassSpring::add_forces(const Points& x, const Points& v, Points& f) const {
  int degenerate = 0;
  for (Eigen::Index s = 0; s < springs_.rows(); ++s) {
    const int i = springs_(s, 0);
    const int j = springs_(s, 1);
    const SpringForce force = spring_force(row3(x, i), row3(x, j), row3(v, i), row3(v, j),
                                           stiffness_(s), damping_(s), rest_lengths_(s));
    degenerate += force.degenerate ? 1 : 0;
    f.row(i) += force.on_i.transpose();
    f.row(j) -= force.on_i.transpose();
  }
  return degenerate;
}

}  // namespace incise::sim
