#pragma once
// Fades the rendered force in and out so that it never jumps: the factor moves toward its target
// (1 = render the model, 0 = no force) by at most 1/kSteps per haptic tick, so at 1 kHz the force
// is gone within 10 ms of the link dropping or the model going stale, and comes back over 10 ms.
//
// The level is an integer number of steps, so the factor is exactly 0 and exactly 1 at the ends.

namespace incise::devices::agent {

class ForceFade {
 public:
  static constexpr int kSteps = 10;

  // One tick: moves one step toward on ? 1 : 0 and returns the new factor.
  double step(bool on) {
    if (on && level_ < kSteps) ++level_;
    if (!on && level_ > 0) --level_;
    return factor();
  }

  double factor() const { return static_cast<double>(level_) / kSteps; }

 private:
  int level_ = 0;  // starts silent: the first model fades in
};

}  // namespace incise::devices::agent
