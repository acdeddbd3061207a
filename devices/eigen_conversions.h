#pragma once
// The wire protocol's plain Vec3 / Quat to and from Eigen, for the kinematics' arithmetic.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "devices/device_state.h"

namespace incise::devices {

inline Eigen::Vector3d to_eigen(const Vec3& v) {
  return {v.x, v.y, v.z};
}
inline Eigen::Quaterniond to_eigen(const Quat& q) {
  return {q.w, q.x, q.y, q.z};
}
inline Vec3 to_vec3(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}
inline Quat to_quat(const Eigen::Quaterniond& q) {
  return {q.w(), q.x(), q.y(), q.z()};
}

}  // namespace incise::devices
