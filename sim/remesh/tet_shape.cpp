#include "sim/remesh/tet_shape.h"

#include <algorithm>
#include <cmath>

#include "sim/mesh/tet_adjacency.h"

namespace incise::sim::remesh {

Vec3 circumcenter(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 u = b - a, v = c - a, w = d - a;
  const Vec3 vw = v.cross(w), wu = w.cross(u), uv = u.cross(v);
  return a + (u.squaredNorm() * vw + v.squaredNorm() * wu + w.squaredNorm() * uv) / (2 * u.dot(vw));
}

TetShape tet_shape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 x[4] = {a, b, c, d};
  TetShape shape;
  shape.circumradius = (circumcenter(a, b, c, d) - a).norm();
  Real shortest_squared = (x[1] - x[0]).squaredNorm();
  for (const auto& e : kTetEdges)
    shortest_squared = std::min(shortest_squared, (x[e[1]] - x[e[0]]).squaredNorm());
  shape.shortest_edge = std::sqrt(shortest_squared);
  shape.radius_edge_ratio = shape.circumradius / shape.shortest_edge;
  // Altitude to face k = 3 V / area_k = |6 V| / |twice the face's area vector|.
  const Real six_volume = std::abs((b - a).dot((c - a).cross(d - a)));
  Real largest_face = 0;
  for (const auto& f : kTetFaces) {
    largest_face = std::max(largest_face, (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]).norm());
  }
  shape.min_altitude = six_volume / largest_face;
  return shape;
}

}  // namespace incise::sim::remesh
