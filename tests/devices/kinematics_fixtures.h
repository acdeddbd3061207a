#pragma once
// The helpers the kinematics tests share (tests/devices/{workspace_mapping,portal_scope,pen_device,
// station_calibration,station_calibration_json}_test.cpp): seeded random numbers, vectors and
// rotations, a tilted scope portal and a sample station calibration.

#include <cstdint>
#include <numbers>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "devices/eigen_conversions.h"
#include "devices/portal_scope.h"
#include "devices/station_calibration.h"

namespace incise::devices {

inline constexpr double kPi = std::numbers::pi;

class Random {
 public:
  explicit Random(uint64_t seed) : engine_(seed) {}
  double uniform(double low, double high) {
    return std::uniform_real_distribution<double>(low, high)(engine_);
  }
  Eigen::Vector3d vector(double half_width) {
    return {uniform(-half_width, half_width), uniform(-half_width, half_width),
            uniform(-half_width, half_width)};
  }
  // Uniform over rotations: a normalised 4D Gaussian.
  Eigen::Quaterniond rotation() {
    std::normal_distribution<double> normal;
    Eigen::Quaterniond q(normal(engine_), normal(engine_), normal(engine_), normal(engine_));
    return q.normalized();
  }

 private:
  std::mt19937_64 engine_;
};

// A portal that is neither at the origin nor axis-aligned, so no convention error can hide.
inline ScopeGeometry tilted_geometry() {
  ScopeGeometry g;
  g.portal = {0.04, 0.05, 0.08};
  g.portal_orientation =
      to_quat(Eigen::Quaterniond(Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, 2, 3).normalized())));
  g.min_insertion = 0.01;
  g.max_insertion = 0.15;
  g.min_pitch = -50 * kDegree;
  g.max_pitch = 40 * kDegree;
  g.min_yaw = -70 * kDegree;
  g.max_yaw = 65 * kDegree;
  return g;
}

// A scope (index 1, on the tilted portal) and a pen (index 0), each with a mapping that is not
// the identity.
inline StationCalibration sample_calibration() {
  StationCalibration c;
  DeviceCalibration scope;
  scope.index = 1;
  scope.kind = DeviceKind::Scope;
  scope.mapping = {1.5,
                   to_quat(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))),
                   {0.01, -0.02, 0.3}};
  scope.scope = tilted_geometry();
  scope.scope.view_angle = 45 * kDegree;
  scope.scope.field_of_view = 85 * kDegree;
  DeviceCalibration pen;
  pen.mapping = {
      0.5,
      to_quat(Eigen::Quaterniond(Eigen::AngleAxisd(-1.2, Eigen::Vector3d(1, 1, 0).normalized()))),
      {1.0 / 3.0, 0.0, -0.125}};
  c.devices = {scope, pen};
  return c;
}

}  // namespace incise::devices
