#pragma once
// The haptic side of a ForceModel (devices/protocol.h): holds the latest model and evaluates it
// at the tool tip every tick. Pure: the time is an argument, so tests drive it without clocks.

#include <chrono>

#include "devices/device_state.h"
#include "devices/protocol.h"

namespace incise::devices::agent {

using Clock = std::chrono::steady_clock;

// A model older than this is stale: the server or the link has stalled, and the contact it
// linearises has most likely moved on.
inline constexpr Clock::duration kModelMaxAge = std::chrono::milliseconds(100);

class ForceModelEvaluator {
 public:
  // Replaces the model; received_at is when it arrived, on the agent's clock.
  void set_model(const ForceModel& model, Clock::time_point received_at);
  void clear() { has_model_ = false; }

  bool has_model() const { return has_model_; }
  const ForceModel& model() const { return model_; }

  // A model has arrived, at most kModelMaxAge before now.
  bool fresh(Clock::time_point now) const;

  // force - K (position - reference_position) [N] for a tool tip at position [m]; zero without a
  // model. Scaled down to kMaxModelForce if longer: far from its reference point a linearisation
  // can ask for any force, and the hand must never get more than a valid model may carry.
  Vec3 force_at(const Vec3& position) const;

 private:
  ForceModel model_{};
  Clock::time_point received_at_{};
  bool has_model_ = false;
};

}  // namespace incise::devices::agent
