#include "sim/mesh/cgal/implicit_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace incise::sim {
namespace {

// Points of a regular n^3 grid over box.
template <typename F>
void for_grid(const Box3& box, int n, F&& f) {
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Vec3 s = (Vec3(i, j, k) + Vec3::Constant(0.5)) / n;
        f(Vec3(box.min() + s.cwiseProduct(box.sizes())));
      }
}

TEST(ImplicitShape, SphereValueIsTheSignedDistance) {
  const Sphere s{Vec3(0.1, -0.2, 0.3), 0.05};
  const Vec3 dir = Vec3(1, 2, -2).normalized();
  for (Real d : {-0.05, -0.01, 0.0, 0.02, 0.3}) {
    EXPECT_NEAR(implicit_value(s, s.centre + (s.radius + d) * dir), d, 1e-15);
  }
}

TEST(ImplicitShape, EllipsoidIsZeroOnItsSurfaceAndSignedAcrossIt) {
  const Ellipsoid e{Vec3(0.0, 0.01, -0.02), Vec3(0.06, 0.04, 0.03)};
  for (const Vec3& u :
       {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(1, 1, 1).normalized(), Vec3(-2, 1, 3).normalized()}) {
    const Vec3 on = e.centre + e.radii.cwiseProduct(u);  // |(p - c) / r| = 1
    EXPECT_NEAR(implicit_value(e, on), 0, 1e-15);
    EXPECT_LT(implicit_value(e, e.centre + 0.9 * (on - e.centre)), 0);
    EXPECT_GT(implicit_value(e, e.centre + 1.1 * (on - e.centre)), 0);
  }
  // Along a semi-axis the estimate is the exact distance.
  EXPECT_NEAR(implicit_value(e, e.centre + Vec3(0, 0, 0.04)), 0.01, 1e-15);
  EXPECT_NEAR(implicit_value(e, e.centre), -0.03, 1e-15);
}

TEST(ImplicitShape, BlendOnlyAddsMaterialAndOnlyNearCreases) {
  const Ellipsoid a{Vec3(-0.03, 0, 0), Vec3(0.05, 0.03, 0.03)};
  const Ellipsoid b{Vec3(0.03, 0, 0), Vec3(0.04, 0.04, 0.02)};
  const EllipsoidBlend blend{{a, b}, 0.01};
  const Box3 box = implicit_extent(blend);
  int filled = 0;
  for_grid(Box3(Vec3(-0.1, -0.06, -0.05), Vec3(0.1, 0.06, 0.05)), 24, [&](const Vec3& p) {
    const Real fa = implicit_value(a, p);
    const Real fb = implicit_value(b, p);
    const Real f = implicit_value(blend, p);
    EXPECT_LE(f, std::min(fa, fb));
    EXPECT_GE(f, std::min(fa, fb) - blend.blend_radius / 4);
    if (std::abs(fa - fb) >= blend.blend_radius) {
      EXPECT_EQ(f, std::min(fa, fb));
    }
    if (f < 0) {
      EXPECT_TRUE(box.contains(p));
    }
    if (f < 0 && fa >= 0 && fb >= 0) ++filled;
  });
  EXPECT_GT(filled, 0);  // the fillet exists
}

TEST(ImplicitShape, LiverLikeOrganIsFlatBelowAndInsideItsExtent) {
  const LobedOrgan organ = liver_like_organ(Vec3(0, 0, 0), 0.2);
  ASSERT_EQ(organ.lobes.parts.size(), 3u);
  const Box3 box = implicit_extent(organ);
  EXPECT_EQ(box.min().z(), organ.flat_side_z);
  int inside = 0;
  for_grid(Box3(Vec3(-0.15, -0.1, -0.06), Vec3(0.15, 0.1, 0.06)), 30, [&](const Vec3& p) {
    const Real f = implicit_value(organ, p);
    if (p.z() < organ.flat_side_z) {
      EXPECT_GT(f, 0);
    }
    if (f < 0) {
      ++inside;
      EXPECT_TRUE(box.contains(p));
    }
  });
  EXPECT_GT(inside, 100);
}

TEST(ImplicitShape, InvalidShapesAreRejectedWithTheReason) {
  const auto message = [](const ImplicitShape& s) {
    try {
      check_implicit_shape(s);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(Sphere{Vec3::Zero(), 0}).find("radius"), std::string::npos);
  EXPECT_NE(message(Sphere{Vec3(NAN, 0, 0), 1}).find("centre"), std::string::npos);
  EXPECT_NE(message(Ellipsoid{Vec3::Zero(), Vec3(1, -1, 1)}).find("radii"), std::string::npos);
  EXPECT_NE(message(EllipsoidBlend{{}, 0.1}).find("at least one part"), std::string::npos);
  EXPECT_NE(message(EllipsoidBlend{{Ellipsoid{Vec3::Zero(), Vec3::Ones()}}, -1}).find("blend"),
            std::string::npos);
  LobedOrgan cut_away = liver_like_organ(Vec3::Zero(), 1);
  cut_away.flat_side_z = 10;
  EXPECT_NE(message(cut_away).find("nothing is left"), std::string::npos);
  EXPECT_EQ(message(liver_like_organ(Vec3::Zero(), 1)), "no error");
}

}  // namespace
}  // namespace incise::sim
