#pragma once

// The marked cut target of a task, in rest coordinates: a polyline drawn on the
// organ (the "marked line") and the surface it sweeps into the tissue along a depth direction,
// down to a depth. A perfect cut lies on that surface; a cut's accuracy is the distance of its
// crack faces from it, and the band of half_width on either side counts as on target.
//
// The surface of segment (p, q) is the rectangle p, q, q + D n, p + D n (n the unit depth
// direction, D the depth); the distance of a point to the target is the least distance to these
// rectangles, computed exactly (two triangles each). A marked line on the organ's top face with
// n pointing down and D the organ's thickness thus measures how far a cut strays sideways from
// the line at every depth, not how deep a crack face lies below the line.

#include "sim/core/types.h"

namespace incise::sim::tools {

struct MarkedTarget {
  Points line;                            // #P by 3 rest positions [m] of the marked polyline
  Vec3 depth_direction = -Vec3::UnitZ();  // into the tissue; normalised by the user of it
  Real depth = 0;                         // [m] how far the target surface reaches, > 0
  Real half_width = 0;                    // [m] the on-target band on either side, > 0

  // No polyline: the task marks no target (every cut is then off target).
  bool empty() const { return line.rows() == 0; }
};

// Throws std::invalid_argument, naming the field, unless target is empty or has >= 2 finite
// points, no zero-length segment, a finite non-zero depth_direction and finite depth and
// half_width > 0.
void validate_target(const MarkedTarget& target);

// The rest distance [m] from point to the target surface (see above). target must be valid and
// not empty. Allocates nothing.
Real distance_to_target(const MarkedTarget& target, const Vec3& point);

}  // namespace incise::sim::tools
