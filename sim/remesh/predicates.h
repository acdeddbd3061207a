#pragma once

// Exact geometric predicates for remeshing: the one door through which sim/remesh/ reaches CGAL
// (STYLE.md). Only predicates.cpp includes CGAL; these are plain functions on our Vec3.
// Results are exact for the double coordinates given (CGAL's filtered exact predicates), so that
// every topological decision of the remesher is consistent with every other one.

#include "sim/core/types.h"

namespace incise::sim::remesh {

// Sign of det[b - a, c - a, d - a]: +1 if d lies on the side of the plane (a, b, c) that
// (b - a) x (c - a) points to (the tet (a, b, c, d) is positively oriented, as in
// signed_volume), -1 on the other side, 0 if the four points are coplanar.
int orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// True if a, b, c lie on one line.
bool collinear(const Vec3& a, const Vec3& b, const Vec3& c);

// Position of e relative to the sphere through a, b, c, d, which must be positively oriented
// (orientation(a, b, c, d) > 0): +1 strictly inside, -1 strictly outside, 0 on the sphere.
int side_of_sphere(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, const Vec3& e);

// side_of_sphere with symbolic perturbation, never 0: ties (five cospherical points) are broken
// as if each point's lifted height |p|^2 were raised by an infinitesimal eps_k, with
// eps_k >> eps_j whenever key k > key j. The keys are the points' vertex ids, so every
// vertex set has one Delaunay tetrahedralisation (no four coplanar points assumed among the
// tested tet a, b, c, d). Requires orientation(a, b, c, d) > 0 and five distinct keys.
int side_of_sphere_perturbed(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                             const Vec3& e, int key_a, int key_b, int key_c, int key_d, int key_e);

}  // namespace incise::sim::remesh
