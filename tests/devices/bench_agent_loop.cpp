// bench_agent_loop: runs the station agent's real haptic loop (devices/agent/haptic_loop.h) with
// the default simulated device and a constant force model, without a server, and prints its
// timing. A measurement, not a test: the figures depend on the machine and its load.
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

  SimulatedDevice device(*parse_simulated_script(default_simulated_script()).value);
  HapticChannel channel;
  channel.link_up = true;
  ForceModel model;  // a stiff contact under the script's first press
  model.reference_position = {0.04, 0.04, 0.035};
  model.force = {0.0, 0.0, 1.0};
  model.stiffness = {300, 0, 0, 0, 300, 0, 0, 0, 800};

  HapticLoop loop(device, channel, 2, Clock::now());  // 500 Hz of states, the agent's default
  loop.start();
  const auto start = Clock::now();
  const auto end =
      start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  uint64_t drained = 0;
  auto next_model = start;
  for (auto now = start; now < end; now = Clock::now()) {
    if (now >= next_model) {
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
  return 0;
}
