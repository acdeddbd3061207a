#include "sim/mesh/tet_mesh.h"

#include <stdexcept>
#include <string>
#include <utility>

namespace incise::sim {

TetMesh make_tet_mesh(Points rest, Tets tets, Eigen::VectorXi labels) {
  const Eigen::Index num_nodes = rest.rows();
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    for (int k = 0; k < 4; ++k) {
      const int node = tets(t, k);
      if (node < 0 || node >= num_nodes) {
        throw std::invalid_argument("tet " + std::to_string(t) + " refers to node " +
                                    std::to_string(node) + " outside [0, " +
                                    std::to_string(num_nodes) + ")");
      }
      for (int l = 0; l < k; ++l) {
        if (tets(t, l) == node) {
          throw std::invalid_argument("tet " + std::to_string(t) + " repeats node " +
                                      std::to_string(node));
        }
      }
    }
  }
  if (labels.size() == 0) labels = Eigen::VectorXi::Zero(tets.rows());
  if (labels.size() != tets.rows()) {
    throw std::invalid_argument("labels has " + std::to_string(labels.size()) + " entries for " +
                                std::to_string(tets.rows()) + " tets");
  }
  TetMesh mesh;
  mesh.x = rest;
  mesh.v = Points::Zero(num_nodes, 3);
  mesh.rest = std::move(rest);
  mesh.tets = std::move(tets);
  mesh.labels = std::move(labels);
  return mesh;
}

VecX tet_volumes(const Points& points, const Tets& tets) {
  VecX volumes(tets.rows());
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    volumes(t) = signed_volume(row3(points, tets(t, 0)), row3(points, tets(t, 1)),
                               row3(points, tets(t, 2)), row3(points, tets(t, 3)));
  }
  return volumes;
}

Real total_volume(const Points& points, const Tets& tets) {
  return tet_volumes(points, tets).sum();
}

}  // namespace incise::sim
