#include "sim/cut/cut_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace incise::sim::cut {
namespace {

constexpr Real kBorderTolerance = 1e-12;
constexpr Real kMergeTolerance = 1e-9;

void check_blade(const Vec3& a, const Vec3& b, int pose) {
  if (!((a - b).norm() > 0)) {
    throw std::invalid_argument("blade pose " + std::to_string(pose) + " has zero length");
  }
}

Vec3 vertex(const CutSurface& surface, int triangle, int corner) {
  return row3(surface.vertices, surface.triangles(triangle, corner));
}

// Closest point to p on the triangle (a, b, c), by the Voronoi regions of its vertices, edges and
// face (Ericson, "Real-Time Collision Detection", section 5.1.5).
Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Vec3 ap = p - a;
  const Real d1 = ab.dot(ap);
  const Real d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp);
  const Real d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp);
  const Real d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const Real denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

CutSurface blade_sweep(const Vec3& a0, const Vec3& b0, const Vec3& a1, const Vec3& b1) {
  Points a(2, 3);
  Points b(2, 3);
  a.row(0) = a0.transpose();
  a.row(1) = a1.transpose();
  b.row(0) = b0.transpose();
  b.row(1) = b1.transpose();
  return blade_path(a, b);
}

CutSurface blade_path(const Points& a, const Points& b) {
  if (a.rows() != b.rows()) {
    throw std::invalid_argument("blade path: " + std::to_string(a.rows()) + " poses of a but " +
                                std::to_string(b.rows()) + " of b");
  }
  if (a.rows() < 2) throw std::invalid_argument("blade path: fewer than 2 poses");
  const int poses = static_cast<int>(a.rows());
  for (int k = 0; k < poses; ++k)
    check_blade(row3(a, k), row3(b, k), k);
  CutSurface surface;
  // Vertex 2k is a_k, 2k + 1 is b_k.
  surface.vertices.resize(2 * poses, 3);
  for (int k = 0; k < poses; ++k) {
    surface.vertices.row(2 * k) = a.row(k);
    surface.vertices.row(2 * k + 1) = b.row(k);
  }
  surface.triangles.resize(2 * (poses - 1), 3);
  for (int k = 0; k + 1 < poses; ++k) {
    const int a0 = 2 * k, b0 = 2 * k + 1, a1 = 2 * k + 2, b1 = 2 * k + 3;
    surface.triangles.row(2 * k) << a0, b0, b1;
    surface.triangles.row(2 * k + 1) << a0, b1, a1;
  }
  return surface;
}

void segment_hits(const CutSurface& surface, const Vec3& p, const Vec3& q,
                  std::vector<Real>& hits) {
  hits.clear();
  const Vec3 d = q - p;
  if (!(d.squaredNorm() > 0)) return;
  for (int f = 0; f < static_cast<int>(surface.triangles.rows()); ++f) {
    const Vec3 a = vertex(surface, f, 0);
    const Vec3 e1 = vertex(surface, f, 1) - a;
    const Vec3 e2 = vertex(surface, f, 2) - a;
    // Moeller-Trumbore: p + t d = a + u e1 + w e2, solved by Cramer's rule.
    const Vec3 h = d.cross(e2);
    const Real det = e1.dot(h);
    const Real scale = e1.norm() * e2.norm() * d.norm();
    if (!(std::abs(det) > 1e-12 * scale)) continue;  // parallel (or a flat triangle)
    const Real inv = 1 / det;
    const Vec3 s = p - a;
    const Real u = s.dot(h) * inv;
    if (u < -kBorderTolerance || u > 1 + kBorderTolerance) continue;
    const Vec3 r = s.cross(e1);
    const Real w = d.dot(r) * inv;
    if (w < -kBorderTolerance || u + w > 1 + kBorderTolerance) continue;
    const Real t = e2.dot(r) * inv;
    if (t < -kBorderTolerance || t > 1 + kBorderTolerance) continue;
    hits.push_back(std::clamp(t, Real(0), Real(1)));
  }
  std::sort(hits.begin(), hits.end());
  hits.erase(std::unique(hits.begin(), hits.end(),
                         [](Real x, Real y) { return std::abs(x - y) < kMergeTolerance; }),
             hits.end());
}

Real distance_to_surface(const CutSurface& surface, const Vec3& point) {
  Real best = std::numeric_limits<Real>::infinity();
  for (int f = 0; f < static_cast<int>(surface.triangles.rows()); ++f) {
    const Vec3 c = closest_point_on_triangle(point, vertex(surface, f, 0), vertex(surface, f, 1),
                                             vertex(surface, f, 2));
    best = std::min(best, (c - point).norm());
  }
  return best;
}

Box3 surface_bounds(const CutSurface& surface) {
  Box3 box;
  for (int i = 0; i < static_cast<int>(surface.vertices.rows()); ++i)
    box.extend(row3(surface.vertices, i));
  return box;
}

}  // namespace incise::sim::cut
