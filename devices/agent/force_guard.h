#pragma once
// What stands between a force model and the user's hand, per device, every haptic tick
// (docs/haptic_safety.md):
//
//   1. virtual coupling: the hand holds the tool through a spring k_c and damper b_c, so the
//      stiffness it feels is the model's K in series with k_c, never above k_c, whatever the
//      server sends; the coupling softens as the model ages (a delayed model is rendered softer);
//   2. the watchdog's fade (ForceFade) scales the force to zero within 10 ticks of any fault;
//   3. the passivity guard: an energy observer integrates the energy the display has given the
//      hand, and when the virtual side would have produced energy (a delayed or stale model
//      pushes back harder than it was pushed) it injects exactly the damping that dissipates the
//      excess (Hannaford and Ryu's time-domain passivity controller);
//   4. per-axis force limits and a slew limit on rising force.
//
// Pure and allocation-free: times are arguments, so the tests drive it tick by tick.

#include <array>
#include <cstdint>

#include "devices/device_state.h"
#include "devices/protocol.h"

namespace incise::devices::agent {

struct ForceGuardSettings {
  // Virtual coupling (off: the model's force is rendered as it is). 1.5 kN/m is what a desktop
  // haptic device renders stably at 1 kHz.
  bool coupling = true;
  double coupling_stiffness = 1500.0;  // k_c [N/m]
  double coupling_damping = 3.0;       // b_c [N s/m], along the directions the model is stiff
  // The coupling stiffness at model age a is k_c / (1 + a / softening_age): a model 50 ms old
  // (a long round trip) is felt at half the stiffness.
  double softening_age_s = 0.05;
  // Passivity guard (energy observer and damping injection).
  bool passivity = true;
  double max_damping = 30.0;       // [N s/m] the most damping it injects
  double energy_reserve_j = 0.05;  // the most energy credit the observer keeps [J]
  double reserve_leak_s = 0.5;     // the credit's decay time constant [s]
  // Limits, in the device's axes.
  std::array<double, 3> max_force_n{8.0, 8.0, 8.0};
  double max_force_rate_n_s = 1000.0;  // rising force per axis [N/s]: 1 N per tick
  // Faster than this is a sensor glitch or a dropped device, not a hand [m/s].
  double max_speed_m_s = 3.0;

  // Everything off and unlimited: the model's force exactly (tests of the loop's plumbing).
  static ForceGuardSettings transparent();
  // Velocity estimate: first-order low pass of the position difference [Hz].
  double velocity_cutoff_hz = 100.0;
};

// Why the watchdog has the force off this tick (None: it may render).
enum class GuardFault {
  None,
  LinkDown,     // no server link
  NoModel,      // no model for this device yet, or the last one is over kModelMaxGap old
  StaleModel,   // the state the model answers is over kModelMaxAge old
  DeviceFault,  // the driver reports a fault
  BadState,     // non-finite position, or faster than max_speed_m_s
  LateTick,     // the loop was starved (a period of more than kMaxTickGap)
  Stopping,     // the agent is stopping
};
const char* to_string(GuardFault fault);

class ForceGuard {
 public:
  explicit ForceGuard(const ForceGuardSettings& settings = {});

  // Call once per tick with the device's position [m] and the time since the previous tick dt
  // [s]; updates the velocity estimate and returns it. The first call returns zero.
  Vec3 track(const Vec3& position, double dt);

  // The coupled force for a model evaluated at the tip: model_force = F0 - K (x - x_ref) from
  // ForceModelEvaluator::force_at, stiffness = K, age_s = the model's age. Returns
  // k (K + k I)^-1 model_force - b S v with k the (softened) coupling stiffness and
  // S = K (K + k I)^-1 the share of the motion the model resists.
  Vec3 couple(const Vec3& model_force, const std::array<double, 9>& stiffness, double age_s) const;

  // Passivity guard, then limits: the force to command given the desired one (already faded)
  // and the time step dt [s]. Updates the energy observer with what is commanded. silent: the
  // watchdog has the force off; returns exactly zero (no damping either).
  Vec3 finish(const Vec3& desired, double dt, bool silent = false);

  // Resets velocity, energy and the slew limit's memory (after a fault the hand may have moved).
  void reset();

  const Vec3& velocity() const { return velocity_; }
  // Energy the virtual side has absorbed from the hand [J] (kept >= 0 by the guard).
  double energy_j() const { return energy_j_; }
  // Energy the guard has dissipated by injected damping [J] and the damping of the last tick.
  double dissipated_j() const { return dissipated_j_; }
  double last_damping() const { return last_damping_; }
  // Ticks on which a force limit or the slew limit cut the force.
  uint64_t limited_ticks() const { return limited_ticks_; }
  const ForceGuardSettings& settings() const { return settings_; }

 private:
  ForceGuardSettings settings_;
  Vec3 position_;
  Vec3 displacement_;  // over the last interval [m]: the work of the held force is F . dx
  Vec3 velocity_;
  bool tracking_ = false;
  double energy_j_ = 0.0;
  double dissipated_j_ = 0.0;
  double last_damping_ = 0.0;
  Vec3 previous_force_;
  uint64_t limited_ticks_ = 0;
};

}  // namespace incise::devices::agent
