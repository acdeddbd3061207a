#include "sim/models/spring_force.h"

#include <gtest/gtest.h>

namespace incise::sim {
namespace {

const Vec3 kRest = Vec3::Zero();

TEST(SpringForce, StretchedSpringPullsBackWithHookeMagnitude) {
  const Vec3 xi(0.1, 0.2, 0.3);
  const Vec3 direction = Vec3(1, 2, -2) / 3;  // unit
  const Real l0 = 0.5;
  const Real k = 40;
  const Vec3 xj = xi + 0.6 * direction;  // stretched by 0.1
  const SpringForce f = spring_force(xi, xj, kRest, kRest, k, 0, l0);
  EXPECT_FALSE(f.degenerate);
  // Node i is pulled towards j, i.e. against the stretch, by k (l - l0).
  EXPECT_TRUE(f.on_i.isApprox(k * 0.1 * direction, 1e-12));
}

TEST(SpringForce, CompressedSpringPushesApart) {
  const Vec3 xi(0, 0, 0);
  const Vec3 xj(0, 0.3, 0);
  const SpringForce f = spring_force(xi, xj, kRest, kRest, 10, 0, 0.5);
  EXPECT_TRUE(f.on_i.isApprox(Vec3(0, -10 * 0.2, 0), 1e-12));
}

TEST(SpringForce, AtRestLengthAndStillThereIsNoForce) {
  const SpringForce f = spring_force(Vec3(1, 1, 1), Vec3(1, 1, 1.5), kRest, kRest, 10, 3, 0.5);
  EXPECT_TRUE(f.on_i.isZero(0));
}

TEST(SpringForce, DamperResistsTheRateOfStretchOnly) {
  const Vec3 xi(0, 0, 0);
  const Vec3 xj(2, 0, 0);  // at rest length
  const Real c = 3;
  // j moving away from i at 0.5 m/s: i is dragged along, with c * 0.5.
  const SpringForce separating = spring_force(xi, xj, kRest, Vec3(0.5, 0, 0), 10, c, 2);
  EXPECT_TRUE(separating.on_i.isApprox(Vec3(c * 0.5, 0, 0), 1e-12));
  // Sideways relative motion does not change the length: no damping force.
  const SpringForce sideways = spring_force(xi, xj, kRest, Vec3(0, 0.7, -0.2), 10, c, 2);
  EXPECT_TRUE(sideways.on_i.isZero(0));
  // A common velocity is a rigid translation: no force either.
  const Vec3 common(0.3, -0.4, 0.9);
  EXPECT_TRUE(spring_force(xi, xj, common, common, 10, c, 2).on_i.isZero(0));
}

TEST(SpringForce, CoincidentNodesAreReportedNotDividedBy) {
  const SpringForce f = spring_force(Vec3(1, 2, 3), Vec3(1, 2, 3), kRest, Vec3(1, 0, 0), 10, 3, 1);
  EXPECT_TRUE(f.degenerate);
  EXPECT_TRUE(f.on_i.isZero(0));
}

}  // namespace
}  // namespace incise::sim
