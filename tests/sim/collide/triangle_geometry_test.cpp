// The triangle kernels against dense sampling of the same distances (a brute-force minimum over
// a fine barycentric grid) on random triangles, and the plane crossing time in closed form.

#include "sim/collide/triangle_geometry.h"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

namespace incise::sim::collide {
namespace {

constexpr int kGrid = 120;  // barycentric samples per edge

Vec3 random_point(std::mt19937& random, Real scale) {
  std::uniform_real_distribution<Real> uniform(-scale, scale);
  return Vec3(uniform(random), uniform(random), uniform(random));
}

// min over the sampled triangle of distance(q, .); the sampling error is at most the grid step.
Real sampled_distance(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  Real best = std::numeric_limits<Real>::infinity();
  for (int i = 0; i <= kGrid; ++i) {
    for (int j = 0; i + j <= kGrid; ++j) {
      const Real u = Real(i) / kGrid;
      const Real v = Real(j) / kGrid;
      best = std::min(best, (q - ((1 - u - v) * a + u * b + v * c)).norm());
    }
  }
  return best;
}

Real grid_step(const Vec3& a, const Vec3& b, const Vec3& c) {
  return std::max({(b - a).norm(), (c - a).norm(), (c - b).norm()}) / kGrid;
}

TEST(TriangleGeometry, ClosestPointIsNoFartherThanAnySampleAndIsOnTheTriangle) {
  std::mt19937 random(11);
  for (int trial = 0; trial < 60; ++trial) {
    const Vec3 a = random_point(random, 1), b = random_point(random, 1),
               c = random_point(random, 1);
    const Vec3 q = random_point(random, 2);
    const Vec3 w = closest_point_barycentric(q, a, b, c);
    EXPECT_NEAR(w.sum(), 1, 1e-12);
    EXPECT_GE(w.minCoeff(), -1e-12);
    const Real ours = (q - (w[0] * a + w[1] * b + w[2] * c)).norm();
    const Real sampled = sampled_distance(q, a, b, c);
    EXPECT_LE(ours, sampled + 1e-12);
    EXPECT_GE(ours, sampled - grid_step(a, b, c));
  }
}

TEST(TriangleGeometry, ClosestPointRegionsInClosedForm) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // Above the face: the foot of the perpendicular.
  EXPECT_TRUE(
      closest_point_barycentric(Vec3(0.2, 0.3, 5), a, b, c).isApprox(Vec3(0.5, 0.2, 0.3), 1e-14));
  // Beyond edge bc: the projection onto the line x + y = 1.
  EXPECT_TRUE(closest_point_barycentric(Vec3(1, 1, -2), a, b, c).isApprox(Vec3(0, 0.5, 0.5)));
  // Beyond vertex b.
  EXPECT_TRUE(closest_point_barycentric(Vec3(3, -1, 1), a, b, c).isApprox(Vec3(0, 1, 0)));
  // A collapsed triangle (all on a line) falls back to its edges.
  const Vec3 w = closest_point_barycentric(Vec3(0.5, 1, 0), a, b, Vec3(2, 0, 0));
  EXPECT_TRUE(w.allFinite());
  EXPECT_NEAR((w[0] * a + w[1] * b + w[2] * Vec3(2, 0, 0) - Vec3(0.5, 0, 0)).norm(), 0, 1e-14);
}

TEST(TriangleGeometry, SegmentTriangleClosestMatchesSampling) {
  std::mt19937 random(12);
  for (int trial = 0; trial < 40; ++trial) {
    const Vec3 a = random_point(random, 1), b = random_point(random, 1),
               c = random_point(random, 1);
    const Vec3 p0 = random_point(random, 1.5), p1 = random_point(random, 1.5);
    const SegmentTriangleClosest closest = segment_triangle_closest(p0, p1, a, b, c);
    Real sampled = std::numeric_limits<Real>::infinity();
    for (int k = 0; k <= 200; ++k) {
      const Vec3 q = p0 + (Real(k) / 200) * (p1 - p0);
      const Vec3 w = closest_point_barycentric(q, a, b, c);
      sampled = std::min(sampled, (q - (w[0] * a + w[1] * b + w[2] * c)).norm());
    }
    const Vec3& w = closest.barycentric;
    const Vec3 on_segment = p0 + closest.s * (p1 - p0);
    EXPECT_NEAR((on_segment - (w[0] * a + w[1] * b + w[2] * c)).norm(), closest.distance, 1e-12);
    EXPECT_LE(closest.distance, sampled + 1e-12);
    EXPECT_GE(closest.distance, sampled - (p1 - p0).norm() / 200);
    if (closest.pierces) {
      EXPECT_EQ(closest.distance, 0);
    }
  }
}

TEST(TriangleGeometry, SegmentThroughTheFacePierces) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  const SegmentTriangleClosest closest =
      segment_triangle_closest(Vec3(0.25, 0.25, 1), Vec3(0.25, 0.25, -3), a, b, c);
  EXPECT_TRUE(closest.pierces);
  EXPECT_NEAR(closest.s, 0.25, 1e-15);
  EXPECT_TRUE(closest.barycentric.isApprox(Vec3(0.5, 0.25, 0.25)));
}

// Rounding grows with the coordinates: a triangle far smaller than its distance from the origin,
// pierced inside, is pierced (a 0.5 mm crack piece of a cut at 5 cm was once taken for a miss at
// 0.05 mm, its edge's distance).
TEST(TriangleGeometry, ASmallTriangleFarFromTheOriginIsPiercedToo) {
  const SegmentTriangleClosest crack_piece =
      segment_triangle_closest(Vec3(0.0437, 0.0298, 0.02), Vec3(0.0437, 0.0298, 0.04),
                               Vec3(0.043830000000000008, 0.029483000000000006, 0.03),
                               Vec3(0.0437, 0.03, 0.03), Vec3(0.04, 0.03, 0.03));
  EXPECT_TRUE(crack_piece.pierces);
  EXPECT_EQ(crack_piece.distance, 0);
  EXPECT_NEAR(crack_piece.s, 0.5, 1e-12);
  std::mt19937 random(5);
  for (const Real offset : {0.05, 1.0, 30.0}) {
    for (const Real size : {1e-4, 1e-3, 1e-2}) {
      for (int trial = 0; trial < 50; ++trial) {
        const Vec3 centre = offset * random_point(random, 1).normalized();
        const Vec3 a = centre + size * random_point(random, 1);
        const Vec3 b = centre + size * random_point(random, 1);
        const Vec3 c = centre + size * random_point(random, 1);
        const Vec3 n = (b - a).cross(c - a).normalized();
        const Vec3 inside = 0.3 * a + 0.3 * b + 0.4 * c;
        const Vec3 along = (n + 0.5 * random_point(random, 1)).normalized();
        const SegmentTriangleClosest closest =
            segment_triangle_closest(inside - size * along, inside + 2 * size * along, a, b, c);
        EXPECT_TRUE(closest.pierces) << "offset " << offset << ", size " << size;
        EXPECT_EQ(closest.distance, 0);
        EXPECT_NEAR(closest.s, 1.0 / 3, 1e-6);
      }
    }
  }
}

TEST(TriangleGeometry, SweepHitsThePlaneAtTheClosedFormTime) {
  const Vec3 a(-1, -1, 0), b(1, -1, 0), c(0, 1, 0);
  const Real r = 0.01, d0 = 0.3, d1 = -0.2;
  SweepContact contact;
  ASSERT_TRUE(sweep_sphere_triangle(Vec3(0, 0, d0), Vec3(0.01, 0, d1), r, a, b, c, contact));
  const Real t = (d0 - r) / (d0 - d1);
  EXPECT_NEAR(contact.time, t, 1e-15);
  // From below (a sheet has two sides).
  ASSERT_TRUE(sweep_sphere_triangle(Vec3(0, 0, -d0), Vec3(0, 0, -d1), r, a, b, c, contact));
  EXPECT_NEAR(contact.time, t, 1e-15);
  // Already touching.
  ASSERT_TRUE(sweep_sphere_triangle(Vec3(0, 0, 0.5 * r), Vec3(0, 0, 1), r, a, b, c, contact));
  EXPECT_EQ(contact.time, 0);
  // Moving away, or passing beside.
  EXPECT_FALSE(sweep_sphere_triangle(Vec3(0, 0, d0), Vec3(0, 0, 1), r, a, b, c, contact));
  EXPECT_FALSE(sweep_sphere_triangle(Vec3(3, 0, d0), Vec3(3, 0, d1), r, a, b, c, contact));
}

TEST(TriangleGeometry, SweepTimeIsTheFirstTouchOfSampledMotion) {
  // At the returned time the distance is r; at every earlier sampled time it is more than r.
  std::mt19937 random(13);
  int hits = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a = random_point(random, 1), b = random_point(random, 1),
               c = random_point(random, 1);
    const Vec3 c0 = random_point(random, 2), c1 = random_point(random, 2);
    const Real r = 0.2;
    const auto distance = [&](Real t) {
      const Vec3 q = c0 + t * (c1 - c0);
      const Vec3 w = closest_point_barycentric(q, a, b, c);
      return (q - (w[0] * a + w[1] * b + w[2] * c)).norm();
    };
    SweepContact contact;
    const bool hit = sweep_sphere_triangle(c0, c1, r, a, b, c, contact);
    Real first_sampled = 2;
    for (int k = 0; k <= 400; ++k) {
      if (distance(Real(k) / 400) <= r) {
        first_sampled = Real(k) / 400;
        break;
      }
    }
    if (!hit) {
      EXPECT_EQ(first_sampled, 2) << "trial " << trial;
      continue;
    }
    ++hits;
    if (contact.time > 0) {
      EXPECT_NEAR(distance(contact.time), r, 1e-9) << "trial " << trial;
    }
    EXPECT_LE(contact.time, first_sampled + 1e-12) << "trial " << trial;
    const Vec3& w = contact.barycentric;
    const Vec3 q = c0 + contact.time * (c1 - c0);
    EXPECT_NEAR((q - (w[0] * a + w[1] * b + w[2] * c)).norm(), distance(contact.time), 1e-9);
  }
  EXPECT_GT(hits, 20);
}

}  // namespace
}  // namespace incise::sim::collide
