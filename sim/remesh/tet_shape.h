#pragma once

// Shape measures that Delaunay refinement steers by (Shewchuk 1998, "Tetrahedral mesh generation by
// Delaunay refinement", reference 3 of Paloc 2006): the circumcentre where a bad tet is split, the
// circumradius that the size field bounds, and the radius-edge ratio that bounds its quality.

#include "sim/core/types.h"

namespace incise::sim::remesh {

// Circumcentre of the tet (a, b, c, d) [m]: with u = b - a, v = c - a, w = d - a,
// a + (|u|^2 v x w + |v|^2 w x u + |w|^2 u x v) / (2 u . (v x w)). Rounded, not exact; not finite
// for a flat tet.
Vec3 circumcenter(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

struct TetShape {
  Real circumradius = 0;       // [m]
  Real shortest_edge = 0;      // [m]
  Real radius_edge_ratio = 0;  // circumradius / shortest edge: sqrt(6)/4 = 0.61 at best (regular)
  Real min_altitude = 0;       // shortest distance from a vertex to its opposite face [m]
};

// The shape of a positively oriented tet.
TetShape tet_shape(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// The radius-edge ratio of the regular tet, the smallest any tet has.
inline constexpr Real kRegularRadiusEdgeRatio = 0.6123724356957945;

}  // namespace incise::sim::remesh
