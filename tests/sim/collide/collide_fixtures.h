#pragma once

// Surfaces for the collision tests: a deformed box boundary, a jittered sphere-like surface, a
// flat sheet, and a box-shaped bone. All triangles have their right-hand normal pointing out.

#include "sim/core/types.h"

namespace incise::sim::collide::testing {

struct TestSurface {
  Points points;        // #V by 3 [m]
  Triangles triangles;  // #T by 3 indices into points
};

// The boundary of make_box_mesh(size, cells) (its surface vertices, numbered locally), each
// vertex moved by a smooth bend plus a random jitter of up to `jitter` [m] per coordinate.
TestSurface deformed_box_surface(const Vec3& size, const Vec3i& cells, Real jitter, unsigned seed);

// A closed latitude-longitude sphere of radius `radius` around `centre` with `rings` rings of
// `segments` vertices and two poles, each vertex's radius scaled by 1 + U(-jitter, jitter).
TestSurface jittered_sphere_surface(const Vec3& centre, Real radius, int rings, int segments,
                                    Real jitter, unsigned seed);

// The square [-half, half]^2 at height z, n by n cells, two triangles each, normal +z.
TestSurface flat_sheet(Real half, int n, Real z);

// The 8 corners and 12 outward triangles of the box [lo, hi].
TestSurface box_hull(const Vec3& lo, const Vec3& hi);

// Every point moved by `displacement` (a smooth field sampled per point).
template <class Field>
void displace(Points& points, Field&& displacement) {
  for (int i = 0; i < points.rows(); ++i) {
    points.row(i) += displacement(row3(points, i)).transpose();
  }
}

}  // namespace incise::sim::collide::testing
