#include "delayed_wall.h"

#include <algorithm>

namespace incise::devices::agent::testing {

DelayedWall::DelayedWall(HapticChannel& channel, WallLinkSettings settings, Clock::time_point epoch)
    : channel_(channel), settings_(settings), epoch_(epoch), rng_(settings.seed) {}

bool DelayedWall::lose() {
  return settings_.loss > 0 && std::uniform_real_distribution<double>(0, 1)(rng_) < settings_.loss;
}

ForceModel DelayedWall::answer(const TimedState& timed) const {
  ForceModel model;
  model.device_index = timed.state.device_index;
  model.reference_position = timed.state.position;
  model.state_timestamp_us = timed.timestamp_us;
  const double depth = settings_.wall_z - timed.state.position.z;
  if (depth > 0) {
    model.force = {0, 0, settings_.stiffness * depth};
    model.stiffness[8] = settings_.stiffness;
  }
  return model;
}

void DelayedWall::step(Clock::time_point now) {
  TimedState queued;
  while (channel_.states.pop(queued)) {
    if (!queued.send) continue;
    if (lose()) {
      ++states_lost_;
      continue;
    }
    const Clock::time_point sent = epoch_ + std::chrono::microseconds(queued.timestamp_us);
    states_.push_back({sent + settings_.delay, queued});
  }
  while (!states_.empty() && states_.front().arrives <= now) {
    const InFlight state = states_.front();
    states_.pop_front();
    if (lose()) {
      ++models_lost_;
      continue;
    }
    models_.push_back({state.arrives + settings_.delay, state.state});
  }
  while (!models_.empty() && models_.front().arrives <= now) {
    const InFlight& in_flight = models_.front();
    channel_.models[in_flight.state.state.device_index].publish({answer(in_flight.state), now});
    models_.pop_front();
  }
}

double DelayedWall::ideal_force(double z, double coupling_stiffness) const {
  const double depth = std::max(settings_.wall_z - z, 0.0);
  const double k = settings_.stiffness;
  return k * coupling_stiffness / (k + coupling_stiffness) * depth;
}

}  // namespace incise::devices::agent::testing

#include <cmath>

#include "devices/simulated_script.h"

namespace incise::devices::agent::testing {

WallRun run_wall(const WallLinkSettings& link, const ForceGuardSettings& guard, double seconds,
                 HandSettings hand_settings) {
  SimulatedScript script;
  script.loop = true;
  const double top = link.wall_z + 0.01;
  const double inside = link.wall_z - 0.01;
  script.waypoints = {{0.0, {0, 0, top}, 0}, {0.5, {0, 0, inside}, 0}, {1.0, {0, 0, top}, 0}};
  SimulatedHand hand(script, hand_settings);
  HapticChannel channel;
  channel.link_up = true;
  const Clock::time_point epoch{};
  LoopSettings settings;
  settings.send_every = 2;
  settings.deadband.enabled = false;
  settings.guard = guard;
  Device* devices[] = {&hand};
  HapticLoop loop(devices, channel, settings, epoch);
  DelayedWall wall(channel, link, epoch);

  WallRun run;
  double error_squared = 0;
  uint64_t contact_ticks = 0;
  const int ticks = static_cast<int>(seconds * 1000);
  for (int tick = 0; tick < ticks; ++tick) {
    const Clock::time_point now = epoch + std::chrono::milliseconds(tick);
    wall.step(now);
    loop.tick(now);
    const double z = loop.last_state().position.z;
    const Vec3& f = loop.last_force();
    if (z < link.wall_z) {
      const double error = f.z - wall.ideal_force(z, guard.coupling_stiffness);
      error_squared += error * error + f.x * f.x + f.y * f.y;
      ++contact_ticks;
    }
    run.peak_force_n = std::max(run.peak_force_n, std::sqrt(f.x * f.x + f.y * f.y + f.z * f.z));
    const Vec3& v = hand.velocity();
    run.max_speed_m_s = std::max(run.max_speed_m_s, std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z));
    run.peak_depth_m = std::max(run.peak_depth_m, link.wall_z - z);
    if (tick == ticks / 2) run.work_first_half_j = hand.work_on_hand_j();
    if (loop.fault() != GuardFault::None) ++run.fault_ticks;
  }
  run.work_on_hand_j = hand.work_on_hand_j();
  run.rms_force_error_n = contact_ticks ? std::sqrt(error_squared / contact_ticks) : 0.0;
  run.dissipated_j = loop.guard().dissipated_j();
  return run;
}

}  // namespace incise::devices::agent::testing
