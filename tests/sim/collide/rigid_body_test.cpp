// RigidBody (FCL) against closed forms on a box-shaped bone: sphere and capsule contacts
// (depth, normal, point) and separation distances, under a general pose; and bad input.

#include "sim/collide/rigid_body.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <gtest/gtest.h>

#include "collide_fixtures.h"

namespace incise::sim::collide {
namespace {

// A 4 x 4 x 1 cm bone slab whose top face is z = 0 in the body frame.
testing::TestSurface slab() {
  return testing::box_hull(Vec3(-0.02, -0.02, -0.01), Vec3(0.02, 0.02, 0));
}

Eigen::Isometry3d some_pose() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.7, Vec3(1, 2, -0.5).normalized()).toRotationMatrix();
  pose.translation() = Vec3(0.1, -0.05, 0.2);
  return pose;
}

const Contact& deepest(const std::vector<Contact>& contacts) {
  return *std::max_element(contacts.begin(), contacts.end(),
                           [](const Contact& a, const Contact& b) { return a.depth < b.depth; });
}

class RigidBodyTest : public ::testing::TestWithParam<bool> {
 protected:
  // The pose of the parameter (identity or a general one); every closed form is stated in the
  // body frame and mapped by it.
  Eigen::Isometry3d pose() const {
    return GetParam() ? some_pose() : Eigen::Isometry3d::Identity();
  }
  RigidBody body() const {
    const testing::TestSurface hull = slab();
    return RigidBody(hull.points, hull.triangles, pose());
  }
};

TEST_P(RigidBodyTest, SphereOnTheTopFace) {
  const RigidBody bone = body();
  const Real r = 0.005, h = 0.002;
  const Vec3 foot(0.0031, 0.0052, 0);
  std::vector<Contact> contacts;
  bone.contacts(Sphere{pose() * Vec3(foot + Vec3(0, 0, h)), r}, contacts);
  ASSERT_FALSE(contacts.empty());
  const Contact& best = deepest(contacts);
  EXPECT_NEAR(best.depth, r - h, 1e-9);
  EXPECT_TRUE(best.normal.isApprox(pose().linear() * Vec3::UnitZ(), 1e-6));
  EXPECT_LT((best.point - pose() * foot).norm(), 1e-6);
  EXPECT_TRUE(best.triangle >= 2 && best.triangle <= 3);  // the top face's two triangles
  EXPECT_NEAR(best.barycentric.sum(), 1, 1e-12);
}

TEST_P(RigidBodyTest, CapsuleOnTheTopFace) {
  const RigidBody bone = body();
  const Real r = 0.003;
  // Tilted, the lower end at height h_a above the face.
  const Vec3 a(0.0021, -0.0013, 0.001);
  const Vec3 b(0.006, 0.004, 0.02);
  std::vector<Contact> contacts;
  bone.contacts(Capsule{pose() * a, pose() * b, r}, contacts);
  ASSERT_FALSE(contacts.empty());
  const Contact& best = deepest(contacts);
  EXPECT_NEAR(best.depth, r - a.z(), 1e-6);
  EXPECT_TRUE(best.normal.isApprox(pose().linear() * Vec3::UnitZ(), 1e-4));
}

TEST_P(RigidBodyTest, SeparationDistances) {
  const RigidBody bone = body();
  const Real r = 0.004, h = 0.01;
  const Vec3 foot(-0.0042, 0.0071, 0);
  const RigidDistance sphere = bone.distance(Sphere{pose() * Vec3(foot + Vec3(0, 0, h)), r});
  EXPECT_NEAR(sphere.distance, h - r, 1e-9);
  EXPECT_LT((sphere.point_on_body - pose() * foot).norm(), 1e-7);
  EXPECT_LT((sphere.point_on_tool - pose() * Vec3(foot + Vec3(0, 0, h - r))).norm(), 1e-7);
  // Beside the slab, off its x = 0.02 side by 5 mm: distance 5 mm - r.
  const RigidDistance side =
      bone.distance(Sphere{pose() * Vec3(0.025 + 0.0, 0.001, -0.004), 0.002});
  EXPECT_NEAR(side.distance, 0.005 - 0.002, 1e-9);
  // A capsule above the face with its lower end at height h_a.
  const RigidDistance capsule =
      bone.distance(Capsule{pose() * Vec3(0.001, 0.002, 0.007), pose() * Vec3(0.01, 0.0, 0.03), r});
  EXPECT_NEAR(capsule.distance, 0.007 - r, 1e-7);
  // Touching: distance 0.
  EXPECT_EQ(bone.distance(Sphere{pose() * Vec3(0, 0, 0.001), r}).distance, 0);
}

INSTANTIATE_TEST_SUITE_P(Poses, RigidBodyTest, ::testing::Values(false, true));

TEST(RigidBody, AFarToolHasNoContact) {
  const testing::TestSurface hull = slab();
  const RigidBody bone(hull.points, hull.triangles);
  std::vector<Contact> contacts{Contact{}};
  bone.contacts(Sphere{Vec3(0, 0, 0.05), 0.01}, contacts);
  EXPECT_TRUE(contacts.empty());
  bone.contacts(Capsule{Vec3(0, 0, 0.05), Vec3(0.01, 0, 0.06), 0.01}, contacts);
  EXPECT_TRUE(contacts.empty());
}

TEST(RigidBody, BadInputIsRejectedWithAPreciseMessage) {
  const testing::TestSurface hull = slab();
  const auto message = [](auto&& make) {
    try {
      make();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  EXPECT_EQ(message([&] { RigidBody(Points(0, 3), hull.triangles); }),
            "RigidBody: the mesh has no vertices");
  EXPECT_EQ(message([&] { RigidBody(hull.points, Triangles(0, 3)); }),
            "RigidBody: the mesh has no triangles");
  Triangles bad = hull.triangles;
  bad(5, 2) = 8;
  EXPECT_EQ(message([&] { RigidBody(hull.points, bad); }),
            "RigidBody: triangle 5 has index 8 outside [0, 8)");
  Points nan_points = hull.points;
  nan_points(6, 0) = std::numeric_limits<Real>::quiet_NaN();
  EXPECT_EQ(message([&] { RigidBody(nan_points, hull.triangles); }),
            "RigidBody: vertex 6 is not finite");
  RigidBody bone(hull.points, hull.triangles);
  std::vector<Contact> contacts;
  EXPECT_EQ(message([&] {
              bone.contacts(Sphere{Vec3::Zero(), 0}, contacts);
            }),
            "RigidBody::contacts: the tool radius must be finite and > 0, got 0.000000");
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose(0, 3) = std::numeric_limits<Real>::infinity();
  EXPECT_THROW(bone.set_pose(pose), std::invalid_argument);
}

}  // namespace
}  // namespace incise::sim::collide
