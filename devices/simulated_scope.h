#pragma once
// A simulated 4-DOF arthroscope / laparoscope at a portal (the two-handed interface of
// Knee Arthroscopy VR, section III): the
// hand's script says where it wants the tip; the scope's kinematics (PortalScope) turn that into
// pitch, yaw and insertion about the fulcrum (clamped to the joint limits; roll from the
// script's buttons is not modelled: 0), and the reported pose follows from the joints, so the
// shaft always passes through the portal and an unreachable target stops at the limit. A force
// on the tip is mapped to the actuated axes through the Jacobian's transpose (pitch and yaw
// torque, insertion force; roll is free), as a real scope device would render it.

#include <string>

#include "devices/device.h"
#include "devices/portal_scope.h"
#include "devices/simulated_device.h"

namespace incise::devices {

// Above the demo tissue block (x, y in [0, 0.08], top z = 0.03), pointing down into it.
ScopeGeometry demo_scope_geometry();

// At a portal of the knee scene (its frame; sim/mesh/cgal/anatomy.cpp's knee_portals: either
// side of the patellar tendon, a centimetre above the joint line, aimed at the notch): the
// anterolateral one for the arthroscope (30-degree optics), the anteromedial one for an
// instrument; inserted up to 6 cm, pivoting up to 50 degrees each way.
ScopeGeometry knee_portal_geometry(bool anterolateral);

class SimulatedScope final : public Device {
 public:
  // Throws std::invalid_argument for an invalid script or geometry.
  SimulatedScope(SimulatedScript script, const ScopeGeometry& geometry,
                 std::string name = "simulated scope");

  std::string_view name() const override { return name_; }
  int degrees_of_freedom() const override { return 4; }
  DeviceCapabilities capabilities() const override { return {.has_force_output = true}; }
  DeviceState poll(double t) override;
  // Commands the tip force; kept as the actuated axes' forces (allocation-free).
  void set_force(const Vec3& force_n) override;

  const ScopeJoints& joints() const { return joints_; }
  const ScopePose& pose() const { return pose_; }
  const ActuatedForces& actuated_forces() const { return actuated_; }
  const PortalScope& scope() const { return scope_; }

 private:
  SimulatedDevice script_;
  PortalScope scope_;
  std::string name_;
  ScopeJoints joints_;
  ScopePose pose_;
  ActuatedForces actuated_{};
};

}  // namespace incise::devices
