#pragma once
// The device poses the station benchmarks script (bench_surgery_live, bench_station): tools
// pointing down, the grasper's jaws along the surface, a parked hand, and the straight-line blend
// between two poses that a scripted move ticks through.
#include <cmath>

#include <Eigen/Geometry>

#include "devices/device_state.h"
#include "server/live/sim_engine.h"
#include "sim/core/types.h"

namespace incise::bench {

// The scalpel (or probe) points down: R = 180 degrees about x.
inline devices::DeviceState down(const sim::Vec3& tip) {
  devices::DeviceState s;
  s.position = {tip.x(), tip.y(), tip.z()};
  s.orientation = {0, 1, 0, 0};
  return s;
}

// The grasper's jaws lie along the surface: its axis along +x, R = 90 degrees about y.
inline devices::DeviceState along_x(const sim::Vec3& tip, float jaw) {
  devices::DeviceState s;
  s.position = {tip.x(), tip.y(), tip.z()};
  s.orientation = {std::sqrt(0.5), 0, std::sqrt(0.5), 0};
  s.jaw = jaw;
  return s;
}

// A tool pointing along direction (R takes e_z onto it), e.g. a scope or probe through a portal.
inline devices::DeviceState pointing(const sim::Vec3& tip, const sim::Vec3& direction) {
  const Eigen::Quaterniond q =
      Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), direction.normalized());
  devices::DeviceState s;
  s.position = {tip.x(), tip.y(), tip.z()};
  s.orientation = {q.w(), q.x(), q.y(), q.z()};
  return s;
}

// A hand whose device has not reported: out of every scene.
inline devices::DeviceState parked() {
  devices::DeviceState s;
  s.position = {0, 0, server::live::kParkedToolHeight};
  return s;
}

// p moved the fraction s of the way to q: position and jaw (the orientation stays p's).
inline devices::DeviceState blend(devices::DeviceState p, const devices::DeviceState& q, double s) {
  p.position = {(1 - s) * p.position.x + s * q.position.x,
                (1 - s) * p.position.y + s * q.position.y,
                (1 - s) * p.position.z + s * q.position.z};
  p.jaw = static_cast<float>((1 - s) * p.jaw + s * q.jaw);
  return p;
}

}  // namespace incise::bench
