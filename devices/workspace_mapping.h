#pragma once
// A device's workspace in the scene: device frame -> scene frame (scale, rotation, offset), and
// forces and force models back. Part of the station kinematics (kinematics.h).

#include "devices/device_state.h"
#include "devices/protocol.h"

namespace incise::devices {

// Device frame -> scene frame:  x_scene = R (s x_device) + o.
//
// Forces go the other way by the transpose, scaled so that virtual work is preserved: a device
// displacement dx_dev moves the tool by dx_scene = s R dx_dev in the scene, so the force the
// hand must feel is the one doing the same work,
//   F_dev . dx_dev = F_scene . dx_scene = F_scene . (s R dx_dev)  =>  F_dev = s R^T F_scene.
// A scale > 1 (small hand motions, large scene motions) therefore makes scene forces feel
// stronger, exactly as a lever would. Stiffness follows as K_dev = s^2 R^T K_scene R.
struct WorkspaceMapping {
  double scale = 1.0;  // s > 0, scene metres per device metre
  Quat rotation;       // R, unit quaternion
  Vec3 offset;         // o, where the device origin lands in the scene [m]

  Vec3 to_scene(const Vec3& p_device) const;
  Vec3 to_device(const Vec3& p_scene) const;
  // A velocity or displacement: no offset.
  Vec3 displacement_to_scene(const Vec3& d_device) const;
  Vec3 displacement_to_device(const Vec3& d_scene) const;
  // q_scene = R q_device (the scale does not affect directions).
  Quat orientation_to_scene(const Quat& q_device) const;
  Quat orientation_to_device(const Quat& q_scene) const;
  // F_dev = s R^T F_scene (see above).
  Vec3 force_to_device(const Vec3& f_scene) const;
  Vec3 force_to_scene(const Vec3& f_device) const;
  // Position and orientation into the scene; index, buttons and jaw unchanged.
  DeviceState state_to_scene(const DeviceState& device) const;
  // A scene-frame local force model as the device renders it: reference point to_device,
  // force force_to_device, K_dev = s^2 R^T K R. Then for every device point x,
  //   device_model.force(x) == force_to_device(scene_model.force(to_scene(x))).
  ForceModel force_model_to_device(const ForceModel& scene_model) const;
};

}  // namespace incise::devices
