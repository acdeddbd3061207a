// The workspace mapping between a device's frame and the scene's.
#include "devices/workspace_mapping.h"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "devices/eigen_conversions.h"

namespace incise::devices {
namespace {

using Eigen::Matrix3d;

}  // namespace

Vec3 WorkspaceMapping::to_scene(const Vec3& p_device) const {
  return to_vec3(to_eigen(rotation) * (scale * to_eigen(p_device)) + to_eigen(offset));
}

Vec3 WorkspaceMapping::to_device(const Vec3& p_scene) const {
  return to_vec3(to_eigen(rotation).conjugate() * (to_eigen(p_scene) - to_eigen(offset)) / scale);
}

Vec3 WorkspaceMapping::displacement_to_scene(const Vec3& d_device) const {
  return to_vec3(to_eigen(rotation) * (scale * to_eigen(d_device)));
}

Vec3 WorkspaceMapping::displacement_to_device(const Vec3& d_scene) const {
  return to_vec3(to_eigen(rotation).conjugate() * to_eigen(d_scene) / scale);
}

Quat WorkspaceMapping::orientation_to_scene(const Quat& q_device) const {
  return to_quat(to_eigen(rotation) * to_eigen(q_device));
}

Quat WorkspaceMapping::orientation_to_device(const Quat& q_scene) const {
  return to_quat(to_eigen(rotation).conjugate() * to_eigen(q_scene));
}

Vec3 WorkspaceMapping::force_to_device(const Vec3& f_scene) const {
  return to_vec3(scale * (to_eigen(rotation).conjugate() * to_eigen(f_scene)));
}

Vec3 WorkspaceMapping::force_to_scene(const Vec3& f_device) const {
  return to_vec3(to_eigen(rotation) * to_eigen(f_device) / scale);
}

DeviceState WorkspaceMapping::state_to_scene(const DeviceState& device) const {
  DeviceState scene = device;
  scene.position = to_scene(device.position);
  scene.orientation = orientation_to_scene(device.orientation);
  return scene;
}

ForceModel WorkspaceMapping::force_model_to_device(const ForceModel& scene_model) const {
  ForceModel device = scene_model;
  device.reference_position = to_device(scene_model.reference_position);
  device.force = force_to_device(scene_model.force);
  const Matrix3d r = to_eigen(rotation).toRotationMatrix();
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> k(
      scene_model.stiffness.data());
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(device.stiffness.data()) =
      scale * scale * r.transpose() * k * r;
  return device;
}

}  // namespace incise::devices
