// The pen device: devices/pen_device.h. Every expectation is a closed form or an identity
// (round trips, virtual work), checked over many random configurations.

#include "devices/pen_device.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "devices/device_state.h"
#include "devices/eigen_conversions.h"
#include "devices/portal_scope.h"  // kDegree
#include "kinematics_fixtures.h"

namespace incise::devices {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;

TEST(PenDevice, FollowsTheDocumentedConvention) {
  const PenDevice pen;
  const double a = 0.4;
  const auto axis = [&](double yaw, double pitch, double roll) {
    return Vector3d(to_eigen(pen.forward({{}, yaw, pitch, roll}).orientation) * Vector3d::UnitZ());
  };
  EXPECT_LT((axis(a, 0, 0) - Vector3d(std::sin(a), 0, std::cos(a))).norm(), 1e-15);
  EXPECT_LT((axis(0, a, 0) - Vector3d(0, -std::sin(a), std::cos(a))).norm(), 1e-15);
  EXPECT_LT((axis(0, 0, a) - Vector3d::UnitZ()).norm(), 1e-15);  // roll turns the pen in place
  const PenPose pose = pen.forward({{0.01, 0.02, 0.03}, a, a, a});
  EXPECT_EQ(pose.position, (Vec3{0.01, 0.02, 0.03}));
}

TEST(PenDevice, JointsToPoseToJointsRoundTripsAwayFromGimbalLock) {
  const PenDevice pen;
  Random random(13);
  for (int trial = 0; trial < 1000; ++trial) {
    const PenJoints joints{to_vec3(random.vector(0.1)), random.uniform(-kPi, kPi),
                           random.uniform(-80 * kDegree, 80 * kDegree), random.uniform(-kPi, kPi)};
    const PenJoints back = pen.inverse(pen.forward(joints));
    EXPECT_EQ(back.position, joints.position);
    EXPECT_NEAR(back.yaw, joints.yaw, 1e-9);
    EXPECT_NEAR(back.pitch, joints.pitch, 1e-9);
    EXPECT_NEAR(back.roll, joints.roll, 1e-9);
  }
}

TEST(PenDevice, PoseToJointsToPoseRoundTripsEverywhere) {
  const PenDevice pen;
  Random random(14);
  std::vector<Quaterniond> rotations;
  for (int trial = 0; trial < 1000; ++trial)
    rotations.push_back(random.rotation());
  // Exactly at and next to gimbal lock, where yaw and roll turn about the same axis.
  for (double pitch : {kPi / 2, -kPi / 2, kPi / 2 - 1e-10, -kPi / 2 + 1e-7}) {
    rotations.push_back(to_eigen(pen.forward({{}, 0.7, pitch, -0.3}).orientation));
  }
  // At lock exactly, the documented split: no yaw, the whole turn in roll. At pitch = +90 deg
  // Rx(90) Rz(r) = Ry(-r) Rx(90), so Ry(0.7) Rx(90) Rz(-0.3) = Rx(90) Rz(-0.3 - 0.7).
  const PenJoints locked = pen.inverse({{}, to_quat(rotations[1000])});
  EXPECT_EQ(locked.yaw, 0.0);
  EXPECT_NEAR(locked.roll, -1.0, 1e-12);
  for (const Quaterniond& q : rotations) {
    const PenJoints joints = pen.inverse({{}, to_quat(q)});
    EXPECT_GE(joints.pitch, -kPi / 2);
    EXPECT_LE(joints.pitch, kPi / 2);
    EXPECT_LT(to_eigen(pen.forward(joints).orientation).angularDistance(q), 1e-9);
  }
}

TEST(PenDevice, ForceActsFullyOnTheTranslationalAxesAndTorqueIsDropped) {
  const PenDevice pen;
  Random random(15);
  for (int trial = 0; trial < 100; ++trial) {
    const Vector3d f = random.vector(3.0), torque = random.vector(0.1);
    const PenForces forces = pen.joint_forces(to_vec3(f), to_vec3(torque));
    // The translational axes are the tool point's x, y, z (J = [I 0]), so J^T F = F and the
    // virtual work of any translation is the same on the device as in the scene.
    const Vector3d dx = random.vector(1e-3);
    EXPECT_NEAR(to_eigen(forces.axis_forces_n).dot(dx), f.dot(dx), 1e-15);
    EXPECT_EQ(forces.axis_forces_n, to_vec3(f));
    EXPECT_EQ(forces.dropped_torque_nm, to_vec3(torque));
  }
  EXPECT_EQ(pen.joint_forces({1, 2, 3}).dropped_torque_nm, Vec3{});
}

}  // namespace
}  // namespace incise::devices
