// Device kinematics: devices/kinematics.h. Every expectation is a closed form or an identity
// (round trips, virtual work, the fulcrum), checked over many random configurations.

#include "devices/kinematics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace incise::devices {
namespace {

using Eigen::Quaterniond;
using Eigen::Vector3d;
constexpr double kPi = std::numbers::pi;

class Random {
 public:
  explicit Random(uint64_t seed) : engine_(seed) {}
  double uniform(double low, double high) {
    return std::uniform_real_distribution<double>(low, high)(engine_);
  }
  Vector3d vector(double half_width) {
    return {uniform(-half_width, half_width), uniform(-half_width, half_width),
            uniform(-half_width, half_width)};
  }
  // Uniform over rotations: a normalised 4D Gaussian.
  Quaterniond rotation() {
    std::normal_distribution<double> normal;
    Quaterniond q(normal(engine_), normal(engine_), normal(engine_), normal(engine_));
    return q.normalized();
  }

 private:
  std::mt19937_64 engine_;
};

double angle_between(const Vector3d& a, const Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

WorkspaceMapping random_mapping(Random& random) {
  return {random.uniform(0.2, 5.0), to_quat(random.rotation()), to_vec3(random.vector(0.5))};
}

// --- WorkspaceMapping --------------------------------------------------------------------------

TEST(WorkspaceMapping, MapsPointsAndRoundTrips) {
  Random random(1);
  for (int trial = 0; trial < 200; ++trial) {
    const WorkspaceMapping m = random_mapping(random);
    const Vector3d p = random.vector(0.3), q = random.vector(0.3);
    const Vector3d p_scene = to_eigen(m.to_scene(to_vec3(p)));
    // x_scene = R (s x) + o, written out with a rotation matrix.
    const Vector3d expected =
        to_eigen(m.rotation).toRotationMatrix() * (m.scale * p) + to_eigen(m.offset);
    EXPECT_LT((p_scene - expected).norm(), 1e-12);
    EXPECT_LT((to_eigen(m.to_device(to_vec3(p_scene))) - p).norm(), 1e-12);
    // Distances scale by s; displacements are differences of mapped points.
    const Vector3d q_scene = to_eigen(m.to_scene(to_vec3(q)));
    EXPECT_NEAR((p_scene - q_scene).norm(), m.scale * (p - q).norm(), 1e-12);
    const Vector3d d_scene = to_eigen(m.displacement_to_scene(to_vec3(p - q)));
    EXPECT_LT((d_scene - (p_scene - q_scene)).norm(), 1e-12);
    EXPECT_LT((to_eigen(m.displacement_to_device(to_vec3(d_scene))) - (p - q)).norm(), 1e-12);
  }
}

TEST(WorkspaceMapping, RotatesOrientationsAndRoundTrips) {
  Random random(2);
  for (int trial = 0; trial < 200; ++trial) {
    const WorkspaceMapping m = random_mapping(random);
    const Quaterniond q_device = random.rotation();
    const Quaterniond q_scene = to_eigen(m.orientation_to_scene(to_quat(q_device)));
    // A tool axis seen in the scene is the device's tool axis turned by R.
    const Vector3d axis = random.vector(1.0);
    EXPECT_LT((q_scene * axis - to_eigen(m.rotation) * (q_device * axis)).norm(), 1e-12);
    const Quaterniond back = to_eigen(m.orientation_to_device(to_quat(q_scene)));
    EXPECT_LT(back.angularDistance(q_device), 1e-12);
  }
}

TEST(WorkspaceMapping, MappedForcesDoTheSameVirtualWork) {
  Random random(3);
  for (int trial = 0; trial < 200; ++trial) {
    const WorkspaceMapping m = random_mapping(random);
    const Vector3d f_scene = random.vector(5.0);
    const Vector3d dx_device = random.vector(1e-3);
    const Vector3d f_device = to_eigen(m.force_to_device(to_vec3(f_scene)));
    const Vector3d dx_scene = to_eigen(m.displacement_to_scene(to_vec3(dx_device)));
    EXPECT_NEAR(f_device.dot(dx_device), f_scene.dot(dx_scene), 1e-14);
    EXPECT_NEAR(f_device.norm(), m.scale * f_scene.norm(), 1e-12);
    EXPECT_LT((to_eigen(m.force_to_scene(to_vec3(f_device))) - f_scene).norm(), 1e-12);
  }
}

TEST(WorkspaceMapping, ForceModelAgreesWithTheSceneModelEverywhere) {
  Random random(4);
  const auto force_at = [](const ForceModel& model, const Vector3d& x) {
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> k(model.stiffness.data());
    return Vector3d(to_eigen(model.force) - k * (x - to_eigen(model.reference_position)));
  };
  for (int trial = 0; trial < 50; ++trial) {
    const WorkspaceMapping m = random_mapping(random);
    ForceModel scene;
    scene.device_index = 1;
    scene.reference_position = to_vec3(random.vector(0.1));
    scene.force = to_vec3(random.vector(3.0));
    for (double& k : scene.stiffness)
      k = random.uniform(-500.0, 500.0);
    scene.state_timestamp_us = 77;
    const ForceModel device = m.force_model_to_device(scene);
    EXPECT_EQ(device.device_index, 1);
    EXPECT_EQ(device.state_timestamp_us, 77u);
    for (int point = 0; point < 10; ++point) {
      const Vector3d x = random.vector(0.1);
      const Vector3d expected =
          to_eigen(m.force_to_device(to_vec3(force_at(scene, to_eigen(m.to_scene(to_vec3(x)))))));
      EXPECT_LT((force_at(device, x) - expected).norm(), 1e-9 * (1.0 + expected.norm()));
    }
  }
}

TEST(WorkspaceMapping, StateToSceneMapsPoseOnly) {
  const WorkspaceMapping m{
      2.0, to_quat(Quaterniond(Eigen::AngleAxisd(kPi / 2, Vector3d::UnitZ()))), {0.1, 0.0, 0.0}};
  DeviceState device{1, 0b101, 0.25f, {0.01, 0.0, 0.0}, {}};
  const DeviceState scene = m.state_to_scene(device);
  EXPECT_EQ(scene.device_index, 1);
  EXPECT_EQ(scene.buttons, 0b101);
  EXPECT_EQ(scene.jaw, 0.25f);
  // 1 cm along x, doubled, turned a quarter about z, then offset: (0.1, 0.02, 0).
  EXPECT_NEAR(scene.position.x, 0.1, 1e-15);
  EXPECT_NEAR(scene.position.y, 0.02, 1e-15);
  EXPECT_NEAR(scene.position.z, 0.0, 1e-15);
  EXPECT_LT(to_eigen(scene.orientation).angularDistance(to_eigen(m.rotation)), 1e-15);
}

// --- PortalScope -------------------------------------------------------------------------------

// A portal that is neither at the origin nor axis-aligned, so no convention error can hide.
ScopeGeometry tilted_geometry() {
  ScopeGeometry g;
  g.portal = {0.04, 0.05, 0.08};
  g.portal_orientation =
      to_quat(Quaterniond(Eigen::AngleAxisd(2.5, Vector3d(1, 2, 3).normalized())));
  g.min_insertion = 0.01;
  g.max_insertion = 0.15;
  g.min_pitch = -50 * kDegree;
  g.max_pitch = 40 * kDegree;
  g.min_yaw = -70 * kDegree;
  g.max_yaw = 65 * kDegree;
  return g;
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

// --- PenDevice ---------------------------------------------------------------------------------

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

// --- StationCalibration ------------------------------------------------------------------------

StationCalibration sample_calibration() {
  StationCalibration c;
  DeviceCalibration scope;
  scope.index = 1;
  scope.kind = DeviceKind::Scope;
  scope.mapping = {
      1.5, to_quat(Quaterniond(Eigen::AngleAxisd(0.3, Vector3d::UnitX()))), {0.01, -0.02, 0.3}};
  scope.scope = tilted_geometry();
  scope.scope.view_angle = 45 * kDegree;
  scope.scope.field_of_view = 85 * kDegree;
  DeviceCalibration pen;
  pen.mapping = {0.5,
                 to_quat(Quaterniond(Eigen::AngleAxisd(-1.2, Vector3d(1, 1, 0).normalized()))),
                 {1.0 / 3.0, 0.0, -0.125}};
  c.devices = {scope, pen};
  return c;
}

void expect_same(const StationCalibration& a, const StationCalibration& b) {
  ASSERT_EQ(a.devices.size(), b.devices.size());
  const auto near = [](const auto& x, const auto& y) {
    return (to_eigen(x) - to_eigen(y)).norm() < 1e-15;
  };
  for (std::size_t i = 0; i < a.devices.size(); ++i) {
    const DeviceCalibration &x = a.devices[i], &y = b.devices[i];
    EXPECT_EQ(x.index, y.index);
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_EQ(x.mapping.scale, y.mapping.scale);
    EXPECT_TRUE(to_eigen(x.mapping.rotation)
                    .coeffs()
                    .isApprox(to_eigen(y.mapping.rotation).coeffs(), 1e-15));
    EXPECT_TRUE(near(x.mapping.offset, y.mapping.offset));
    if (x.kind != DeviceKind::Scope) continue;
    const ScopeGeometry &s = x.scope, &t = y.scope;
    EXPECT_TRUE(near(s.portal, t.portal));
    EXPECT_TRUE(to_eigen(s.portal_orientation)
                    .coeffs()
                    .isApprox(to_eigen(t.portal_orientation).coeffs(), 1e-15));
    const std::pair<double, double> pairs[] = {{s.view_angle, t.view_angle},
                                               {s.field_of_view, t.field_of_view},
                                               {s.min_insertion, t.min_insertion},
                                               {s.max_insertion, t.max_insertion},
                                               {s.min_pitch, t.min_pitch},
                                               {s.max_pitch, t.max_pitch},
                                               {s.min_yaw, t.min_yaw},
                                               {s.max_yaw, t.max_yaw}};
    for (const auto& [u, v] : pairs)
      EXPECT_NEAR(u, v, 1e-15);
  }
}

TEST(StationCalibration, DefaultIsTwoPensWithIdentityMappings) {
  const StationCalibration c = default_station_calibration();
  EXPECT_EQ(check_station_calibration(c), "");
  for (int index : {0, 1}) {
    const DeviceCalibration* device = c.find(index);
    ASSERT_NE(device, nullptr);
    EXPECT_EQ(device->kind, DeviceKind::Pen);
    const Vec3 p{0.1, -0.2, 0.3};
    EXPECT_EQ(device->mapping.to_scene(p), p);
    EXPECT_EQ(device->mapping.force_to_device(p), p);
  }
  EXPECT_EQ(c.find(2), nullptr);
}

TEST(StationCalibration, JsonRoundTrips) {
  const StationCalibration c = sample_calibration();
  ASSERT_EQ(check_station_calibration(c), "");
  const std::string text = station_calibration_json(c);
  const auto parsed = parse_station_calibration(text);
  ASSERT_TRUE(parsed) << parsed.error << "\n" << text;
  expect_same(*parsed.value, c);
  ASSERT_NE(parsed.value->find(1), nullptr);
  EXPECT_EQ(parsed.value->find(1)->kind, DeviceKind::Scope);
  // Printing what was read and reading it again changes nothing.
  const auto again = parse_station_calibration(station_calibration_json(*parsed.value));
  ASSERT_TRUE(again) << again.error;
  expect_same(*again.value, *parsed.value);
}

TEST(StationCalibration, DocumentedExampleParses) {
  const auto parsed = parse_station_calibration(R"({"devices": [
    {"index": 0, "kind": "pen",
     "mapping": {"scale": 1.0, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]}},
    {"index": 1, "kind": "scope",
     "mapping": {"scale": 1.0, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]},
     "scope": {"portal": [0.04, 0.04, 0.08], "portal_orientation": [0, 1, 0, 0],
               "view_angle_deg": 30, "field_of_view_deg": 70, "insertion_limits_m": [0, 0.2],
               "pitch_limits_deg": [-60, 60], "yaw_limits_deg": [-60, 60]}}]})");
  ASSERT_TRUE(parsed) << parsed.error;
  const DeviceCalibration& scope = parsed.value->devices[1];
  EXPECT_EQ(scope.kind, DeviceKind::Scope);
  EXPECT_NEAR(scope.scope.view_angle, kPi / 6, 1e-15);
  EXPECT_NEAR(scope.scope.max_yaw, kPi / 3, 1e-15);
  EXPECT_EQ(scope.scope.max_insertion, 0.2);
  // The portal is turned half a turn about x: the shaft points down (-z) into the tissue.
  const PortalScope portal_scope(scope.scope);
  const ScopePose pose = portal_scope.forward({0, 0, 0.05, 0});
  EXPECT_NEAR(pose.tip.z, 0.03, 1e-15);
}

TEST(StationCalibration, OptionalScopeKeysTakeTheirDefaults) {
  const auto parsed = parse_station_calibration(R"({"devices": [{"index": 1, "kind": "scope",
    "mapping": {"scale": 2, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]},
    "scope": {"portal": [0, 0, 0], "portal_orientation": [1, 0, 0, 0],
              "insertion_limits_m": [0.01, 0.1]}}]})");
  ASSERT_TRUE(parsed) << parsed.error;
  const ScopeGeometry& g = parsed.value->devices[0].scope;
  const ScopeGeometry defaults;
  EXPECT_EQ(g.view_angle, defaults.view_angle);
  EXPECT_EQ(g.field_of_view, defaults.field_of_view);
  EXPECT_EQ(g.min_pitch, defaults.min_pitch);
  EXPECT_EQ(g.max_yaw, defaults.max_yaw);
  EXPECT_EQ(g.min_insertion, 0.01);
}

TEST(StationCalibration, NearlyUnitQuaternionsAreNormalised) {
  const auto parsed = parse_station_calibration(R"({"devices": [{"index": 0, "kind": "pen",
    "mapping": {"scale": 1, "rotation": [0.6, 0.8004, 0, 0], "offset": [0, 0, 0]}}]})");
  ASSERT_TRUE(parsed) << parsed.error;
  const Quat q = parsed.value->devices[0].mapping.rotation;
  EXPECT_NEAR(to_eigen(q).norm(), 1.0, 1e-15);
  EXPECT_NEAR(q.x / q.w, 0.8004 / 0.6, 1e-12);  // same rotation, only rescaled
}

// A station of the given device entries (JSON text), and entries to build them from.
std::string station(const std::string& devices) {
  return R"({"devices": [)" + devices + "]}";
}
const std::string kIdentity = R"({"scale": 1, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]})";
std::string pen(const std::string& index = "0", const std::string& mapping = kIdentity,
                const std::string& kind = R"("pen")") {
  return R"({"index": )" + index + R"(, "kind": )" + kind + R"(, "mapping": )" + mapping + "}";
}
std::string scope(const std::string& geometry_extra, const std::string& index = "1") {
  return R"({"index": )" + index + R"(, "kind": "scope", "mapping": )" + kIdentity +
         R"(, "scope": {"portal": [0, 0, 0], "portal_orientation": [1, 0, 0, 0])" + geometry_extra +
         "}}";
}
const std::string kLimits = R"(, "insertion_limits_m": [0, 0.2])";

TEST(StationCalibration, BadInputsGetPreciseErrors) {
  struct Case {
    std::string json;
    std::string error;
  };
  const std::vector<Case> cases = {
      {"[]", "(calibration): must be an object, got array"},
      {"{}", "devices: missing"},
      {R"({"devices": {}})", "devices: must be an array, got object"},
      {station(""), "devices: must list at least one device"},
      {station(pen() + "," + pen("1") + "," + pen("1")), "devices: at most 2 devices, got 3"},
      {R"({"devices": [], "stations": 1})", "stations: unknown key (a calibration has devices)"},
      {station("7"), "devices[0]: must be an object, got number"},
      {station(pen() + "," +
               pen("1", R"({"scale": -2, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]})")),
       "devices[1].mapping.scale: must be > 0, got -2"},
      {station(pen("0", R"({"scale": 0, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]})")),
       "devices[0].mapping.scale: must be > 0, got 0"},
      {station(pen("0", R"({"scale": "1", "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]})")),
       "devices[0].mapping.scale: must be a number, got string"},
      {station(pen("0", R"({"scale": 1, "rotation": [2, 0, 0, 0], "offset": [0, 0, 0]})")),
       "devices[0].mapping.rotation: must be a unit quaternion (|q| within 0.001 of 1), got |q| "
       "= 2"},
      {station(pen("0", R"({"scale": 1, "rotation": [1, 0, 0], "offset": [0, 0, 0]})")),
       "devices[0].mapping.rotation: must have 4 numbers, got 3"},
      {station(pen("0", R"({"scale": 1, "rotation": [1, 0, 0, 0], "offset": [0, null, 0]})")),
       "devices[0].mapping.offset[1]: must be a number, got null"},
      {station(pen("0", R"({"scale": 1, "rotation": [1, 0, 0, 0]})")),
       "devices[0].mapping.offset: missing"},
      {station(pen("0", R"({"scale": 1, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0],
                            "shift": 1})")),
       "devices[0].mapping.shift: unknown key (a mapping has scale, rotation and offset)"},
      {station(pen("0", kIdentity, R"("laser")")),
       R"(devices[0].kind: must be "pen" or "scope", got "laser")"},
      {station(R"({"index": 0, "mapping": )" + kIdentity + "}"), "devices[0].kind: missing"},
      {station(pen("2")), "devices[0].index: must be 0 or 1, got 2"},
      {station(pen("0.5")), "devices[0].index: must be 0 or 1, got 0.5"},
      {station(pen(R"("0")")), "devices[0].index: must be 0 or 1, got string"},
      {station(pen() + "," + scope(kLimits, "0")),
       "devices[1].index: device 0 is already calibrated by devices[0]"},
      {station(R"({"index": 0, "kind": "pen", "mapping": )" + kIdentity + R"(, "tool": 1})"),
       "devices[0].tool: unknown key (a device has index, kind, mapping and scope)"},
      {station(R"({"index": 0, "kind": "pen", "mapping": )" + kIdentity + R"(, "scope": {}})"),
       "devices[0].scope: only a scope device has scope geometry, this one is a pen"},
      {station(R"({"index": 1, "kind": "scope", "mapping": )" + kIdentity + R"(, "scope": {}})"),
       "devices[0].scope.portal: missing"},
      {station(R"({"index": 1, "kind": "scope", "mapping": )" + kIdentity + "}"),
       "devices[0].scope: missing (a scope device needs its geometry)"},
      {station(pen() + "," + scope("")), "devices[1].scope.insertion_limits_m: missing"},
      {station(pen() + "," + scope(kLimits + R"(, "view_angle_deg": 95)")),
       "devices[1].scope.view_angle_deg: must be in [0, 90), got 95"},
      {station(pen() + "," + scope(kLimits + R"(, "view_angle_deg": -5)")),
       "devices[1].scope.view_angle_deg: must be in [0, 90), got -5"},
      {station(pen() + "," + scope(kLimits + R"(, "field_of_view_deg": 200)")),
       "devices[1].scope.field_of_view_deg: must be in [10, 140], got 200"},
      {station(pen() + "," + scope(R"(, "insertion_limits_m": [0.3, 0.1])")),
       "devices[1].scope.insertion_limits_m: must satisfy 0 <= min < max, got [0.3, 0.1]"},
      {station(pen() + "," + scope(R"(, "insertion_limits_m": [-0.1, 0.1])")),
       "devices[1].scope.insertion_limits_m: must satisfy 0 <= min < max, got [-0.1, 0.1]"},
      {station(pen() + "," + scope(kLimits + R"(, "pitch_limits_deg": [-100, 60])")),
       "devices[1].scope.pitch_limits_deg: must satisfy -90 < min < max < 90, got [-100, 60]"},
      {station(pen() + "," + scope(kLimits + R"(, "yaw_limits_deg": [30, 20])")),
       "devices[1].scope.yaw_limits_deg: must satisfy -90 < min < max < 90, got [30, 20]"},
      {station(pen() + "," + scope(kLimits + R"(, "yaw_limits_deg": [30])")),
       "devices[1].scope.yaw_limits_deg: must have 2 numbers, got 1"},
      {station(pen() + "," + scope(kLimits + R"(, "zoom": 2)")),
       "devices[1].scope.zoom: unknown key (a scope has portal, portal_orientation, "
       "view_angle_deg, field_of_view_deg, insertion_limits_m, pitch_limits_deg and "
       "yaw_limits_deg)"},
      {station(R"({"index": 1, "kind": "scope", "mapping": )" + kIdentity +
               R"(, "scope": {"portal": [0, 0, 0], "portal_orientation": [0, 0, 0, 0],
                              "insertion_limits_m": [0, 0.2]}})"),
       "devices[0].scope.portal_orientation: must be a unit quaternion (|q| within 0.001 of 1), "
       "got |q| = 0"},
      // Numbers beyond a double never become infinities: the JSON reader refuses them.
      {station(pen("0", R"({"scale": 1e999, "rotation": [1, 0, 0, 0], "offset": [0, 0, 0]})")),
       "not valid JSON: number overflow parsing '1e999'"},
  };
  for (const Case& c : cases) {
    const auto parsed = parse_station_calibration(c.json);
    EXPECT_FALSE(parsed) << c.json;
    EXPECT_EQ(parsed.error, c.error) << c.json;
  }
  // Syntax errors keep the reader's position.
  const auto parsed = parse_station_calibration(R"({"devices": [})");
  EXPECT_EQ(parsed.error.rfind("not valid JSON: parse error at line 1, column 14", 0), 0u)
      << parsed.error;
}

TEST(StationCalibration, CheckRefusesNonFiniteValuesBuiltInCode) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  StationCalibration c = sample_calibration();
  c.devices[1].mapping.scale = inf;
  EXPECT_EQ(check_station_calibration(c), "devices[1].mapping.scale: must be finite, got inf");
  c = sample_calibration();
  c.devices[1].mapping.scale = nan;
  EXPECT_EQ(check_station_calibration(c), "devices[1].mapping.scale: must be finite, got nan");
  c = sample_calibration();
  c.devices[1].mapping.offset.y = -inf;
  EXPECT_EQ(check_station_calibration(c),
            "devices[1].mapping.offset: must be finite, got [0.333333, -inf, -0.125]");
  c = sample_calibration();
  c.devices[0].mapping.rotation.x = nan;
  EXPECT_EQ(check_station_calibration(c).rfind("devices[0].mapping.rotation: must be finite", 0),
            0u);
  c = sample_calibration();
  c.devices[0].scope.portal.z = inf;
  EXPECT_EQ(check_station_calibration(c),
            "devices[0].scope.portal: must be finite, got [0.04, "
            "0.05, inf]");
  c = sample_calibration();
  c.devices[0].scope.max_insertion = inf;
  EXPECT_EQ(check_station_calibration(c),
            "devices[0].scope.insertion_limits_m: must satisfy 0 <= min < max, got [0.01, inf]");
  // A pen's unused scope geometry is not checked.
  c = sample_calibration();
  c.devices[1].scope.max_insertion = inf;
  EXPECT_EQ(check_station_calibration(c), "");
}

}  // namespace
}  // namespace incise::devices
