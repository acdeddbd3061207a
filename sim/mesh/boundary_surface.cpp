#include "sim/mesh/boundary_surface.h"

#include "sim/mesh/tet_adjacency.h"

namespace incise::sim {

BoundarySurface boundary_surface(const TetMesh& mesh) {
  BoundarySurface surface;
  const Triangles global = boundary_faces(mesh.tets, &surface.tets);
  // Global -> local vertex numbers; -1 for nodes off the surface. Ascending local numbering keeps
  // `nodes` sorted, so the surface of the same mesh is always numbered the same way.
  std::vector<int> local(static_cast<std::size_t>(mesh.num_nodes()), -1);
  for (Eigen::Index f = 0; f < global.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      local[static_cast<std::size_t>(global(f, c))] = 0;
  }
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (local[static_cast<std::size_t>(i)] < 0) continue;
    local[static_cast<std::size_t>(i)] = static_cast<int>(surface.nodes.size());
    surface.nodes.push_back(i);
  }
  surface.faces.resize(global.rows(), 3);
  for (Eigen::Index f = 0; f < global.rows(); ++f) {
    for (int c = 0; c < 3; ++c)
      surface.faces(f, c) = local[static_cast<std::size_t>(global(f, c))];
  }
  return surface;
}

void surface_vertices(const BoundarySurface& surface, const Points& x, Points& V, Points& N) {
  const auto count = static_cast<Eigen::Index>(surface.nodes.size());
  V.resize(count, 3);  // no-ops once sized
  N.resize(count, 3);
  for (Eigen::Index j = 0; j < count; ++j)
    V.row(j) = x.row(surface.nodes[static_cast<std::size_t>(j)]);
  N.setZero();
  for (Eigen::Index f = 0; f < surface.faces.rows(); ++f) {
    const int a = surface.faces(f, 0);
    const int b = surface.faces(f, 1);
    const int c = surface.faces(f, 2);
    // |(b - a) x (c - a)| is twice the face's area: the sum is area weighted.
    const Vec3 area = (row3(V, b) - row3(V, a)).cross(row3(V, c) - row3(V, a));
    N.row(a) += area.transpose();
    N.row(b) += area.transpose();
    N.row(c) += area.transpose();
  }
  for (Eigen::Index j = 0; j < count; ++j) {
    const Real length = N.row(j).norm();
    if (length > 0) {
      N.row(j) /= length;
    }
  }
}

}  // namespace incise::sim
