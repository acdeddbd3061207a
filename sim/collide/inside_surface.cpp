#include "sim/collide/inside_surface.h"

#include <cmath>

#include "sim/collide/tool_shapes.h"

namespace incise::sim::collide {

bool inside_closed_surface(const SurfaceBvh& bvh, const Points& x, const Vec3& p,
                           std::vector<int>& scratch) {
  // Crossings by Moller-Trumbore.
  const Vec3 direction = Vec3(0.5773, 0.6123, 0.5402).normalized();
  const Vec3 far = p + 10.0 * direction;
  bvh.overlapping_triangles(x, Capsule{p, far, 1e-9}, scratch);
  int crossings = 0;
  for (const int t : scratch) {
    const Vec3i& tri = bvh.triangle(t);
    const Vec3 a = row3(x, tri[0]), e1 = row3(x, tri[1]) - a, e2 = row3(x, tri[2]) - a;
    const Vec3 h = direction.cross(e2);
    const Real det = e1.dot(h);
    if (std::abs(det) < 1e-300) continue;
    const Vec3 s = p - a;
    const Real u = s.dot(h) / det;
    const Vec3 q = s.cross(e1);
    const Real w = direction.dot(q) / det;
    const Real t_hit = e2.dot(q) / det;
    if (u >= 0 && w >= 0 && u + w <= 1 && t_hit > 0) ++crossings;
  }
  return crossings % 2 == 1;
}

}  // namespace incise::sim::collide
