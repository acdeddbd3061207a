#include "sim/remesh/region_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "sim/mesh/mesh_quality.h"
#include "sim/mesh/tet_adjacency.h"
#include "sim/remesh/tet_shape.h"

namespace incise::sim::remesh {

RegionQuality region_quality(const RemeshMesh& mesh, const SizeField& field) {
  constexpr Real kInfinity = std::numeric_limits<Real>::infinity();
  RegionQuality q;
  q.min_dihedral = q.min_edge = q.min_altitude = kInfinity;
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const TetVertices& v = mesh.tet(t);
    const Vec3 &a = mesh.point(v[0]), &b = mesh.point(v[1]), &c = mesh.point(v[2]),
               &d = mesh.point(v[3]);
    const Real target = field((a + b + c + d) / 4);
    if (!std::isfinite(target)) continue;
    ++q.num_tets;
    const TetShape shape = tet_shape(a, b, c, d);
    const TetQuality angles = tet_quality(a, b, c, d);
    q.max_size_ratio = std::max(q.max_size_ratio, shape.circumradius / target);
    q.max_radius_edge_ratio = std::max(q.max_radius_edge_ratio, shape.radius_edge_ratio);
    q.min_dihedral = std::min(q.min_dihedral, angles.min_dihedral);
    q.max_dihedral = std::max(q.max_dihedral, angles.max_dihedral);
    q.min_edge = std::min(q.min_edge, shape.shortest_edge);
    q.min_altitude = std::min(q.min_altitude, shape.min_altitude);
  }
  if (q.num_tets == 0) q = RegionQuality{};
  return q;
}

Real shortest_inserted_edge(const RemeshMesh& mesh) {
  Real shortest = std::numeric_limits<Real>::infinity();
  for (int t = 0; t < mesh.num_tet_slots(); ++t) {
    if (!mesh.tet_alive(t)) continue;
    const TetVertices& v = mesh.tet(t);
    for (const auto& e : kTetEdges) {
      if (mesh.is_original(v[e[0]]) && mesh.is_original(v[e[1]])) continue;
      shortest = std::min(shortest, (mesh.point(v[e[0]]) - mesh.point(v[e[1]])).norm());
    }
  }
  return shortest;
}

}  // namespace incise::sim::remesh
