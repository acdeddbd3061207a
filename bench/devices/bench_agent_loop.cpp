// bench_agent_loop: runs the station agent's real haptic loop (devices/agent/haptic_loop.h, with
// the agent's default settings: force guard and deadband on) with the default simulated device
// and a constant force model, without a server, and prints its timing and the device-to-force
// latency: from the device poll to the force command of the same tick (the local force model
// answers every position at once; docs/haptic_safety.md). A measurement, not a test: the
// figures depend on the machine and its load.
//
//   bench_agent_loop [--seconds N]   (default 60)
//
// The main thread stands in for the io thread: it republishes the model every 10 ms (so that it
// stays fresh and the full evaluation runs) and drains the state ring every 2 ms.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "devices/agent/haptic_loop.h"
#include "devices/agent/histogram.h"
#include "devices/simulated_device.h"
#include "devices/simulated_script.h"

namespace {

using namespace incise::devices;
using namespace incise::devices::agent;
using namespace std::chrono_literals;

int usage(const char* error) {
  std::fprintf(stderr, "bench_agent_loop: %s\nusage: bench_agent_loop [--seconds N]\n", error);
  return 2;
}

// The simulated device, timing each tick from its poll to its force command.
class TimedDevice final : public Device {
 public:
  explicit TimedDevice(SimulatedScript script) : inner_(std::move(script)) {}
  std::string_view name() const override { return inner_.name(); }
  int degrees_of_freedom() const override { return inner_.degrees_of_freedom(); }
  DeviceCapabilities capabilities() const override { return {.has_force_output = true}; }
  DeviceState poll(double t) override {
    polled_at_ = Clock::now();
    return inner_.poll(t);
  }
  void set_force(const Vec3&) override {
    latency_ns_.add(static_cast<uint64_t>(
        std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - polled_at_).count()));
  }
  const Histogram& latency_ns() const { return latency_ns_; }

 private:
  SimulatedDevice inner_;
  Clock::time_point polled_at_;
  Histogram latency_ns_{10, 100000};  // 10 ns bins up to 1 ms
};

}  // namespace

int main(int argc, char** argv) {
  double seconds = 60.0;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) {
      char* end = nullptr;
      seconds = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(seconds > 0.0 && seconds <= 86400.0)) {
        return usage("--seconds must be a number in (0, 86400]");
      }
    } else {
      return usage((std::string("unknown argument ") + argv[i]).c_str());
    }
  }

  TimedDevice device(*parse_simulated_script(default_simulated_script()).value);
  HapticChannel channel;
  channel.link_up = true;
  ForceModel model;  // a stiff contact under the script's first press
  model.reference_position = {0.04, 0.04, 0.035};
  model.force = {0.0, 0.0, 1.0};
  model.stiffness = {300, 0, 0, 0, 300, 0, 0, 0, 800};

  const Clock::time_point epoch = Clock::now();
  Device* devices[] = {&device};
  HapticLoop loop(devices, channel, LoopSettings{}, epoch);  // the agent's defaults: 500 Hz
  loop.start();
  const auto start = Clock::now();
  const auto end =
      start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  uint64_t drained = 0;
  auto next_model = start;
  for (auto now = start; now < end; now = Clock::now()) {
    if (now >= next_model) {
      // As if it answered the state sampled just now: the model is fresh.
      model.state_timestamp_us = static_cast<uint64_t>(
          std::chrono::duration_cast<std::chrono::microseconds>(now - epoch).count());
      channel.models[0].publish({model, now});
      next_model += 10ms;
    }
    TimedState state;
    while (channel.states.pop(state))
      ++drained;
    std::this_thread::sleep_for(2ms);
  }
  loop.stop();
  const LoopSummary s = loop.summary();

  std::printf("haptic loop, %.0f s, %llu periods, %llu states handed over (%llu dropped)\n",
              seconds, static_cast<unsigned long long>(s.periods),
              static_cast<unsigned long long>(drained),
              static_cast<unsigned long long>(channel.states.dropped()));
  std::printf("achieved rate [Hz]: %.2f\n", s.rate_hz);
  std::printf("period p50 [us]: %.0f\n", s.period_p50_us);
  std::printf("period p99 [us]: %.0f\n", s.period_p99_us);
  std::printf("max jitter [us]: %.1f\n", s.max_jitter_us);
  std::printf("jitter p99 [us]: %.0f\n", s.jitter_p99_us);
  std::printf("overruns: %llu\n", static_cast<unsigned long long>(s.overruns));
  std::printf("device -> force latency (poll to force command) p50 [us]: %.2f\n",
              device.latency_ns().percentile(50) / 1000.0);
  std::printf("device -> force latency (poll to force command) p99 [us]: %.2f\n",
              device.latency_ns().percentile(99) / 1000.0);
  return 0;
}
