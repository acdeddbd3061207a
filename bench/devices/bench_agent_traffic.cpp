// bench_agent_traffic: device-state traffic from agent to server with and without the deadband,
// for a scripted task: the built-in script (20 s of pressing, sliding and grasping on the demo
// tissue, with its hand tremor) or a script file, played by the real haptic loop in simulated
// time at 500 Hz. Also reports how far the server's held state strays from the hand's (the
// recording's fidelity), which the deadband bounds.
//
//   bench_agent_traffic [--script FILE] [--seconds S]

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

#include "devices/agent/haptic_loop.h"
#include "devices/protocol.h"
#include "devices/simulated_device.h"
#include "devices/simulated_script.h"

using namespace incise::devices;
using namespace incise::devices::agent;

namespace {

struct Traffic {
  uint64_t sent = 0;
  uint64_t held = 0;
  double max_error_m = 0;  // |hand - last sent| over every tick
};

Traffic run(const SimulatedScript& script, double seconds, bool deadband) {
  SimulatedDevice device(script);
  HapticChannel channel;
  channel.link_up = true;
  LoopSettings settings;
  settings.deadband.enabled = deadband;
  Device* devices[] = {&device};
  const Clock::time_point epoch{};
  HapticLoop loop(devices, channel, settings, epoch);
  Traffic traffic;
  DeviceState last_sent;
  for (int tick = 0; tick < static_cast<int>(seconds * 1000); ++tick) {
    loop.tick(epoch + std::chrono::milliseconds(tick));
    TimedState queued;
    while (channel.states.pop(queued)) {
      if (queued.send) {
        ++traffic.sent;
        last_sent = queued.state;
      } else {
        ++traffic.held;
      }
    }
    const Vec3& a = loop.last_state().position;
    const Vec3& b = last_sent.position;
    traffic.max_error_m =
        std::max(traffic.max_error_m, std::hypot(a.x - b.x, a.y - b.y, a.z - b.z));
  }
  return traffic;
}

}  // namespace

int main(int argc, char** argv) {
  std::string path;
  double seconds = 0;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--script") == 0) path = argv[i + 1];
    if (std::strcmp(argv[i], "--seconds") == 0) seconds = std::atof(argv[i + 1]);
  }
  std::string text(default_simulated_script());
  if (!path.empty()) {
    std::ifstream file(path);
    std::ostringstream buffer;
    buffer << file.rdbuf();
    text = buffer.str();
  }
  auto script = parse_simulated_script(text);
  if (!script) {
    std::fprintf(stderr, "bench_agent_traffic: %s\n", script.error.c_str());
    return 2;
  }
  if (seconds <= 0) seconds = script.value->waypoints.back().t;
  // On the wire a state is a 2-byte WebSocket header + 4-byte mask + the frame.
  const double wire_bytes = 2 + 4 + static_cast<double>(kDeviceStateFrameSize);
  std::printf(
      "%s, %.0f s at 500 Hz\n| deadband | states/s | bytes/s | held | max |hand - held state| "
      "|\n|---|---|---|---|---|\n",
      path.empty() ? "built-in script" : path.c_str(), seconds);
  for (bool deadband : {false, true}) {
    const Traffic t = run(*script.value, seconds, deadband);
    std::printf("| %s | %.0f | %.0f | %.0f %% | %.3f mm |\n", deadband ? "on" : "off",
                t.sent / seconds, t.sent * wire_bytes / seconds,
                100.0 * t.held / std::max<uint64_t>(1, t.sent + t.held), t.max_error_m * 1e3);
  }
  return 0;
}
