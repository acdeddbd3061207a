#pragma once
// A 6-DOF pen (Phantom-like): 3 actuated translations and a passive gimbal. Part of the station
// kinematics (kinematics.h).

#include "devices/device_state.h"

namespace incise::devices {

// A pen-style 6-DOF device (Phantom-like, Knee Arthroscopy VR Fig. 1): three actuated
// translational axes move the gimbal centre, which is the tool point; three passive gimbal angles
// orient the pen.
//   orientation = Ry(yaw) Rx(pitch) Rz(roll),  the pen points along its +z (as the scope)
// Gimbal lock at pitch = +-90 degrees: yaw and roll then turn about the same axis, and
// inverse() returns yaw = 0 with the whole turn in roll (the pose still round-trips).
// The motors render the tip force unchanged; the gimbal has no motors, so torques are not
// rendered (Knee Arthroscopy VR, Fig. 1(b)): joint_forces() returns the dropped torque for logging.

struct PenJoints {
  Vec3 position;       // gimbal centre = tool point, device frame [m]
  double yaw = 0.0;    // [rad]
  double pitch = 0.0;  // [rad]
  double roll = 0.0;   // [rad]
};

struct PenPose {
  Vec3 position;  // [m]
  Quat orientation;
};

struct PenForces {
  Vec3 axis_forces_n;      // along the device's x, y, z axes
  Vec3 dropped_torque_nm;  // the part of the requested wrench the device cannot render
};

struct PenDevice {
  PenPose forward(const PenJoints& joints) const;
  // Yaw and roll in [-pi, pi], pitch in [-pi/2, pi/2].
  PenJoints inverse(const PenPose& pose) const;
  PenForces joint_forces(const Vec3& tip_force_n, const Vec3& tip_torque_nm = {}) const;
};

}  // namespace incise::devices
