#include "sim/collide/triangle_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace incise::sim::collide {

namespace {

Real clamp01(Real x) {
  return std::clamp(x, Real(0), Real(1));
}

// Parameter in [0, 1] of the point of segment [a, b] closest to p.
Real closest_on_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const Real length2 = ab.squaredNorm();
  return length2 > 0 ? clamp01((p - a).dot(ab) / length2) : Real(0);
}

// A triangle with no area has no face region: its closest point is on one of its edges.
Vec3 closest_on_edges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 corners[3] = {a, b, c};
  Vec3 best = Vec3(1, 0, 0);
  Real best_distance2 = std::numeric_limits<Real>::infinity();
  for (int e = 0; e < 3; ++e) {
    const int i = e;
    const int j = (e + 1) % 3;
    const Real t = closest_on_segment(p, corners[i], corners[j]);
    const Real distance2 = (p - ((1 - t) * corners[i] + t * corners[j])).squaredNorm();
    if (distance2 < best_distance2) {
      best_distance2 = distance2;
      best = Vec3::Zero();
      best[i] = 1 - t;
      best[j] = t;
    }
  }
  return best;
}

}  // namespace

Vec3 closest_point_barycentric(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a;
  const Vec3 ac = c - a;
  const Real scale2 = std::max({ab.squaredNorm(), ac.squaredNorm(), (c - b).squaredNorm()});
  if (!(ab.cross(ac).squaredNorm() > 1e-24 * scale2 * scale2)) return closest_on_edges(p, a, b, c);

  // Dot products of p's offsets from each corner with the two edge vectors decide the Voronoi
  // region; the face region's barycentrics are ratios of the signed sub-areas va, vb, vc.
  const Vec3 ap = p - a;
  const Real d1 = ab.dot(ap);
  const Real d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return Vec3(1, 0, 0);
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp);
  const Real d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return Vec3(0, 1, 0);
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const Real t = d1 / (d1 - d3);
    return Vec3(1 - t, t, 0);
  }
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp);
  const Real d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return Vec3(0, 0, 1);
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const Real t = d2 / (d2 - d6);
    return Vec3(1 - t, 0, t);
  }
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    const Real t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return Vec3(0, 1 - t, t);
  }
  const Real inverse = 1 / (va + vb + vc);
  const Real v = vb * inverse;
  const Real w = vc * inverse;
  return Vec3(1 - v - w, v, w);
}

Eigen::Vector2d closest_segment_parameters(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                           const Vec3& q1) {
  const Vec3 d1 = p1 - p0;
  const Vec3 d2 = q1 - q0;
  const Vec3 r = p0 - q0;
  const Real a = d1.squaredNorm();
  const Real e = d2.squaredNorm();
  const Real f = d2.dot(r);
  if (a <= 0 && e <= 0) return {0, 0};
  if (a <= 0) return {0, clamp01(f / e)};
  const Real c = d1.dot(r);
  if (e <= 0) return {clamp01(-c / a), 0};
  // Minimise |r + s d1 - t d2|^2: s from the unclamped 2x2 system (0 for parallel segments),
  // then t for that s, re-clamping s whenever t had to be clamped.
  const Real b = d1.dot(d2);
  const Real denominator = a * e - b * b;
  Real s = denominator > 0 ? clamp01((b * f - c * e) / denominator) : Real(0);
  Real t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = clamp01(-c / a);
  } else if (t > 1) {
    t = 1;
    s = clamp01((b - c) / a);
  }
  return {s, t};
}

SegmentTriangleClosest segment_triangle_closest(const Vec3& p0, const Vec3& p1, const Vec3& a,
                                                const Vec3& b, const Vec3& c) {
  SegmentTriangleClosest best;
  const Vec3 normal = (b - a).cross(c - a);
  const Real h0 = (p0 - a).dot(normal);
  const Real h1 = (p1 - a).dot(normal);
  if (normal.squaredNorm() > 0 && h0 != h1 && h0 * h1 <= 0) {
    const Real s = h0 / (h0 - h1);
    const Vec3 x = p0 + s * (p1 - p0);
    const Vec3 w = closest_point_barycentric(x, a, b, c);
    // The crossing point of the plane is inside when it is its own closest point, to rounding,
    // which grows with the coordinates as well as with the triangle: a triangle under a millimetre
    // across, 5 cm from the origin, pierced well inside, was taken for a miss at its edge's
    // distance.
    const Real scale2 = std::max((b - a).squaredNorm(), x.squaredNorm());
    if ((w[0] * a + w[1] * b + w[2] * c - x).squaredNorm() <= 1e-28 * scale2) {
      best.s = s;
      best.barycentric = w;
      best.distance = 0;
      best.pierces = true;
      return best;
    }
  }
  Real best_distance2 = std::numeric_limits<Real>::infinity();
  const auto consider = [&](Real s, const Vec3& w) {
    const Vec3 on_segment = p0 + s * (p1 - p0);
    const Real distance2 = (on_segment - (w[0] * a + w[1] * b + w[2] * c)).squaredNorm();
    if (distance2 < best_distance2) {
      best_distance2 = distance2;
      best.s = s;
      best.barycentric = w;
    }
  };
  consider(0, closest_point_barycentric(p0, a, b, c));
  consider(1, closest_point_barycentric(p1, a, b, c));
  const Vec3 corners[3] = {a, b, c};
  for (int e = 0; e < 3; ++e) {
    const int i = e;
    const int j = (e + 1) % 3;
    const Eigen::Vector2d st = closest_segment_parameters(p0, p1, corners[i], corners[j]);
    Vec3 w = Vec3::Zero();
    w[i] = 1 - st[1];
    w[j] = st[1];
    consider(st[0], w);
  }
  best.distance = std::sqrt(best_distance2);
  return best;
}

namespace {

// Earliest root in [0, 1] of A t^2 + B t + C = 0 with C > 0 (the centre starts outside), i.e.
// the entry time of a ray into a sphere or cylinder; false if it misses or enters later.
bool entry_time(Real A, Real B, Real C, Real& t) {
  if (!(A > 0)) return false;
  const Real discriminant = B * B - 4 * A * C;
  if (discriminant < 0) return false;
  t = (-B - std::sqrt(discriminant)) / (2 * A);
  return t >= 0 && t <= 1;
}

}  // namespace

bool sweep_sphere_triangle(const Vec3& c0, const Vec3& c1, Real r, const Vec3& a, const Vec3& b,
                           const Vec3& c, SweepContact& contact) {
  const Vec3 w0 = closest_point_barycentric(c0, a, b, c);
  if ((c0 - (w0[0] * a + w0[1] * b + w0[2] * c)).norm() <= r) {
    contact.time = 0;
    contact.barycentric = w0;
    return true;
  }
  const Vec3 D = c1 - c0;
  Real best = std::numeric_limits<Real>::infinity();
  Vec3 best_w = Vec3::Zero();

  // Face: the signed distance to the plane reaches +-r while the touching point is inside.
  Vec3 normal = (b - a).cross(c - a);
  const Real normal_length = normal.norm();
  if (normal_length > 0) {
    normal /= normal_length;
    const Real s0 = (c0 - a).dot(normal);
    const Real s1 = (c1 - a).dot(normal);
    if (std::abs(s0) >= r) {
      const Real target = s0 > 0 ? r : -r;
      if ((s1 - target) * target < 0) {  // moves to within r of the plane
        const Real t = (s0 - target) / (s0 - s1);
        const Vec3 touch = c0 + t * D - target * normal;
        const Vec3 w = closest_point_barycentric(touch, a, b, c);
        const Real scale = r + (b - a).norm() + (c - a).norm();
        if ((w[0] * a + w[1] * b + w[2] * c - touch).norm() <= 1e-12 * scale) {
          best = t;
          best_w = w;
        }
      }
    }
  }

  // Edges: the centre reaches distance r from the edge's line (a cylinder) within the edge.
  const Vec3 corners[3] = {a, b, c};
  for (int e = 0; e < 3; ++e) {
    const int i = e;
    const int j = (e + 1) % 3;
    const Vec3 edge = corners[j] - corners[i];
    const Real edge2 = edge.squaredNorm();
    if (!(edge2 > 0)) continue;
    const Vec3 m = c0 - corners[i];
    const Vec3 m_perp = m - (m.dot(edge) / edge2) * edge;
    const Vec3 D_perp = D - (D.dot(edge) / edge2) * edge;
    const Real C = m_perp.squaredNorm() - r * r;
    Real t = 0;
    // C <= 0: inside the infinite cylinder but beyond the edge's ends at c0 (the initial test
    // found no contact): the first contact, if any, is with an end vertex.
    if (C <= 0 || !entry_time(D_perp.squaredNorm(), 2 * m_perp.dot(D_perp), C, t)) continue;
    const Real u = (m + t * D).dot(edge) / edge2;
    if (u < 0 || u > 1 || t >= best) continue;
    best = t;
    best_w = Vec3::Zero();
    best_w[i] = 1 - u;
    best_w[j] = u;
  }

  // Vertices: the centre reaches distance r from a corner.
  for (int i = 0; i < 3; ++i) {
    const Vec3 m = c0 - corners[i];
    Real t = 0;
    if (!entry_time(D.squaredNorm(), 2 * m.dot(D), m.squaredNorm() - r * r, t) || t >= best) {
      continue;
    }
    best = t;
    best_w = Vec3::Zero();
    best_w[i] = 1;
  }
  if (!(best <= 1)) return false;
  contact.time = best;
  contact.barycentric = best_w;
  return true;
}

}  // namespace incise::sim::collide
