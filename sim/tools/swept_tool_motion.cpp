#include "sim/tools/swept_tool_motion.h"

#include <stdexcept>
#include <string>

#include "sim/collide/shape_triangle_contact.h"
#include "sim/collide/triangle_geometry.h"
#include "sim/tools/tool_checks.h"

namespace incise::sim::tools {
namespace {

constexpr int kMaxHits = 3;
constexpr int kMaxPushes = 4;

Vec3 corner(const Points& x, const Vec3i& triangle, int k) {
  return row3(x, triangle[k]);
}

}  // namespace

SweptToolMotion::SweptToolMotion(Real radius, Real allowed_penetration)
    : radius_(radius), allowed_(allowed_penetration) {
  checks::check_radius(radius, "SweptToolMotion");
  if (!(allowed_penetration > 0 && allowed_penetration < radius)) {
    throw std::invalid_argument(
        "SweptToolMotion: allowed_penetration must be in (0, radius = " + std::to_string(radius) +
        "), got " + std::to_string(allowed_penetration));
  }
}

ToolMotion SweptToolMotion::move(const collide::SurfaceBvh& bvh, const Points& x, const Vec3& from,
                                 const Vec3& to) {
  checks::check_vector(from, "SweptToolMotion::move", "from");
  checks::check_vector(to, "SweptToolMotion::move", "to");
  const Real core = radius_ - allowed_;
  ToolMotion result;
  Vec3 start = from;
  // 1. Out of the tissue that moved into the core.
  for (int pass = 0; pass < kMaxPushes; ++pass) {
    bvh.contacts(x, collide::Sphere{start, core}, contacts_);
    const collide::Contact* deepest = nullptr;
    for (const collide::Contact& c : contacts_) {
      if (deepest == nullptr || c.depth > deepest->depth) deepest = &c;
    }
    if (deepest == nullptr) break;
    start += deepest->depth * deepest->normal;
    result.blocked = true;
    result.triangle = deepest->triangle;
    result.normal = deepest->normal;
  }
  // 2. The sweep.
  Vec3 motion = to - start;
  for (int pass = 0; pass < kMaxHits; ++pass) {
    const Real length = motion.norm();
    if (!(length > 0)) break;
    bvh.overlapping_triangles(x, collide::Capsule{start, start + motion, core}, slots_);
    bool found = false;
    Real best_time = 1;
    Vec3 best_normal = Vec3::Zero();
    int best_slot = -1;
    for (const int slot : slots_) {
      const Vec3i& t = bvh.triangle(slot);
      const Vec3 a = corner(x, t, 0), b = corner(x, t, 1), c = corner(x, t, 2);
      collide::SweepContact hit;
      if (!collide::sweep_sphere_triangle(start, start + motion, core, a, b, c, hit)) continue;
      if (found && hit.time >= best_time) continue;
      const Vec3 point = hit.barycentric[0] * a + hit.barycentric[1] * b + hit.barycentric[2] * c;
      const Vec3 offset = start + hit.time * motion - point;
      const Real distance = offset.norm();
      Vec3 normal;
      if (distance > 1e-12 * core) {
        normal = offset / distance;
      } else {
        // The centre is on the triangle: take the face normal on the side the tool came from.
        normal = collide::triangle_normal(a, b, c);
        if (normal.dot(start - point) < 0) normal = -normal;
      }
      // Sliding along or leaving the triangle is free; only a motion into it is stopped.
      if (!(motion.dot(normal) < -1e-12 * length)) continue;
      found = true;
      best_time = hit.time;
      best_normal = normal;
      best_slot = slot;
    }
    if (!found) {
      start += motion;
      motion.setZero();
      break;
    }
    result.blocked = true;
    result.triangle = best_slot;
    result.normal = best_normal;
    start += best_time * motion;
    Vec3 rest = (1 - best_time) * motion;
    rest -= rest.dot(best_normal) * best_normal;
    motion = rest;
  }
  result.centre = start;
  return result;
}

}  // namespace incise::sim::tools
