// bench_haptic_network: the table of force error against network delay and loss (README). The
// real haptic loop, force guard and simulated hand tap a 3 kN/m wall behind a link that delays
// each direction by 0..100 ms and loses 0 or 5 % of the messages (tests/devices/agent/
// delayed_wall.h), in simulated time, so the figures are exact and repeatable: 20 taps each.
//
//   bench_haptic_network [--seconds S]

#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "tests/devices/agent/delayed_wall.h"

using namespace incise::devices::agent;
using namespace incise::devices::agent::testing;

int main(int argc, char** argv) {
  double seconds = 20.0;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--seconds") == 0) seconds = std::atof(argv[i + 1]);
  std::printf(
      "wall 3000 N/m, coupling 1500 N/m, hand 300 N/m 0.15 kg, %g taps; delay each way\n"
      "| delay | loss | guard | RMS force error [N] | peak force [N] | deepest [mm] | energy to "
      "hand [mJ] | dissipated by guard [mJ] |\n|---|---|---|---|---|---|---|---|\n",
      seconds);
  for (int delay_ms : {0, 10, 25, 50, 100}) {
    for (double loss : {0.0, 0.05}) {
      for (bool passivity : {false, true}) {
        WallLinkSettings link;
        link.delay = std::chrono::milliseconds(delay_ms);
        link.loss = loss;
        ForceGuardSettings guard;
        guard.passivity = passivity;
        const WallRun run = run_wall(link, guard, seconds);
        std::printf("| %d ms | %.0f %% | %s | %.3f | %.2f | %.1f | %+.1f | %.1f |\n", delay_ms,
                    loss * 100, passivity ? "on" : "off", run.rms_force_error_n, run.peak_force_n,
                    run.peak_depth_m * 1e3, run.work_on_hand_j * 1e3, run.dissipated_j * 1e3);
      }
    }
  }
  return 0;
}
