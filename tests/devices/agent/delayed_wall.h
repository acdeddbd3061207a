#pragma once
// A stiff wall behind a delaying, lossy link, for the haptic loop in simulated time: what the
// passivity tests and bench_haptic_network hold the loop against.
//
// The "server" sees each state the loop queues one delay after it was sent (or never, with
// probability loss), answers it at once with the wall's local force model, and that model
// reaches the loop one delay later (or never). The wall fills z < wall_z:
//   in contact (z < wall_z): F0 = k (wall_z - z) e_z, K = k e_z e_z^T, reference = x
//   out of contact:          F0 = 0, K = 0
// so the model is exact at the state it answers and the delay alone makes it wrong.

#include <chrono>
#include <cstdint>
#include <deque>
#include <random>

#include "devices/agent/force_model_evaluator.h"
#include "devices/agent/haptic_channel.h"

namespace incise::devices::agent::testing {

struct WallLinkSettings {
  double wall_z = 0.0;                 // [m]
  double stiffness = 3000.0;           // k [N/m]
  std::chrono::microseconds delay{0};  // one way, each direction
  double loss = 0.0;                   // per message, each direction
  uint64_t seed = 1;
};

class DelayedWall {
 public:
  DelayedWall(HapticChannel& channel, WallLinkSettings settings, Clock::time_point epoch);

  // Moves messages up to now: states reach the wall, models reach the loop. Call before each tick.
  void step(Clock::time_point now);

  // The force of the wall without delay at tip z, through a coupling k_c in series [N, along z].
  double ideal_force(double z, double coupling_stiffness) const;

  uint64_t states_lost() const { return states_lost_; }
  uint64_t models_lost() const { return models_lost_; }

 private:
  struct InFlight {
    Clock::time_point arrives;
    TimedState state;
  };
  ForceModel answer(const TimedState& state) const;
  bool lose();

  HapticChannel& channel_;
  WallLinkSettings settings_;
  Clock::time_point epoch_;
  std::mt19937_64 rng_;
  std::deque<InFlight> states_;  // to the wall
  std::deque<InFlight> models_;  // back: the state they answer
  uint64_t states_lost_ = 0;
  uint64_t models_lost_ = 0;
};

}  // namespace incise::devices::agent::testing

#include "devices/agent/haptic_loop.h"
#include "devices/simulated_hand.h"

namespace incise::devices::agent::testing {

// A simulated hand tapping the wall: its target goes from 10 mm above to 10 mm inside and back,
// once a second, for `seconds` of simulated time at 1 kHz.
struct WallRun {
  double work_on_hand_j = 0;     // energy the device gave the hand over the run
  double work_first_half_j = 0;  // ... over the first half
  double rms_force_error_n = 0;  // rendered vs ideal_force at the same tip, ticks in contact
  double peak_force_n = 0;
  double max_speed_m_s = 0;
  double peak_depth_m = 0;     // deepest the tip went into the wall
  double dissipated_j = 0;     // by the passivity guard
  double loop_rate_hz = 1000;  // in simulated time: every tick runs
  uint64_t fault_ticks = 0;
};
WallRun run_wall(const WallLinkSettings& link, const ForceGuardSettings& guard, double seconds,
                 HandSettings hand = {});

}  // namespace incise::devices::agent::testing
