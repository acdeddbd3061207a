#include "devices/simulated_scope.h"

namespace incise::devices {

ScopeGeometry demo_scope_geometry() {
  ScopeGeometry geometry;
  geometry.portal = {0.04, 0.04, 0.09};
  geometry.portal_orientation = {0.0, 1.0, 0.0, 0.0};  // half a turn about x: +z points down
  geometry.min_insertion = 0.0;
  geometry.max_insertion = 0.1;
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
