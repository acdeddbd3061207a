// A tool script sampled in time: each device's input, keyframes interpolated.
#include <algorithm>
#include <vector>

#include "sim/surgery/track_sampling.h"

namespace incise::sim::surgery {

ToolInput sample_track(const DeviceTrack& track, Real t) {
  const std::vector<Keyframe>& keys = track.keyframes;
  const auto next = std::upper_bound(keys.begin(), keys.end(), t,
                                     [](Real time, const Keyframe& k) { return time < k.t; });
  Vec3 tip, direction;
  Real jaw = 0;
  if (next == keys.begin() || next == keys.end()) {
    const Keyframe& held = next == keys.begin() ? keys.front() : keys.back();
    tip = held.tip;
    direction = held.direction;
    jaw = held.jaw;
  } else {
    const Keyframe& a = *(next - 1);
    const Keyframe& b = *next;
    const Real s = (t - a.t) / (b.t - a.t);
    tip = a.tip + s * (b.tip - a.tip);
    direction = ((1 - s) * a.direction + s * b.direction).normalized();
    jaw = a.jaw + s * (b.jaw - a.jaw);
  }
  ToolInput input;
  input.tip = tip;
  input.orientation = Eigen::Quaternion<Real>::FromTwoVectors(Vec3::UnitZ(), direction);
  input.jaw = jaw;
  return input;
}

void sample_script(const ToolScript& script, Real t, std::vector<ToolInput>& inputs) {
  inputs.resize(script.devices.size());
  for (std::size_t d = 0; d < script.devices.size(); ++d)
    inputs[d] = sample_track(script.devices[d], t);
}

}  // namespace incise::sim::surgery
