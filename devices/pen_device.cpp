// The pen's kinematics: its gimbal angles to and from an orientation, and the forces its motors
// render.
#include "devices/pen_device.h"

#include <cmath>

#include <Eigen/Core>

#include "devices/eigen_conversions.h"
#include "devices/yaw_pitch_roll.h"

namespace incise::devices {
namespace {

using Eigen::Matrix3d;

}  // namespace

PenPose PenDevice::forward(const PenJoints& joints) const {
  return {joints.position, to_quat(yaw_pitch_roll(joints.yaw, joints.pitch, joints.roll))};
}

PenJoints PenDevice::inverse(const PenPose& pose) const {
  // m = Ry(yaw) Rx(pitch) Rz(roll) has row 1 = (cp sin(roll), cp cos(roll), -sin(pitch)) and
  // column 2 = (cp sin(yaw), -sin(pitch), cp cos(yaw)), cp = cos(pitch) >= 0.
  const Matrix3d m = to_eigen(pose.orientation).normalized().toRotationMatrix();
  PenJoints joints;
  joints.position = pose.position;
  joints.pitch = std::atan2(-m(1, 2), std::hypot(m(1, 0), m(1, 1)));
  // At lock both entries of column 2 are rounding noise: put the whole turn in roll.
  joints.yaw = std::hypot(m(0, 2), m(2, 2)) < 1e-12 ? 0.0 : std::atan2(m(0, 2), m(2, 2));
  joints.roll = residual_roll(m, joints.yaw, joints.pitch);
  return joints;
}

PenForces PenDevice::joint_forces(const Vec3& tip_force_n, const Vec3& tip_torque_nm) const {
  return {tip_force_n, tip_torque_nm};
}

}  // namespace incise::devices
