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

// A ball (rest coordinates) that holds every point where a size field is finite: a hint that lets
// refinement visit only the tets near the region instead of scanning the whole mesh (see
// RefinementSettings::region). A hint smaller than the field's region makes refinement miss the
// tets outside the hint, so give the field's own bounding ball (region_hint_of below).
struct RegionHint {
  Vec3 center = Vec3::Zero();  // [m]
  Real radius = 0;             // [m], >= 0
};

// The smallest ball holding the box (its circumscribed ball), and the ball itself: the hints for
// box_size_field and sphere_size_field.
RegionHint region_hint_of(const Box3& box);
RegionHint region_hint_of(const Vec3& center, Real radius);

// True if the ball (center, radius) meets the hint's ball (closed: touching counts).
bool intersects(const RegionHint& hint, const Vec3& center, Real radius);

// True if the tet (a, b, c, d) is in the field's region (finite at its centroid).
bool in_region(const SizeField& field, const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

}  // namespace incise::sim::remesh
