// make_jaw_pair against its closed form, and the test surfaces' orientation (every fixture
// surface is closed or flat with outward normals, which the contact rule depends on).

#include "sim/collide/tool_shapes.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <gtest/gtest.h>

#include "collide_fixtures.h"

namespace incise::sim::collide {
namespace {

TEST(ToolShapes, JawPairOpensSymmetricallyInThePlaneOfTheNormal) {
  const Vec3 pivot(0.01, -0.02, 0.03);
  const Real angle = std::numbers::pi / 3;
  // The opening normal need not be orthogonal to the axis or unit: only its orthogonal part
  // counts.
  const JawPair pair = make_jaw_pair(pivot, Vec3(0, 0, -2), Vec3(0, 3, 1), angle, 0.02, 0.001);
  const Real s = 0.02 * std::sin(angle / 2);
  const Real c = 0.02 * std::cos(angle / 2);
  for (const Capsule& jaw : pair.jaws) {
    EXPECT_EQ(jaw.a, pivot);
    EXPECT_EQ(jaw.radius, 0.001);
    EXPECT_NEAR((jaw.b - jaw.a).norm(), 0.02, 1e-15);
  }
  EXPECT_TRUE(pair.jaws[0].b.isApprox(pivot + Vec3(0, s, -c), 1e-14));
  EXPECT_TRUE(pair.jaws[1].b.isApprox(pivot + Vec3(0, -s, -c), 1e-14));
  // The angle between the jaws is the opening angle.
  const Vec3 u = (pair.jaws[0].b - pivot).normalized();
  const Vec3 v = (pair.jaws[1].b - pivot).normalized();
  EXPECT_NEAR(std::acos(u.dot(v)), angle, 1e-12);
  // Closed: both jaws on the axis.
  const JawPair closed = make_jaw_pair(pivot, Vec3(1, 0, 0), Vec3(0, 1, 0), 0, 0.02, 0.001);
  EXPECT_TRUE(closed.jaws[0].b.isApprox(closed.jaws[1].b));
}

TEST(ToolShapes, JawPairRejectsBadInput) {
  const Vec3 p = Vec3::Zero();
  EXPECT_THROW(make_jaw_pair(p, Vec3::Zero(), Vec3(0, 1, 0), 0.1, 0.02, 0.001),
               std::invalid_argument);
  EXPECT_THROW(make_jaw_pair(p, Vec3(1, 0, 0), Vec3(2, 0, 0), 0.1, 0.02, 0.001),
               std::invalid_argument);
  EXPECT_THROW(make_jaw_pair(p, Vec3(1, 0, 0), Vec3(0, 1, 0), std::numbers::pi, 0.02, 0.001),
               std::invalid_argument);
  EXPECT_THROW(make_jaw_pair(p, Vec3(1, 0, 0), Vec3(0, 1, 0), 0.1, 0, 0.001),
               std::invalid_argument);
  EXPECT_THROW(make_jaw_pair(p, Vec3(1, 0, 0), Vec3(0, 1, 0), 0.1, 0.02, -1),
               std::invalid_argument);
}

// Enclosed volume by the divergence theorem: sum over triangles of a . (b x c) / 6.
Real enclosed_volume(const testing::TestSurface& s) {
  Real volume = 0;
  for (int t = 0; t < s.triangles.rows(); ++t) {
    volume += row3(s.points, s.triangles(t, 0))
                  .dot(row3(s.points, s.triangles(t, 1)).cross(row3(s.points, s.triangles(t, 2))));
  }
  return volume / 6;
}

TEST(CollideFixtures, ClosedSurfacesAreOrientedOutwards) {
  EXPECT_NEAR(enclosed_volume(testing::box_hull(Vec3(-1, -2, 0), Vec3(1, 2, 3))), 24, 1e-12);
  // The sag lowers the top, so the deformed box encloses a bit less than its 24 m^3.
  const Real box =
      enclosed_volume(testing::deformed_box_surface(Vec3(2, 3, 4), Vec3i(2, 3, 4), 0, 1));
  EXPECT_GT(box, 22);
  EXPECT_LT(box, 24);
  const Real sphere =
      enclosed_volume(testing::jittered_sphere_surface(Vec3(1, 2, 3), 1, 40, 60, 0, 1));
  EXPECT_NEAR(sphere, 4 * std::numbers::pi / 3, 0.02);
}

}  // namespace
}  // namespace incise::sim::collide
