// The portal scope: devices/portal_scope.h. Every expectation is a closed form or an identity
// (round trips, virtual work, the fulcrum), checked over many random configurations.

#include "devices/portal_scope.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "devices/eigen_conversions.h"
#include "kinematics_fixtures.h"

namespace incise::devices {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;

double angle_between(const Vector3d& a, const Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

ScopeJoints random_joints(Random& random, const ScopeGeometry& g) {
  return {random.uniform(g.min_pitch, g.max_pitch), random.uniform(g.min_yaw, g.max_yaw),
          random.uniform(g.min_insertion, g.max_insertion), random.uniform(-kPi, kPi)};
}

Vector3d shaft_axis(const ScopePose& pose) {
  return to_eigen(pose.shaft) * Vector3d::UnitZ();
}

TEST(PortalScope, ForwardFollowsTheDocumentedConvention) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  const Quaterniond p = to_eigen(g.portal_orientation);
  const Vector3d portal = to_eigen(g.portal);
  const double l = 0.07;
  // At rest the shaft runs along the portal's +z.
  ScopePose pose = scope.forward({0.0, 0.0, l, 0.0});
  EXPECT_LT((to_eigen(pose.tip) - (portal + l * (p * Vector3d::UnitZ()))).norm(), 1e-15);
  // Yaw tilts toward +x of the portal, pitch toward -y.
  const double a = 0.3;
  pose = scope.forward({0.0, a, l, 0.0});
  EXPECT_LT((shaft_axis(pose) - p * Vector3d(std::sin(a), 0, std::cos(a))).norm(), 1e-15);
  pose = scope.forward({a, 0.0, l, 0.0});
  EXPECT_LT((shaft_axis(pose) - p * Vector3d(0, -std::sin(a), std::cos(a))).norm(), 1e-15);
  EXPECT_EQ(pose.field_of_view, g.field_of_view);
}

TEST(PortalScope, ShaftAlwaysPassesThroughThePortal) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  Random random(5);
  for (int trial = 0; trial < 1000; ++trial) {
    const ScopeJoints joints = random_joints(random, g);
    const ScopePose pose = scope.forward(joints);
    EXPECT_LT(distance_from_shaft_line(pose, g.portal), 1e-12);
    // The same, independently: the portal sits exactly insertion behind the tip on the axis.
    const Vector3d behind = to_eigen(pose.tip) - joints.insertion * shaft_axis(pose);
    EXPECT_LT((behind - to_eigen(g.portal)).norm(), 1e-12);
  }
  // And the helper measures what it says: a point 1 cm off the axis.
  const ScopePose pose = scope.forward({0.1, 0.2, 0.05, 0.3});
  const Vector3d side = to_eigen(pose.shaft) * Vector3d::UnitX();
  const Vector3d off = to_eigen(pose.tip) - 0.02 * shaft_axis(pose) + 0.01 * side;
  EXPECT_NEAR(distance_from_shaft_line(pose, to_vec3(off)), 0.01, 1e-15);
}

TEST(PortalScope, JointsToPoseToJointsRoundTrips) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  Random random(6);
  for (int trial = 0; trial < 1000; ++trial) {
    const ScopeJoints joints = random_joints(random, g);
    const ScopeSolution solution = scope.inverse(scope.forward(joints));
    ASSERT_TRUE(solution) << describe(solution.reach);
    EXPECT_NEAR(solution.joints.pitch, joints.pitch, 1e-9);
    EXPECT_NEAR(solution.joints.yaw, joints.yaw, 1e-9);
    EXPECT_NEAR(solution.joints.insertion, joints.insertion, 1e-9);
    EXPECT_NEAR(solution.joints.roll, joints.roll, 1e-9);
    // From the tip alone, the roll is whatever we pass (wrapped into (-pi, pi]).
    const ScopeSolution from_tip = scope.inverse(scope.forward(joints).tip, joints.roll + 4 * kPi);
    ASSERT_TRUE(from_tip);
    EXPECT_NEAR(from_tip.joints.roll, joints.roll, 1e-9);
    EXPECT_NEAR(from_tip.joints.pitch, joints.pitch, 1e-9);
  }
}

TEST(PortalScope, PoseToJointsToPoseRoundTrips) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  Random random(7);
  for (int trial = 0; trial < 1000; ++trial) {
    // A pose built without the scope's own joints: a tip in the reachable cone and any roll.
    const Quaterniond p = to_eigen(g.portal_orientation);
    const ScopeJoints j = random_joints(random, g);
    const Vector3d d = p * Vector3d(std::cos(j.pitch) * std::sin(j.yaw), -std::sin(j.pitch),
                                    std::cos(j.pitch) * std::cos(j.yaw));
    const Vector3d tip = to_eigen(g.portal) + j.insertion * d;
    const ScopeSolution solution = scope.inverse(to_vec3(tip), j.roll);
    ASSERT_TRUE(solution) << describe(solution.reach);
    const ScopePose pose = scope.forward(solution.joints);
    EXPECT_LT((to_eigen(pose.tip) - tip).norm(), 1e-12);
    const ScopeSolution again = scope.inverse(pose);
    ASSERT_TRUE(again);
    const ScopePose pose_again = scope.forward(again.joints);
    EXPECT_LT((to_eigen(pose_again.tip) - to_eigen(pose.tip)).norm(), 1e-12);
    EXPECT_LT(to_eigen(pose_again.shaft).angularDistance(to_eigen(pose.shaft)), 1e-9);
    EXPECT_LT((to_eigen(pose_again.view_direction) - to_eigen(pose.view_direction)).norm(), 1e-9);
    EXPECT_LT((to_eigen(pose_again.view_up) - to_eigen(pose.view_up)).norm(), 1e-9);
  }
}

TEST(PortalScope, RollComesFromTheShaftOrientation) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  const ScopePose pose = scope.forward({0.2, -0.4, 0.08, 0.0});
  // Turn the shaft orientation about its own axis: only the roll changes.
  const double turn = 1.1;
  const Quaterniond rolled =
      to_eigen(pose.shaft) * Quaterniond(Eigen::AngleAxisd(turn, Vector3d::UnitZ()));
  const ScopeSolution solution = scope.inverse(pose.tip, to_quat(rolled));
  ASSERT_TRUE(solution);
  EXPECT_NEAR(solution.joints.roll, turn, 1e-12);
  EXPECT_NEAR(solution.joints.pitch, 0.2, 1e-12);
  EXPECT_NEAR(solution.joints.yaw, -0.4, 1e-12);
}

TEST(PortalScope, JacobianMatchesCentralDifferences) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  Random random(8);
  const double h = 1e-6;
  for (int trial = 0; trial < 200; ++trial) {
    const ScopeJoints joints = random_joints(random, g);
    const Eigen::Matrix<double, 3, 4> j = scope.jacobian(joints);
    for (int column = 0; column < 4; ++column) {
      ScopeJoints plus = joints, minus = joints;
      double* plus_q[] = {&plus.pitch, &plus.yaw, &plus.insertion, &plus.roll};
      double* minus_q[] = {&minus.pitch, &minus.yaw, &minus.insertion, &minus.roll};
      *plus_q[column] += h;
      *minus_q[column] -= h;
      const Vector3d numeric =
          (to_eigen(scope.forward(plus).tip) - to_eigen(scope.forward(minus).tip)) / (2 * h);
      // Central differences err by O(h^2 |d3 tip|) plus rounding O(eps |tip| / h).
      EXPECT_LT((j.col(column) - numeric).norm(), 1e-8) << "column " << column;
    }
    EXPECT_EQ(j.col(3), Vector3d::Zero());  // roll does not move the tip
  }
}

TEST(PortalScope, JointForcesAreTheJacobianTranspose) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  Random random(9);
  for (int trial = 0; trial < 500; ++trial) {
    const ScopeJoints joints = random_joints(random, g);
    const Vector3d f = random.vector(4.0);
    const ActuatedForces tau = scope.joint_forces(joints, to_vec3(f));
    // Virtual work: F . (J dq) = tau . dq for every dq, the roll getting nothing.
    const Eigen::Vector4d dq(random.uniform(-1e-3, 1e-3), random.uniform(-1e-3, 1e-3),
                             random.uniform(-1e-3, 1e-3), random.uniform(-1, 1));
    const double work = f.dot(scope.jacobian(joints) * dq);
    EXPECT_NEAR(
        work,
        tau.pitch_torque_nm * dq[0] + tau.yaw_torque_nm * dq[1] + tau.insertion_force_n * dq[2],
        1e-15);
    // Statics about the fulcrum: the torque of F at the lever r = tip - portal about each joint
    // axis (yaw about the portal's y, pitch about the yawed x), and the shaft component.
    const Quaterniond p = to_eigen(g.portal_orientation);
    const Vector3d yaw_axis = p * Vector3d::UnitY();
    const Vector3d pitch_axis =
        p * (Eigen::AngleAxisd(joints.yaw, Vector3d::UnitY()) * Vector3d::UnitX());
    const ScopePose pose = scope.forward(joints);
    const Vector3d moment = (to_eigen(pose.tip) - to_eigen(g.portal)).cross(f);
    EXPECT_NEAR(tau.pitch_torque_nm, pitch_axis.dot(moment), 1e-12);
    EXPECT_NEAR(tau.yaw_torque_nm, yaw_axis.dot(moment), 1e-12);
    EXPECT_NEAR(tau.insertion_force_n, shaft_axis(pose).dot(f), 1e-12);
  }
}

TEST(PortalScope, ForceAlongTheShaftIsPureInsertionForce) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  Random random(10);
  for (int trial = 0; trial < 100; ++trial) {
    const ScopeJoints joints = random_joints(random, g);
    const double magnitude = random.uniform(-5.0, 5.0);
    const Vector3d f = magnitude * shaft_axis(scope.forward(joints));
    const ActuatedForces tau = scope.joint_forces(joints, to_vec3(f));
    EXPECT_NEAR(tau.insertion_force_n, magnitude, 1e-12);
    EXPECT_NEAR(tau.pitch_torque_nm, 0.0, 1e-14);
    EXPECT_NEAR(tau.yaw_torque_nm, 0.0, 1e-14);
  }
}

TEST(PortalScope, SideForceGivesTheLeverTorqueOnItsAxis) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  const Quaterniond p = to_eigen(g.portal_orientation);
  Random random(11);
  for (int trial = 0; trial < 100; ++trial) {
    const ScopeJoints joints = random_joints(random, g);
    const double l = joints.insertion, magnitude = random.uniform(0.1, 5.0);
    const Vector3d d = shaft_axis(scope.forward(joints));
    // Normal to the shaft and to the pitch axis: it only pitches, with lever L.
    const Vector3d pitch_axis =
        p * (Eigen::AngleAxisd(joints.yaw, Vector3d::UnitY()) * Vector3d::UnitX());
    ActuatedForces tau =
        scope.joint_forces(joints, to_vec3(magnitude * d.cross(pitch_axis).normalized()));
    EXPECT_NEAR(std::abs(tau.pitch_torque_nm), l * magnitude, 1e-12);
    EXPECT_NEAR(tau.yaw_torque_nm, 0.0, 1e-12);
    EXPECT_NEAR(tau.insertion_force_n, 0.0, 1e-12);
    // Normal to the shaft and to the yaw axis: it only yaws, with lever L cos(pitch), the tip's
    // distance from the yaw axis.
    const Vector3d yaw_axis = p * Vector3d::UnitY();
    tau = scope.joint_forces(joints, to_vec3(magnitude * d.cross(yaw_axis).normalized()));
    EXPECT_NEAR(std::abs(tau.yaw_torque_nm), l * std::cos(joints.pitch) * magnitude, 1e-12);
    EXPECT_NEAR(tau.pitch_torque_nm, 0.0, 1e-12);
    EXPECT_NEAR(tau.insertion_force_n, 0.0, 1e-12);
  }
}

TEST(PortalScope, RollIsFreeAndGetsNoForce) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  const Vector3d f(1.0, -2.0, 0.5);
  const ActuatedForces a = scope.joint_forces({0.1, 0.2, 0.05, 0.0}, to_vec3(f));
  const ActuatedForces b = scope.joint_forces({0.1, 0.2, 0.05, 2.0}, to_vec3(f));
  EXPECT_NEAR(a.pitch_torque_nm, b.pitch_torque_nm, 1e-15);
  EXPECT_NEAR(a.yaw_torque_nm, b.yaw_torque_nm, 1e-15);
  EXPECT_NEAR(a.insertion_force_n, b.insertion_force_n, 1e-15);
}

TEST(PortalScope, ViewIsTiltedByTheViewAngleForAnyRoll) {
  for (const double view_angle : {0.0, 30 * kDegree, 45 * kDegree, 70 * kDegree}) {
    ScopeGeometry g = tilted_geometry();
    g.view_angle = view_angle;
    const PortalScope scope(g);
    Random random(12);
    for (int trial = 0; trial < 200; ++trial) {
      const ScopeJoints joints = random_joints(random, g);
      const ScopePose pose = scope.forward(joints);
      const Vector3d d = shaft_axis(pose);
      const Vector3d view = to_eigen(pose.view_direction), up = to_eigen(pose.view_up);
      // A few ulps: the frame is the product of four rotations.
      EXPECT_NEAR(view.norm(), 1.0, 1e-14);
      EXPECT_NEAR(up.norm(), 1.0, 1e-14);
      EXPECT_NEAR(view.dot(up), 0.0, 1e-14);
      EXPECT_NEAR(angle_between(d, view), view_angle, 1e-12);
      EXPECT_NEAR(d.cross(view).dot(up), 0.0, 1e-14);  // up lies in the shaft-view plane

      // Rolling by pi mirrors the view across the shaft: the sum is 2 cos(a) d.
      ScopeJoints flipped = joints;
      flipped.roll += kPi;
      const Vector3d view_flipped = to_eigen(scope.forward(flipped).view_direction);
      EXPECT_LT((view + view_flipped - 2 * std::cos(view_angle) * d).norm(), 1e-12);
      if (view_angle > 0) {
        EXPECT_NEAR(angle_between(view, view_flipped), 2 * view_angle, 1e-9);
      }

      // Rolling by r turns the view about the shaft by r: it sweeps the cone.
      const double r = random.uniform(-3.0, 3.0);
      ScopeJoints turned = joints;
      turned.roll += r;
      const Vector3d view_turned = to_eigen(scope.forward(turned).view_direction);
      const Vector3d expected = Eigen::AngleAxisd(r, d) * view;
      EXPECT_LT((view_turned - expected).norm(), 1e-12);
    }
  }
}

TEST(PortalScope, UnreachableTipsAreRefusedWithAReason) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  const Quaterniond p = to_eigen(g.portal_orientation);
  const Vector3d portal = to_eigen(g.portal);
  const auto reach_of = [&](const Vector3d& tip) { return scope.inverse(to_vec3(tip), 0.0); };

  EXPECT_EQ(reach_of(portal).reach, ScopeReach::TipAtPortal);
  EXPECT_EQ(reach_of(portal - 0.05 * (p * Vector3d::UnitZ())).reach, ScopeReach::BehindPortal);
  EXPECT_EQ(reach_of(portal + 0.05 * (p * Vector3d::UnitX())).reach, ScopeReach::BehindPortal);

  // Directions inside the body but beyond a limit: the unclamped solution comes back.
  const auto direction = [&](double pitch, double yaw) {
    return Vector3d(p * Vector3d(std::cos(pitch) * std::sin(yaw), -std::sin(pitch),
                                 std::cos(pitch) * std::cos(yaw)));
  };
  ScopeSolution s = reach_of(portal + 0.05 * direction(45 * kDegree, 0.0));
  EXPECT_EQ(s.reach, ScopeReach::PitchOutOfRange);
  EXPECT_NEAR(s.joints.pitch, 45 * kDegree, 1e-12);
  EXPECT_FALSE(scope.within_limits(s.joints));
  EXPECT_TRUE(scope.within_limits(scope.clamp(s.joints)));
  EXPECT_EQ(scope.clamp(s.joints).pitch, g.max_pitch);

  s = reach_of(portal + 0.05 * direction(0.0, -75 * kDegree));
  EXPECT_EQ(s.reach, ScopeReach::YawOutOfRange);
  EXPECT_NEAR(s.joints.yaw, -75 * kDegree, 1e-12);
  EXPECT_EQ(scope.clamp(s.joints).yaw, g.min_yaw);

  s = reach_of(portal + 0.2 * direction(0.0, 0.0));
  EXPECT_EQ(s.reach, ScopeReach::InsertionOutOfRange);
  EXPECT_NEAR(s.joints.insertion, 0.2, 1e-12);
  s = reach_of(portal + 0.005 * direction(0.0, 0.0));
  EXPECT_EQ(s.reach, ScopeReach::InsertionOutOfRange);
  EXPECT_EQ(scope.clamp(s.joints).insertion, g.min_insertion);

  for (ScopeReach reach :
       {ScopeReach::TipAtPortal, ScopeReach::BehindPortal, ScopeReach::PitchOutOfRange,
        ScopeReach::YawOutOfRange, ScopeReach::InsertionOutOfRange}) {
    EXPECT_FALSE((ScopeSolution{reach, {}}));
    EXPECT_NE(describe(reach), describe(ScopeReach::Ok));
  }
  EXPECT_EQ(describe(ScopeReach::BehindPortal),
            "tip is on or behind the portal plane (outside the body)");
}

TEST(PortalScope, JointLimitsThemselvesAreReachable) {
  const ScopeGeometry g = tilted_geometry();
  const PortalScope scope(g);
  for (double pitch : {g.min_pitch, g.max_pitch}) {
    for (double yaw : {g.min_yaw, g.max_yaw}) {
      for (double insertion : {g.min_insertion, g.max_insertion}) {
        const ScopeSolution s = scope.inverse(scope.forward({pitch, yaw, insertion, 0.0}));
        ASSERT_TRUE(s) << describe(s.reach);
        EXPECT_TRUE(scope.within_limits(s.joints));
        EXPECT_NEAR(s.joints.pitch, pitch, 1e-12);
        EXPECT_NEAR(s.joints.yaw, yaw, 1e-12);
        EXPECT_NEAR(s.joints.insertion, insertion, 1e-12);
      }
    }
  }
}

TEST(PortalScope, FieldOfViewIsAdjustableWithinItsBounds) {
  PortalScope scope(tilted_geometry());
  scope.set_field_of_view(90 * kDegree);
  EXPECT_EQ(scope.forward({}).field_of_view, 90 * kDegree);
  scope.set_field_of_view(1.0 * kDegree);
  EXPECT_EQ(scope.geometry().field_of_view, kMinFieldOfView);
  scope.set_field_of_view(179 * kDegree);
  EXPECT_EQ(scope.geometry().field_of_view, kMaxFieldOfView);
}

TEST(PortalScope, RefusesInvalidGeometry) {
  ScopeGeometry g = tilted_geometry();
  g.max_pitch = 95 * kDegree;
  EXPECT_THROW(PortalScope{g}, std::invalid_argument);
  g = tilted_geometry();
  g.portal_orientation = {2, 0, 0, 0};
  EXPECT_THROW(PortalScope{g}, std::invalid_argument);
  EXPECT_EQ(check_scope_geometry(tilted_geometry()), "");
}

}  // namespace
}  // namespace incise::devices
