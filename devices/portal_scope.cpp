// The portal scope's kinematics: forward, inverse, Jacobian and joint forces about the fulcrum,
// its limits, and the checks of its geometry.
#include "devices/portal_scope.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "devices/calibration_checks.h"
#include "devices/eigen_conversions.h"
#include "devices/yaw_pitch_roll.h"

namespace incise::devices {
namespace {

using Eigen::Matrix3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;

// Into (-pi, pi].
double wrap_angle(double angle) {
  const double wrapped = std::remainder(angle, 2.0 * std::numbers::pi);
  return wrapped <= -std::numbers::pi ? std::numbers::pi : wrapped;
}

// A limit met up to rounding is met: snap onto it. Returns false if value is farther out.
bool snap_into(double& value, double low, double high) {
  if (value < low - kLimitTolerance || value > high + kLimitTolerance) return false;
  value = std::clamp(value, low, high);
  return true;
}

}  // namespace

PortalScope::PortalScope(const ScopeGeometry& geometry) : geometry_(geometry) {
  if (std::string error = check_scope_geometry(geometry); !error.empty()) {
    throw std::invalid_argument("scope geometry: " + error);
  }
  portal_ = to_eigen(geometry.portal);
  portal_orientation_ = to_eigen(geometry.portal_orientation).normalized();
  geometry_.portal_orientation = to_quat(portal_orientation_);
}

void PortalScope::set_field_of_view(double radians) {
  geometry_.field_of_view = std::clamp(radians, kMinFieldOfView, kMaxFieldOfView);
}

ScopePose PortalScope::forward(const ScopeJoints& joints) const {
  // Normalised so that rounding in the product of four rotations does not accumulate.
  const Quaterniond shaft =
      (portal_orientation_ * yaw_pitch_roll(joints.yaw, joints.pitch, joints.roll)).normalized();
  const Matrix3d q = shaft.toRotationMatrix();
  const double a = geometry_.view_angle;
  ScopePose pose;
  pose.tip = to_vec3(portal_ + joints.insertion * q.col(2));
  pose.shaft = to_quat(shaft);
  pose.view_direction = to_vec3(std::sin(a) * q.col(1) + std::cos(a) * q.col(2));
  pose.view_up = to_vec3(std::cos(a) * q.col(1) - std::sin(a) * q.col(2));
  pose.field_of_view = geometry_.field_of_view;
  return pose;
}

ScopeSolution PortalScope::inverse(const Vec3& tip, double roll) const {
  ScopeSolution solution;
  const Vector3d from_portal = to_eigen(tip) - portal_;
  const double distance = from_portal.norm();
  if (!(distance >= kPortalClearance)) {
    solution.reach = ScopeReach::TipAtPortal;
    return solution;
  }
  // d in the portal frame: (cos(pitch) sin(yaw), -sin(pitch), cos(pitch) cos(yaw)).
  const Vector3d d = portal_orientation_.conjugate() * (from_portal / distance);
  if (!(d.z() > 0.0)) {
    solution.reach = ScopeReach::BehindPortal;
    return solution;
  }
  ScopeJoints& j = solution.joints;
  j.pitch = std::atan2(-d.y(), std::hypot(d.x(), d.z()));
  j.yaw = std::atan2(d.x(), d.z());
  j.insertion = distance;
  j.roll = wrap_angle(roll);
  const ScopeGeometry& g = geometry_;
  if (!snap_into(j.pitch, g.min_pitch, g.max_pitch)) {
    solution.reach = ScopeReach::PitchOutOfRange;
  } else if (!snap_into(j.yaw, g.min_yaw, g.max_yaw)) {
    solution.reach = ScopeReach::YawOutOfRange;
  } else if (!snap_into(j.insertion, g.min_insertion, g.max_insertion)) {
    solution.reach = ScopeReach::InsertionOutOfRange;
  }
  return solution;
}

ScopeSolution PortalScope::inverse(const Vec3& tip, const Quat& shaft) const {
  ScopeSolution solution = inverse(tip, 0.0);
  if (solution.reach == ScopeReach::TipAtPortal || solution.reach == ScopeReach::BehindPortal) {
    return solution;
  }
  const Matrix3d local =
      (portal_orientation_.conjugate() * to_eigen(shaft).normalized()).toRotationMatrix();
  solution.joints.roll = residual_roll(local, solution.joints.yaw, solution.joints.pitch);
  return solution;
}

Eigen::Matrix<double, 3, 4> PortalScope::jacobian(const ScopeJoints& joints) const {
  const double sp = std::sin(joints.pitch), cp = std::cos(joints.pitch);
  const double sy = std::sin(joints.yaw), cy = std::cos(joints.yaw);
  const double l = joints.insertion;
  Eigen::Matrix<double, 3, 4> local;
  // Columns: d(l d)/d pitch, d(l d)/d yaw, d, and zero for roll; d as in the header.
  local.col(0) << -l * sp * sy, -l * cp, -l * sp * cy;
  local.col(1) << l * cp * cy, 0.0, -l * cp * sy;
  local.col(2) << cp * sy, -sp, cp * cy;
  local.col(3).setZero();
  return portal_orientation_.toRotationMatrix() * local;
}

ActuatedForces PortalScope::joint_forces(const ScopeJoints& joints, const Vec3& tip_force) const {
  const Eigen::Vector4d tau = jacobian(joints).transpose() * to_eigen(tip_force);
  return {tau[0], tau[1], tau[2]};
}

ScopeJoints PortalScope::clamp(const ScopeJoints& joints) const {
  const ScopeGeometry& g = geometry_;
  ScopeJoints clamped = joints;
  clamped.pitch = std::clamp(joints.pitch, g.min_pitch, g.max_pitch);
  clamped.yaw = std::clamp(joints.yaw, g.min_yaw, g.max_yaw);
  clamped.insertion = std::clamp(joints.insertion, g.min_insertion, g.max_insertion);
  return clamped;
}

bool PortalScope::within_limits(const ScopeJoints& joints) const {
  const ScopeGeometry& g = geometry_;
  return joints.pitch >= g.min_pitch && joints.pitch <= g.max_pitch && joints.yaw >= g.min_yaw &&
         joints.yaw <= g.max_yaw && joints.insertion >= g.min_insertion &&
         joints.insertion <= g.max_insertion;
}

std::string_view describe(ScopeReach reach) {
  switch (reach) {
    case ScopeReach::Ok:
      return "reachable";
    case ScopeReach::TipAtPortal:
      return "tip is at the portal: the shaft direction is undefined";
    case ScopeReach::BehindPortal:
      return "tip is on or behind the portal plane (outside the body)";
    case ScopeReach::PitchOutOfRange:
      return "tip needs a pitch outside the pitch limits";
    case ScopeReach::YawOutOfRange:
      return "tip needs a yaw outside the yaw limits";
    case ScopeReach::InsertionOutOfRange:
      return "tip needs an insertion outside the insertion limits";
  }
  return "unknown";
}

double distance_from_shaft_line(const ScopePose& pose, const Vec3& point) {
  const Vector3d axis = to_eigen(pose.shaft).normalized() * Vector3d::UnitZ();
  return (to_eigen(point) - to_eigen(pose.tip)).cross(axis).norm();
}

std::string check_scope_geometry(const ScopeGeometry& g, const std::string& path) {
  if (auto error = check_point(g.portal, path + "portal"); !error.empty()) return error;
  if (auto error = check_unit_quaternion(g.portal_orientation, path + "portal_orientation");
      !error.empty()) {
    return error;
  }
  if (!(g.view_angle >= 0.0 && g.view_angle < kMaxViewAngle)) {
    return path + "view_angle_deg: must be in [0, " + number(kMaxViewAngle / kDegree) + "), got " +
           number(g.view_angle / kDegree);
  }
  if (!(g.field_of_view >= kMinFieldOfView && g.field_of_view <= kMaxFieldOfView)) {
    return path + "field_of_view_deg: must be in [" + number(kMinFieldOfView / kDegree) + ", " +
           number(kMaxFieldOfView / kDegree) + "], got " + number(g.field_of_view / kDegree);
  }
  if (!(finite({g.min_insertion, g.max_insertion}) && 0.0 <= g.min_insertion &&
        g.min_insertion < g.max_insertion)) {
    return path + "insertion_limits_m: must satisfy 0 <= min < max, got " +
           numbers({g.min_insertion, g.max_insertion});
  }
  if (auto error = check_angle_limits(g.min_pitch, g.max_pitch, path + "pitch_limits_deg");
      !error.empty()) {
    return error;
  }
  return check_angle_limits(g.min_yaw, g.max_yaw, path + "yaw_limits_deg");
}

}  // namespace incise::devices
