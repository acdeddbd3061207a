#include "devices/simulated_scope.h"

#include "devices/eigen_conversions.h"

namespace incise::devices {

ScopeGeometry demo_scope_geometry() {
  ScopeGeometry geometry;
  geometry.portal = {0.04, 0.04, 0.09};
  geometry.portal_orientation = {0.0, 1.0, 0.0, 0.0};  // half a turn about x: +z points down
  geometry.min_insertion = 0.0;
  geometry.max_insertion = 0.1;
  return geometry;
}

ScopeGeometry knee_portal_geometry(bool anterolateral) {
  const Eigen::Vector3d position(anterolateral ? 0.016 : -0.016, 0.042, 0.010);
  const Eigen::Vector3d notch(0.0, -0.004, 0.008);
  ScopeGeometry geometry;
  geometry.portal = to_vec3(position);
  geometry.portal_orientation = to_quat(Eigen::Quaterniond::FromTwoVectors(
      Eigen::Vector3d::UnitZ(), (notch - position).normalized()));
  geometry.min_insertion = 0.0;
  geometry.max_insertion = 0.06;
  geometry.min_pitch = geometry.min_yaw = -50.0 * kDegree;
  geometry.max_pitch = geometry.max_yaw = 50.0 * kDegree;
  return geometry;
}

SimulatedScope::SimulatedScope(SimulatedScript script, const ScopeGeometry& geometry,
                               std::string name)
    : script_(std::move(script)), scope_(geometry), name_(std::move(name)) {
  joints_.insertion = geometry.min_insertion;
  pose_ = scope_.forward(joints_);
}

DeviceState SimulatedScope::poll(double t) {
  DeviceState state = script_.state_at(t);
  const ScopeSolution solution = scope_.inverse(state.position, 0.0);
  // A target at or behind the portal has no pose: the scope stays where it was.
  if (solution.reach != ScopeReach::TipAtPortal && solution.reach != ScopeReach::BehindPortal) {
    joints_ = scope_.clamp(solution.joints);
  }
  pose_ = scope_.forward(joints_);
  state.position = pose_.tip;
  state.orientation = pose_.shaft;
  return state;
}

void SimulatedScope::set_force(const Vec3& force_n) {
  actuated_ = scope_.joint_forces(joints_, force_n);
}

}  // namespace incise::devices
