#pragma once

// The contact of a tool shape with one oriented surface triangle (a, b, c), whose right-hand
// normal nf = (b - a) x (c - a) / |...| points out of the tissue. These kernels are what the
// surface tree (surface_bvh.h) runs on every triangle its boxes let through.
//
// The rule, for the closest points q on the tool's axis (the centre, or the capsule's segment)
// and p on the triangle, at distance d = |q - p|:
//  - no contact if d >= radius, or if q is behind the triangle ((q - p) . nf < 0): a tool that
//    is on the inner side of a triangle is touching the tissue from inside, and the triangles of
//    the far side of a thin body must not pull it through. Keeping the axis from crossing the
//    surface is the swept query's job (SurfaceBvh::sweep);
//  - otherwise normal = (q - p) / d (nf when d is ~0), depth = radius - d, point = p;
//  - a capsule whose segment pierces the triangle: normal = nf, point = the crossing point, and
//    depth = radius + the distance behind the plane of the deeper segment end, i.e. how far the
//    capsule must move along nf to clear the plane.
// A triangle with no area (no normal) gives no contact.

#include "sim/collide/contact.h"
#include "sim/collide/tool_shapes.h"

namespace incise::sim::collide {

// True and the contact (its `triangle` left as is) if the sphere touches triangle (a, b, c).
bool sphere_triangle_contact(const Sphere& sphere, const Vec3& a, const Vec3& b, const Vec3& c,
                             Contact& contact);

// True and the contact (its `triangle` left as is) if the capsule touches triangle (a, b, c).
bool capsule_triangle_contact(const Capsule& capsule, const Vec3& a, const Vec3& b, const Vec3& c,
                              Contact& contact);

// The unit normal of triangle (a, b, c), or zero when it has no area.
Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace incise::sim::collide
