#pragma once
// A simulated hand holding a force-feedback device: the hand wants to follow a SimulatedScript,
// and the device's handle is a mass pulled toward the script by the hand's grip (a spring and a
// damper) and pushed by the force the haptic loop commands. Unlike SimulatedDevice, it feels
// the force: a contact stops it, a bad loop can make it bounce or buzz. The tests of the
// passivity guard and the network emulation hold the loop with it.
//
//   m x'' = k_h (script(t) - x) - b_h x' + F_commanded
//
// integrated semi-implicitly in sub-steps of at most 0.1 ms at each poll. Defaults are a relaxed
// grip on a desktop device (Hogan's hand impedance: tens to hundreds of N/m, a few N s/m).

#include <string>

#include "devices/device.h"
#include "devices/simulated_device.h"

namespace incise::devices {

struct HandSettings {
  double mass_kg = 0.15;            // handle, linkage and fingers
  double grip_stiffness_n_m = 300;  // k_h
  double grip_damping_ns_m = 3;     // b_h
};

class SimulatedHand final : public Device {
 public:
  // Throws std::invalid_argument for an invalid script or non-positive settings.
  explicit SimulatedHand(SimulatedScript script, HandSettings settings = {},
                         std::string name = "simulated hand");

  std::string_view name() const override { return name_; }
  int degrees_of_freedom() const override { return 7; }
  DeviceCapabilities capabilities() const override;
  DeviceState poll(double t) override;
  void set_force(const Vec3& force_n) override { force_ = force_n; }

  // The work the commanded force has done on the hand since the start [J]: positive means the
  // device gave the hand energy.
  double work_on_hand_j() const { return work_j_; }
  // Kinetic energy of the handle [J].
  double kinetic_energy_j() const;
  const Vec3& velocity() const { return velocity_; }
  const Vec3& force() const { return force_; }
  // Where the hand wants to be at t (the script).
  DeviceState target_at(double t) const { return script_.state_at(t); }

 private:
  SimulatedDevice script_;
  HandSettings settings_;
  std::string name_;
  bool started_ = false;
  double t_ = 0;
  Vec3 position_;
  Vec3 velocity_;
  Vec3 force_;
  double work_j_ = 0;
};

}  // namespace incise::devices
