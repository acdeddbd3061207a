// The simulated scope: the script's tip targets through the portal kinematics.

#include "devices/simulated_scope.h"

#include <gtest/gtest.h>

#include <cmath>
#include "devices/eigen_conversions.h"

namespace incise::devices {
namespace {

SimulatedScript still_at(const Vec3& p) {
  SimulatedScript script;
  script.waypoints = {{0.0, p, 0.0}};
  return script;
}

double distance(const Vec3& a, const Vec3& b) {
  return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z);
}

TEST(SimulatedScope, AReachableTargetIsReachedWithTheShaftThroughThePortal) {
  const ScopeGeometry geometry = demo_scope_geometry();
  for (const Vec3 target :
       {Vec3{0.04, 0.04, 0.03}, Vec3{0.02, 0.06, 0.035}, Vec3{0.07, 0.01, 0.04}}) {
    SimulatedScope scope(still_at(target), geometry);
    const DeviceState s = scope.poll(0.1);
    EXPECT_LT(distance(s.position, target), 1e-12);
    // The shaft's +z, from the portal through the tip.
    EXPECT_LT(distance_from_shaft_line(scope.pose(), geometry.portal), 1e-12);
    const double insertion = distance(target, geometry.portal);
    EXPECT_NEAR(scope.joints().insertion, insertion, 1e-12);
    EXPECT_EQ(s.orientation, scope.pose().shaft);
  }
}

TEST(SimulatedScope, AnUnreachableTargetStopsAtTheLimit) {
  const ScopeGeometry geometry = demo_scope_geometry();
  // 20 cm below the portal: beyond the 10 cm insertion limit, straight down.
  SimulatedScope deep(still_at({0.04, 0.04, -0.11}), geometry);
  const DeviceState s = deep.poll(0.0);
  EXPECT_NEAR(deep.joints().insertion, geometry.max_insertion, 1e-12);
  EXPECT_NEAR(s.position.z, geometry.portal.z - geometry.max_insertion, 1e-12);
  // Above the portal (behind it): the scope keeps its previous pose.
  SimulatedScope behind(still_at({0.04, 0.04, 0.2}), geometry);
  const DeviceState b = behind.poll(0.0);
  EXPECT_NEAR(b.position.z, geometry.portal.z - geometry.min_insertion, 1e-12);
}

TEST(SimulatedScope, TipForcesGoToPitchYawAndInsertionByTheJacobianTranspose) {
  const ScopeGeometry geometry = demo_scope_geometry();
  SimulatedScope scope(still_at({0.03, 0.05, 0.035}), geometry);
  scope.poll(0.0);
  const Vec3 force{0.3, -0.2, 1.5};
  scope.set_force(force);
  const Eigen::Matrix<double, 3, 4> J = scope.scope().jacobian(scope.joints());
  const Eigen::Vector4d tau = J.transpose() * to_eigen(force);
  EXPECT_NEAR(scope.actuated_forces().pitch_torque_nm, tau[0], 1e-12);
  EXPECT_NEAR(scope.actuated_forces().yaw_torque_nm, tau[1], 1e-12);
  EXPECT_NEAR(scope.actuated_forces().insertion_force_n, tau[2], 1e-12);
  // A force along the shaft (pushing the scope back out) is all insertion force.
  const Vec3 along = {geometry.portal.x - 0.03, geometry.portal.y - 0.05,
                      geometry.portal.z - 0.035};
  const double length = std::hypot(along.x, along.y, along.z);
  scope.set_force({along.x / length, along.y / length, along.z / length});
  EXPECT_NEAR(scope.actuated_forces().insertion_force_n, -1.0, 1e-12);
  EXPECT_NEAR(scope.actuated_forces().pitch_torque_nm, 0.0, 1e-12);
  EXPECT_NEAR(scope.actuated_forces().yaw_torque_nm, 0.0, 1e-12);
}

}  // namespace
}  // namespace incise::devices
