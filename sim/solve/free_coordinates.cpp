#include "sim/solve/free_coordinates.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace incise::sim {

void check_prescribed(const Prescribed& prescribed, int num_nodes) {
  if (prescribed.mask.rows() == 0) return;
  if (prescribed.mask.rows() != num_nodes || prescribed.position.rows() != num_nodes) {
    throw std::invalid_argument("prescribed mask and position must be " +
                                std::to_string(num_nodes) + " by 3, got " +
                                std::to_string(prescribed.mask.rows()) + " and " +
                                std::to_string(prescribed.position.rows()) + " rows");
  }
  for (Eigen::Index i = 0; i < num_nodes; ++i) {
    for (int a = 0; a < 3; ++a) {
      if (prescribed.mask(i, a) != 0 && !std::isfinite(prescribed.position(i, a))) {
        throw std::invalid_argument("prescribed position of node " + std::to_string(i) + " axis " +
                                    std::to_string(a) + " is not finite");
      }
    }
  }
}

void free_coordinates(const Prescribed& prescribed, const VecX& masses, Points& free) {
  const Eigen::Index n = masses.size();
  if (free.rows() != n) free.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a) {
      free(i, a) = (masses(i) > 0 && !is_prescribed(prescribed, i, a)) ? Real(1) : Real(0);
    }
  }
}

}  // namespace incise::sim
