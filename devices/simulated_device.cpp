#include "devices/simulated_device.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace incise::devices {
namespace {

// Tremor knots are this far apart [s]; linear interpolation between them keeps the tremor's
// energy below ~10 Hz, like physiological tremor.
constexpr double kJitterKnotSpacing = 0.05;

// SplitMix64 (Steele, Lea, Flood 2014): a well-mixed hash of (seed, knot, axis), so jitter needs
// no generator state and depends only on t.
uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Uniform in [-1, 1).
double knot_value(uint64_t seed, int64_t knot, uint64_t axis) {
  const uint64_t h =
      splitmix64(splitmix64(seed ^ (axis * 0xD1B54A32D192ED03ull)) ^ static_cast<uint64_t>(knot));
  return static_cast<double>(h >> 11) * 0x1.0p-52 - 1.0;
}

double tremor(uint64_t seed, uint64_t axis, double t) {
  const double k = t / kJitterKnotSpacing;
  const double k0 = std::floor(k);
  const double s = k - k0;
  const auto knot = static_cast<int64_t>(k0);
  return (1.0 - s) * knot_value(seed, knot, axis) + s * knot_value(seed, knot + 1, axis);
}

double lerp(double a, double b, double s) {
  return a + s * (b - a);
}

}  // namespace

SimulatedDevice::SimulatedDevice(SimulatedScript script, std::string name)
    : script_(std::move(script)), name_(std::move(name)) {
  if (std::string error = check_simulated_script(script_); !error.empty()) {
    throw std::invalid_argument("simulated device script: " + error);
  }
}

DeviceCapabilities SimulatedDevice::capabilities() const {
  return {.has_force_output = false, .has_jaw = true, .button_count = 0};
}

DeviceState SimulatedDevice::state_at(double t) const {
  const auto& w = script_.waypoints;
  const double clock = std::max(t, 0.0);
  double local = clock;
  if (script_.loop) local = std::fmod(clock, w.back().t);

  // The first waypoint after local; before the first or after the last the ends are held.
  const auto next = std::upper_bound(w.begin(), w.end(), local,
                                     [](double value, const Waypoint& p) { return value < p.t; });
  const Waypoint& b = next == w.end() ? w.back() : *next;
  const Waypoint& a = next == w.begin() ? w.front() : *(next - 1);
  const double s = (b.t > a.t) ? std::clamp((local - a.t) / (b.t - a.t), 0.0, 1.0) : 0.0;

  DeviceState state;
  state.jaw = static_cast<float>(std::clamp(lerp(a.jaw, b.jaw, s), 0.0, 1.0));
  state.position = {lerp(a.position.x, b.position.x, s), lerp(a.position.y, b.position.y, s),
                    lerp(a.position.z, b.position.z, s)};
  state.orientation = script_.orientation;
  if (script_.jitter > 0.0) {
    // The tremor follows the unwrapped clock, so a looping script does not repeat it exactly.
    state.position.x += script_.jitter * tremor(script_.seed, 0, clock);
    state.position.y += script_.jitter * tremor(script_.seed, 1, clock);
    state.position.z += script_.jitter * tremor(script_.seed, 2, clock);
  }
  return state;
}

}  // namespace incise::devices
