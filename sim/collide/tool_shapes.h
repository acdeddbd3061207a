#pragma once

// The shapes of a tool's parts, as plain values in world coordinates [m]. Collision queries
// (surface_bvh.h, rigid_body.h) take them by value or const reference; the tool models own the
// poses and rebuild these every step (they are a few doubles, no allocation).

#include <array>

#include "sim/core/types.h"

namespace incise::sim::collide {

// A probe tip: the ball of radius `radius` around `centre`.
struct Sphere {
  Vec3 centre = Vec3::Zero();  // [m]
  Real radius = 0;             // [m], > 0
};

// A tool shaft or a grasper jaw: the points within `radius` of the segment [a, b]. a == b is a
// sphere.
struct Capsule {
  Vec3 a = Vec3::Zero();  // axis end [m]
  Vec3 b = Vec3::Zero();  // other axis end [m]
  Real radius = 0;        // [m], > 0
};

// A grasper's two jaws, each a capsule from the pivot to its tip.
struct JawPair {
  std::array<Capsule, 2> jaws;
};

// The jaws of a grasper opened by `opening_angle` about the tool axis:
//   pivot          the hinge [m]
//   direction      the tool axis, from the pivot towards the tips (normalised here)
//   opening_normal the direction the first jaw opens to; only its part orthogonal to direction
//                  is used (normalised here)
//   opening_angle  the angle between the two jaws [rad], in [0, pi); 0 = closed
//   jaw_length     pivot to tip [m], > 0;  jaw_radius  [m], > 0
// Jaw k (k = 0, 1) runs from the pivot to
//   pivot + jaw_length (cos(opening_angle / 2) d +- sin(opening_angle / 2) u),
// d and u the normalised direction and opening normal, + for jaw 0 and - for jaw 1: the jaws open
// symmetrically about the axis in the plane of d and u.
// Throws std::invalid_argument for a zero direction, an opening normal parallel to it, an angle
// outside [0, pi), or a non-positive length or radius.
JawPair make_jaw_pair(const Vec3& pivot, const Vec3& direction, const Vec3& opening_normal,
                      Real opening_angle, Real jaw_length, Real jaw_radius);

}  // namespace incise::sim::collide
