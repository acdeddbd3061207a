#include "sim/mesh/mesh_from_file_data.h"

#include <algorithm>
#include <utility>

#include "sim/mesh/mesh_file_error.h"
#include "sim/mesh/mesh_quality.h"
#include "sim/mesh/tet_adjacency.h"

namespace incise::sim {

TetMesh mesh_from_file_data(const Points& nodes, Tets tets, Eigen::VectorXi labels,
                            const std::vector<int>& tet_lines, const std::string& file) {
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    const int line = tet_lines[static_cast<std::size_t>(t)];
    for (int k = 0; k < 4; ++k) {
      for (int l = 0; l < k; ++l) {
        if (tets(t, k) == tets(t, l)) {
          throw MeshFileError(file, line, "tetrahedron repeats a node");
        }
      }
    }
    const Vec3 p[4] = {row3(nodes, tets(t, 0)), row3(nodes, tets(t, 1)), row3(nodes, tets(t, 2)),
                       row3(nodes, tets(t, 3))};
    Real longest_edge = 0;
    for (const auto& edge : kTetEdges) {
      longest_edge = std::max(longest_edge, (p[edge[1]] - p[edge[0]]).norm());
    }
    const Real volume = signed_volume(p[0], p[1], p[2], p[3]);
    if (is_degenerate(volume, longest_edge)) {
      throw MeshFileError(file, line,
                          "degenerate tetrahedron (zero volume: its nodes are coplanar or "
                          "coincide)");
    }
    if (volume < 0) std::swap(tets(t, 2), tets(t, 3));
  }

  // Compact the nodes to those the tets use, in their order of appearance in the file.
  std::vector<int> new_index(static_cast<std::size_t>(nodes.rows()), -1);
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    for (int k = 0; k < 4; ++k)
      new_index[static_cast<std::size_t>(tets(t, k))] = 0;
  }
  int count = 0;
  for (int& index : new_index) {
    if (index == 0) index = count++;
  }
  Points rest(count, 3);
  for (Eigen::Index i = 0; i < nodes.rows(); ++i) {
    const int j = new_index[static_cast<std::size_t>(i)];
    if (j >= 0) rest.row(j) = nodes.row(i);
  }
  for (Eigen::Index t = 0; t < tets.rows(); ++t) {
    for (int k = 0; k < 4; ++k)
      tets(t, k) = new_index[static_cast<std::size_t>(tets(t, k))];
  }
  return make_tet_mesh(std::move(rest), std::move(tets), std::move(labels));
}

}  // namespace incise::sim
