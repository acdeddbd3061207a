#pragma once
// The haptic side of a ForceModel (devices/protocol.h): holds the latest model and evaluates it
// at the tool tip every tick. Pure: the time is an argument, so tests drive it without clocks.

#include <chrono>

#include "devices/device_state.h"
#include "devices/protocol.h"

namespace incise::devices::agent {

using Clock = std::chrono::steady_clock;

// The server answers every state (500 Hz), so no model for this long means the link or the
// server has stalled, or the cable is out without the socket noticing (a silent cut): the fade
// then ends 25 ms after the last model. At 5 % loss, 7 models in a row are lost once in 10^9.
inline constexpr Clock::duration kModelMaxGap = std::chrono::milliseconds(15);
// A model answering a state sampled longer ago than this is stale: the contact it linearises has
// most likely moved on. Above the 200 ms round trip of 100 ms added delay each way.
inline constexpr Clock::duration kModelMaxAge = std::chrono::milliseconds(300);

class ForceModelEvaluator {
 public:
  // Replaces the model; received_at is when it arrived, on the agent's clock.
  void set_model(const ForceModel& model, Clock::time_point received_at);
  void clear() { has_model_ = false; }

  bool has_model() const { return has_model_; }
  const ForceModel& model() const { return model_; }

  // A model has arrived, at most kModelMaxGap before now.
  bool fresh(Clock::time_point now) const;
  // now_us - the sample time of the state the model answers (both on the agent's epoch) [us];
  // 0 if the model echoes no state of ours (a timestamp from the future).
  uint64_t age_us(uint64_t now_us) const {
    return now_us > model_.state_timestamp_us ? now_us - model_.state_timestamp_us : 0;
  }
  Clock::time_point received_at() const { return received_at_; }

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
