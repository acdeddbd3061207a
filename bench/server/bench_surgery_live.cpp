// Times the liver station scene as a live session runs it (server/live/surgery_world.h): the
// 2 ms SimEngine tick while the scalpel is above the tissue, while it cuts along the marked line
// 6 mm deep at 6.7 mm/s (the demo agent's stroke, deploy/agent/liver_cut_demo.json), and while
// the grasper holds the lifted lobe; and what the cut came to. A live session needs a tick below
// 2 ms (real time). Run for the station's 12 mm cells and, to see what the coarser mesh costs in
// accuracy, the 8 mm cells of liver_surgery.json with the same tools.
// Prints medians, 95th percentiles and maxima.  Usage: bench_surgery_live [cell_size_m ...]
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "bench/server/station_poses.h"
#include "server/live/scene_library.h"
#include "server/live/session_scene.h"
#include "server/live/sim_engine.h"

namespace {

using namespace incise;
using bench::along_x;
using bench::down;
using bench::parked;
using Clock = std::chrono::steady_clock;
constexpr double kTickS = 0.002;

struct Stats {
  double median = 0;
  double p95 = 0;
  double max = 0;
};

Stats stats_of(std::vector<double> us) {
  std::sort(us.begin(), us.end());
  return {us[us.size() / 2], us[std::min(us.size() - 1, us.size() * 95 / 100)], us.back()};
}

// Ticks the engine from (a0, b0) to (a1, b1) over `seconds`, timing each tick [us].
std::vector<double> move(server::live::SimEngine& engine, devices::DeviceState a0,
                         devices::DeviceState a1, devices::DeviceState b0, devices::DeviceState b1,
                         double seconds) {
  const auto n = static_cast<int>(seconds / kTickS);
  std::vector<double> us;
  for (int i = 1; i <= n; ++i) {
    const double s = static_cast<double>(i) / n;
    const std::array<devices::DeviceState, 2> inputs = {bench::blend(a0, a1, s),
                                                        bench::blend(b0, b1, s)};
    const auto start = Clock::now();
    engine.tick(inputs);
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
  }
  return us;
}

sim::Vec3 landmark(const sim::surgery::SurgicalSceneSetup& setup, const std::string& name) {
  for (const auto& l : setup.landmarks)
    if (l.name == name) return l.position;
  return sim::Vec3::Zero();
}

void report(const char* what, const std::vector<double>& us) {
  const auto s = stats_of(us);
  std::printf("  %-34s median %7.0f us  p95 %7.0f us  max %7.0f us  (%.2fx real time)\n", what,
              s.median, s.p95, s.max, kTickS * 1e6 / s.median);
}

void run(double cell_size) {
  const auto source = server::live::find_scene("scenes/surgery/liver_station.json");
  auto json = nlohmann::json::parse(source->text);
  json["anatomy_options"]["cell_size"] = cell_size;
  const auto built = Clock::now();
  const auto scene = server::live::load_session_scene(source->id, json.dump());
  const double build_s = std::chrono::duration<double>(Clock::now() - built).count();
  const auto& setup = scene.setup();
  server::live::SimEngine engine(scene, kTickS, 2);
  std::printf(
      "liver station, cell %.0f mm: %lld nodes, %lld tets, dt %.1f us (%d steps a tick), "
      "meshed in %.2f s\n",
      cell_size * 1e3, static_cast<long long>(setup.spec.tissue.rest.rows()),
      static_cast<long long>(setup.spec.tissue.tets.rows()), kTickS / engine.substeps() * 1e6,
      engine.substeps(), build_s);

  const sim::Vec3 start = landmark(setup, "cut_start");
  const sim::Vec3 end = landmark(setup, "cut_end");
  std::printf("  marked line from (%.4f, %.4f, %.4f) to (%.4f, %.4f, %.4f) m\n", start.x(),
              start.y(), start.z(), end.x(), end.y(), end.z());
  const sim::Vec3 depth(0, 0, 0.006);
  const sim::Vec3 above(0, 0, 0.01);
  // Idle: the scalpel held above the line's start, the grasper parked.
  std::vector<double> idle =
      move(engine, down(start + above), down(start + above), parked(), parked(), 1.0);
  report("idle (blade above the tissue)", idle);
  // The grasper takes the lobe at the line's middle (its hinge 0.5 mm above the surface, 5 mm
  // before the middle) and lifts it 1 cm.
  const sim::Vec3 lobe = 0.5 * (start + end) + sim::Vec3(-0.005, 0, 0.0005);
  const auto hold_scalpel = down(start + above);
  move(engine, hold_scalpel, hold_scalpel, along_x(lobe + above, 1), along_x(lobe, 1), 0.5);
  move(engine, hold_scalpel, hold_scalpel, along_x(lobe, 1), along_x(lobe, 0), 0.3);
  const auto holding =
      move(engine, hold_scalpel, hold_scalpel, along_x(lobe, 0), along_x(lobe + above, 0), 2.0);
  report("grasper lifting the lobe 1 cm", holding);
  const auto pull = engine.contact(1).force_on_tool;
  std::printf("  pull on the left hand %.3f N\n", pull.norm());
  move(engine, hold_scalpel, hold_scalpel, along_x(lobe + above, 0), along_x(lobe + above, 1), 0.3);
  move(engine, hold_scalpel, hold_scalpel, along_x(lobe + above, 1), parked(), 0.01);
  auto in = move(engine, down(start + above), down(start - depth), parked(), parked(), 1.0);
  auto cutting = move(engine, down(start - depth), down(end - depth), parked(), parked(), 6.0);
  cutting.insert(cutting.end(), in.begin(), in.end());
  report("cutting 6 mm deep along the line", cutting);
  move(engine, down(end - depth), down(end + above), parked(), parked(), 1.0);
  const auto damage = engine.damage();
  std::printf(
      "  cut %.1f mm^2, %.1f mm^2 off target, mean distance %.2f mm, never event %s, "
      "%d tets now\n",
      damage.cut_area * 1e6, damage.cut_area_outside_target * 1e6, damage.cut_mean_distance * 1e3,
      damage.never_event ? "yes" : "no", engine.world().scene().tissue().mesh().num_tets());
  std::printf("  finite %s; events:", engine.state_finite() ? "yes" : "no");
  for (const auto& e : engine.scene_events().events())
    std::printf(" %s (hand %d, %.2f s: %s);", e.kind.c_str(), e.hand, e.t_s, e.label.c_str());
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> cells;
  for (int i = 1; i < argc; ++i)
    cells.push_back(std::atof(argv[i]));
  if (cells.empty()) cells = {0.014, 0.012, 0.008};
  for (const double c : cells)
    run(c);
  return 0;
}
