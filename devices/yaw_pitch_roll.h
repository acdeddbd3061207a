#pragma once
// Internal to the kinematics (portal_scope.cpp, pen_device.cpp): the rotation order the scope
// and the pen share.

#include <cmath>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace incise::devices {

// Ry(yaw) Rx(pitch) Rz(roll): the rotation order shared by the scope and the pen.
inline Eigen::Quaterniond yaw_pitch_roll(double yaw, double pitch, double roll) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY())) *
         Eigen::Quaterniond(Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitX())) *
         Eigen::Quaterniond(Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()));
}

// The roll r for which Ry(yaw) Rx(pitch) Rz(r) is nearest to m: the angle of the x axis of
// (Ry Rx)^T m about z. Exact when m has that form; when yaw is ill-determined (near gimbal
// lock) the roll absorbs the error, so the composite rotation stays right.
inline double residual_roll(const Eigen::Matrix3d& m, double yaw, double pitch) {
  const Eigen::Matrix3d rest = yaw_pitch_roll(yaw, pitch, 0.0).toRotationMatrix().transpose() * m;
  return std::atan2(rest(1, 0), rest(0, 0));
}

}  // namespace incise::devices
