#include "sim/collide/shape_triangle_contact.h"

#include <algorithm>

#include "sim/collide/triangle_geometry.h"

namespace incise::sim::collide {

namespace {

// Contact from the closest points q (tool axis) and p (triangle) at distance `distance`.
bool contact_from_closest(const Vec3& q, const Vec3& p, Real distance, Real radius,
                          const Vec3& face_normal, Contact& contact) {
  if (!(distance < radius)) return false;
  const Vec3 offset = q - p;
  if (offset.dot(face_normal) < 0) return false;
  contact.point = p;
  contact.normal = distance > 1e-12 * radius ? Vec3(offset / distance) : face_normal;
  contact.depth = radius - distance;
  return true;
}

}  // namespace

Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const Real length = n.norm();
  return length > 0 ? Vec3(n / length) : Vec3::Zero();
}

bool sphere_triangle_contact(const Sphere& sphere, const Vec3& a, const Vec3& b, const Vec3& c,
                             Contact& contact) {
  const Vec3 face_normal = triangle_normal(a, b, c);
  if (face_normal.isZero()) return false;
  const Vec3 w = closest_point_barycentric(sphere.centre, a, b, c);
  const Vec3 p = w[0] * a + w[1] * b + w[2] * c;
  if (!contact_from_closest(sphere.centre, p, (sphere.centre - p).norm(), sphere.radius,
                            face_normal, contact)) {
    return false;
  }
  contact.barycentric = w;
  return true;
}

bool capsule_triangle_contact(const Capsule& capsule, const Vec3& a, const Vec3& b, const Vec3& c,
                              Contact& contact) {
  const Vec3 face_normal = triangle_normal(a, b, c);
  if (face_normal.isZero()) return false;
  const SegmentTriangleClosest closest = segment_triangle_closest(capsule.a, capsule.b, a, b, c);
  const Vec3& w = closest.barycentric;
  const Vec3 p = w[0] * a + w[1] * b + w[2] * c;
  if (closest.pierces) {
    const Real behind =
        std::max({Real(0), -(capsule.a - a).dot(face_normal), -(capsule.b - a).dot(face_normal)});
    contact.point = p;
    contact.normal = face_normal;
    contact.depth = capsule.radius + behind;
    contact.barycentric = w;
    return true;
  }
  const Vec3 q = capsule.a + closest.s * (capsule.b - capsule.a);
  if (!contact_from_closest(q, p, closest.distance, capsule.radius, face_normal, contact)) {
    return false;
  }
  contact.barycentric = w;
  return true;
}

}  // namespace incise::sim::collide
