// How fast a replay of a surgical attempt seeks (server/live/replay_session.h): a recording of the
// liver station (scenes/surgery/liver_station.json) of `minutes` minutes, made of 20 s cycles
// (the scalpel hovers, goes 6 mm into the tissue, cuts along the marked line, comes out and
// hovers; the grasper stays parked), replayed paused. Prints how long the replay's checkpointer
// takes to run the whole recording ahead, then the time each of 20 seeks to pseudo-random
// targets, alternately backwards and forwards, takes until the replay's snapshot shows the
// target tick: median and maximum. Wall clock on this machine, the replay's own threads.
//   bench_replay_seek [minutes]   (default 3)
#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <thread>
#include <vector>

#include "server/live/replay_session.h"
#include "server/live/scene_library.h"
#include "server/live/session_scene.h"

namespace {

using namespace incise;
using Clock = std::chrono::steady_clock;
constexpr double kTickS = 0.002;

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

sim::Vec3 landmark(const sim::surgery::SurgicalSceneSetup& setup, const char* name) {
  for (const auto& l : setup.landmarks)
    if (l.name == name) return l.position;
  std::fprintf(stderr, "bench_replay_seek: no landmark %s\n", name);
  std::exit(1);
}

// The scalpel pointing down (R = 180 degrees about x) at tip.
devices::DeviceState scalpel_at(const sim::Vec3& tip) {
  devices::DeviceState s;
  s.position = {static_cast<float>(tip.x()), static_cast<float>(tip.y()),
                static_cast<float>(tip.z())};
  s.orientation = {0, 1, 0, 0};
  return s;
}

std::vector<server::live::TickRecord> recording(const sim::surgery::SurgicalSceneSetup& setup,
                                                double minutes) {
  const sim::Vec3 start = landmark(setup, "cut_start"), end = landmark(setup, "cut_end");
  const sim::Vec3 up(0, 0, 0.01), down(0, 0, -0.006);
  // Waypoints of one 20 s cycle and the seconds to reach each from the last.
  const std::vector<std::pair<sim::Vec3, double>> cycle = {
      {start + up, 5}, {start + down, 2}, {end + down, 6}, {end + up, 2}, {start + up, 5}};
  std::vector<server::live::TickRecord> records;
  sim::Vec3 at = start + up;
  devices::DeviceState parked;
  parked.position = {0, 0, static_cast<float>(server::live::kParkedToolHeight)};
  const auto total = static_cast<std::size_t>(minutes * 60 / kTickS);
  while (records.size() < total) {
    for (const auto& [to, seconds] : cycle) {
      const int n = static_cast<int>(seconds / kTickS);
      for (int i = 1; i <= n && records.size() < total; ++i) {
        const double s = static_cast<double>(i) / n;
        server::live::TickRecord r;
        r.tick = static_cast<std::uint32_t>(records.size());
        r.input = scalpel_at((1 - s) * at + s * to);
        r.has_second = true;
        r.second.input = parked;
        records.push_back(r);
      }
      at = to;
    }
  }
  return records;
}

}  // namespace

int main(int argc, char** argv) {
  const double minutes = argc > 1 ? std::atof(argv[1]) : 3.0;
  if (!(minutes > 0)) {
    std::fprintf(stderr, "usage: bench_replay_seek [minutes > 0]\n");
    return 2;
  }
  const auto source = server::live::find_scene("scenes/surgery/liver_station.json");
  const auto scene = server::live::load_session_scene(source->id, source->text);
  auto records = recording(scene.setup(), minutes);
  const auto total = static_cast<std::int64_t>(records.size());
  server::live::ReplaySession replay(scene, kTickS, std::move(records));
  replay.start();
  replay.pause();
  const auto opened = Clock::now();
  while (replay.checkpointed_to() < total)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double ahead_s = seconds_since(opened);
  std::printf(
      "liver station replay, %.1f min (%lld ticks): checkpointed ahead in %.1f s "
      "(%.1fx real time), a checkpoint every %lld ticks\n",
      minutes, static_cast<long long>(total), ahead_s, minutes * 60 / ahead_s,
      static_cast<long long>(replay.checkpoint_ticks()));

  std::mt19937 rng(7);
  std::uniform_int_distribution<std::int64_t> pick(1, total);
  std::vector<double> seek_s;
  std::int64_t now = 0;
  for (int k = 0; k < 20; ++k) {
    // Alternately before and after where the replay stands.
    std::int64_t target = pick(rng);
    if ((k % 2 == 0) != (target > now))
      target = std::clamp<std::int64_t>(2 * now - target, 1, total);
    const auto asked = Clock::now();
    replay.seek(static_cast<double>(target) * kTickS);
    while (replay.snapshot()->tick != target)
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    seek_s.push_back(seconds_since(asked));
    now = target;
  }
  std::sort(seek_s.begin(), seek_s.end());
  std::printf("20 seeks, backwards and forwards: median %.3f s, max %.3f s\n",
              seek_s[seek_s.size() / 2], seek_s.back());
  return 0;
}
