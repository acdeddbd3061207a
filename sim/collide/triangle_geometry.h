#pragma once

// Exact geometric kernels of one triangle against a point, a segment and a moving sphere. They
// are pure functions over small Eigen values, shared by the surface tree's queries and its
// brute-force reference in the tests. Triangles are (a, b, c) with the right-hand normal
// (b - a) x (c - a) pointing out of the surface (BoundarySurface's orientation).

#include "sim/core/types.h"

namespace incise::sim::collide {

// The point of triangle (a, b, c) closest to p, as barycentric coordinates w (each >= 0, sum 1):
// the point is w[0] a + w[1] b + w[2] c. Found by the Voronoi region of p (three vertices, three
// edges, the face). A degenerate (collinear or collapsed) triangle is handled as its three edges.
Vec3 closest_point_barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Parameters (s, t) in [0, 1]^2 of the closest points p0 + s (p1 - p0) and q0 + t (q1 - q0) of two
// segments. Either segment may be a point.
Eigen::Vector2d closest_segment_parameters(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                           const Vec3& q1);

// The closest points of a segment [p0, p1] and a triangle (a, b, c).
struct SegmentTriangleClosest {
  Real s = 0;                       // the segment point is p0 + s (p1 - p0), s in [0, 1]
  Vec3 barycentric = Vec3::Zero();  // the triangle point (see closest_point_barycentric)
  Real distance = 0;                // between the two points [m]
  bool pierces = false;             // the segment crosses the triangle (distance 0)
};

// Closest points of segment [p0, p1] and triangle (a, b, c): 0 and the crossing point if the
// segment pierces the triangle, else the best of the two end points against the triangle and
// the segment against the three edges (the minimum of a distance between a segment and a
// triangle that do not cross lies on one of those five).
SegmentTriangleClosest segment_triangle_closest(const Vec3& p0, const Vec3& p1, const Vec3& a,
                                                const Vec3& b, const Vec3& c);

// The first contact of a sphere of radius r whose centre moves linearly from c0 (time 0) to c1
// (time 1) with the triangle (a, b, c), either side (a sheet has two).
struct SweepContact {
  Real time = 0;                    // in [0, 1]; 0 if the sphere already touches at c0
  Vec3 barycentric = Vec3::Zero();  // the touched point of the triangle
};

// True and the earliest contact if the moving sphere touches the triangle during [0, 1]. Exact
// (up to rounding): the sphere touches the face interior when its centre is at distance r from
// the plane, an edge when at distance r from the edge's line (a ray against a cylinder), a
// vertex when at distance r from it (a ray against a sphere); the earliest valid one wins.
// Touching at c0 (distance <= r) gives time 0.
bool sweep_sphere_triangle(const Vec3& c0, const Vec3& c1, Real r, const Vec3& a, const Vec3& b,
                           const Vec3& c, SweepContact& contact);

}  // namespace incise::sim::collide
