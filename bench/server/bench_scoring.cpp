// Times what the server computes from a session besides the simulation itself:
//   - the simulation's damage tracker on the palpation block (one record_strain, which the
//     session runs every the block's damage interval), per call and per tick;
//   - a whole SimEngine tick of the palpation block with the probe pressed in, damage included;
//   - the review of a two-minute two-handed recording (events and the 50 ms timeline), and its
//     scoring (every metric), as GET /api/sessions/{id}/review and the session's end run them.
// Prints medians and 95th percentiles of repeated runs.  Usage: bench_scoring

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "curriculum/curriculum_json.h"
#include "server/live/scene_library.h"
#include "server/live/scoring.h"
#include "server/live/sim_engine.h"
#include "sim/io/scene_json.h"

namespace incise::server {
extern const char* const kDemoCurriculumJson;  // server/CMakeLists.txt compiles it in
}

namespace {

using namespace incise;
using Clock = std::chrono::steady_clock;

struct Stats {
  double median = 0;
  double p95 = 0;
};

Stats stats_of(std::vector<double> us) {
  std::sort(us.begin(), us.end());
  return {us[us.size() / 2], us[std::min(us.size() - 1, us.size() * 95 / 100)]};
}

template <class F>
Stats time_us(int runs, F&& f) {
  std::vector<double> us;
  for (int i = 0; i < runs; ++i) {
    const auto start = Clock::now();
    f();
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
  return stats_of(std::move(us));
}

// Two hands circling over the block at 500 Hz for `seconds`, dipping in now and then.
std::vector<server::live::TickRecord> two_handed_recording(double seconds) {
  const auto ticks = static_cast<std::uint32_t>(seconds * 500);
  std::vector<server::live::TickRecord> records(ticks);
  for (std::uint32_t i = 0; i < ticks; ++i) {
    const double t = i * 0.002;
    auto& r = records[i];
    r.tick = i;
    r.input.position = {0.04 + 0.02 * std::cos(t), 0.04 + 0.02 * std::sin(t),
                        0.035 - 0.004 * std::max(0.0, std::sin(3 * t))};
    r.force[2] = static_cast<float>(2.0 * std::max(0.0, std::sin(3 * t)));
    r.input.jaw = static_cast<float>(0.5 + 0.5 * std::cos(0.7 * t));
    r.has_second = true;
    r.second.input.device_index = 1;
    r.second.input.position = {0.02, 0.02 + 0.01 * std::sin(0.5 * t), 0.034};
    r.second.force[2] = 0.5f;
  }
  return records;
}

}  // namespace

int main() {
  const auto source = server::live::find_scene("scenes/palpation.json");
  const auto scene = sim::parse_scene_text(source->text);

  // The engine with the probe pressed 6 mm into the block's centre (settled first, not timed).
  server::live::SimEngine engine(scene, 0.002);
  devices::DeviceState pressed;
  pressed.position = {0.04, 0.04, 0.035 - 0.006};
  for (int i = 0; i < 500; ++i)
    engine.tick(pressed);
  const auto tick = time_us(2000, [&] { engine.tick(pressed); });
  const sim::surgery::BlockSceneOptions block;
  const int damage_ticks = static_cast<int>(std::lround(block.damage_interval_s / 0.002));
  std::printf(
      "SimEngine tick, palpation block, probe pressed 6 mm (damage every %d ticks): "
      "median %.1f us, p95 %.1f us\n",
      damage_ticks, tick.median, tick.p95);

  sim::tools::DamageSettings settings;
  settings.strain_thresholds = {{0, block.strain_threshold}};
  const sim::TetMesh& mesh = engine.world().scene().tissue().mesh();
  sim::tools::DamageTracker tracker(mesh, settings);
  const auto strain = time_us(2000, [&] { tracker.record_strain(mesh.x, 0.01); });
  std::printf(
      "damage tracker, %d tets: record_strain median %.1f us, p95 %.1f us "
      "(%.2f us per tick at one call per %d ticks)\n",
      tracker.num_slots(), strain.median, strain.p95, strain.median / damage_ticks, damage_ticks);

  const auto records = two_handed_recording(120);
  curriculum::Task task =
      curriculum::parse_curriculum_text(server::kDemoCurriculumJson).modules[0].tasks[0];
  const auto review = time_us(20, [&] {
    const auto r = server::live::review_session(records, 0.002, task, 0.05);
    if (r.timeline.t_s.size() != 2400) std::printf("unexpected bins %zu\n", r.timeline.t_s.size());
  });
  std::printf(
      "review of a 2 min two-handed recording (%zu ticks): events + 50 ms timeline "
      "median %.1f ms, p95 %.1f ms\n",
      records.size(), review.median / 1000, review.p95 / 1000);
  const auto scoring = time_us(20, [&] {
    const auto values = server::live::session_metrics(records, 0.002, task);
    if (values.empty()) std::printf("no metrics\n");
  });
  std::printf("every metric of the same recording: median %.1f ms, p95 %.1f ms\n",
              scoring.median / 1000, scoring.p95 / 1000);
  return 0;
}
