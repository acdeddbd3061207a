#pragma once

// Closed shapes given by an implicit function f: f(p) < 0 inside, f(p) > 0 outside, and |f| close
// to the distance [m] to the surface near it (exact for a sphere), so that shapes can be blended
// with a blend radius in metres. Plain values; sim/mesh/cgal/mesh_generation.h meshes them.

#include <variant>
#include <vector>

#include "sim/core/types.h"

namespace incise::sim {

struct Sphere {
  Vec3 centre;  // [m]
  Real radius;  // [m], > 0
};

// An axis-aligned ellipsoid.
struct Ellipsoid {
  Vec3 centre;  // [m]
  Vec3 radii;   // semi-axes along x, y, z [m], each > 0
};

// The smooth union of ellipsoids: where two parts meet, the crease is filled with a fillet of
// about blend_radius [m] (0 gives the plain union).
struct EllipsoidBlend {
  std::vector<Ellipsoid> parts;  // at least one
  Real blend_radius = 0;         // [m], >= 0
};

// A lobed, liver-like organ: a blend of lobes cut flat below the plane z = flat_side_z (the
// organ's flattened visceral side), the cut edge rounded with the lobes' blend radius.
struct LobedOrgan {
  EllipsoidBlend lobes;
  Real flat_side_z;  // [m]
};

using ImplicitShape = std::variant<Sphere, Ellipsoid, EllipsoidBlend, LobedOrgan>;

// A liver-like organ about `length` [m] long (along x) centred near `centre`: a large right lobe,
// a smaller left lobe, a small caudate lobe and a thin bridge between them, blended with a radius
// of length / 20 and flattened on its lower side (z) by a fifth of its height.
LobedOrgan liver_like_organ(const Vec3& centre, Real length);

// The implicit function of shape at p [m]: negative inside, positive outside, ~ the signed distance
// [m] near the surface. Ellipsoids use the first-order distance estimate
// f = k0 (k0 - 1) / k1, k0 = |(p - c) / r|, k1 = |(p - c) / r^2| (exact on a sphere); unions use
// the polynomial smooth minimum min(a, b) - h^2 k / 4, h = max(k - |a - b|, 0) / k, with k the
// blend radius, which lies below min(a, b) so the blend only adds material.
Real implicit_value(const ImplicitShape& shape, const Vec3& p);

// A box [m] that contains the whole shape (including blend fillets).
Box3 implicit_extent(const ImplicitShape& shape);

// Throws std::invalid_argument naming the problem: a non-finite value, a radius <= 0, a negative
// blend radius, a blend without parts, or a flat side that cuts away the whole organ.
void check_implicit_shape(const ImplicitShape& shape);

}  // namespace incise::sim
