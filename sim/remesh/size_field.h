#pragma once

// Where to refine and how finely: a size field over the rest configuration.

#include <functional>

#include "sim/core/types.h"

namespace incise::sim::remesh {

// The target circumradius [m] of the tets at a rest point; +infinity outside the region to keep
// refined. A tet belongs to the region if the field is finite at its centroid (always inside the
// tet, unlike its circumcentre).
using SizeField = std::function<Real(const Vec3& rest_point)>;

// `size` inside the closed box (rest coordinates), +infinity outside.
SizeField box_size_field(const Box3& box, Real size);

// `size` inside the closed ball, +infinity outside.
SizeField sphere_size_field(const Vec3& center, Real radius, Real size);

// True if the tet (a, b, c, d) is in the field's region (finite at its centroid).
bool in_region(const SizeField& field, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace incise::sim::remesh
