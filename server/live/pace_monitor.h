#pragma once
// Whether a live session keeps up with real time, and how much work it sheds when it does not
// (docs/live_sessions.md, "Falling behind real time").
//
// The session thread reports every tick (on_tick) with the wall clock and how late the tick
// started against its schedule; any thread may ask for the state at a wall time (state_at), in
// which a tick that does not end shows as lag growing with the clock: a session stuck for 3 s in
// one tick is 3 s behind, never "running" as if nothing were wrong.
//
//   behind      over the last window the simulation advanced less than behind_factor of the wall
//               time, or it is more than behind_lag_s behind schedule
//   keeping up  again after recover_s of windows at recover_factor or better with the lag under
//               half of behind_lag_s
//   shedding    one level more for each window that ends behind, one less for each recover_s
//               kept up (so a level that was not needed is given back, and one that was comes
//               straight back): ShedPlan says what each level leaves out.
//
// Plain arithmetic on the times it is given: no clock, no thread, no allocation.
#include <cstdint>
#include <string>

namespace incise::server::live {

struct PaceSettings {
  double window_s = 0.5;         // the real-time factor's window [s]
  double behind_factor = 0.95;   // simulated / wall time below this over a window: behind
  double behind_lag_s = 0.05;    // or more than this behind schedule [s]
  double recover_factor = 0.99;  // at or above this ...
  double recover_s = 2.0;        // ... for this long [s]: keeping up again, one level less shed
};

struct PaceState {
  bool behind = false;
  double lag_s = 0;             // how far behind schedule [s], a stalled tick included
  double real_time_factor = 1;  // simulated over wall time in the last window
  int shed_level = 0;           // 0 .. max_level
};

// Levels of shedding, in the order they are taken: first the physics' (a scene with adaptivity
// pauses its refinement, then also coarsens what it refined as soon as no tool holds it:
// sim::surgery::shed_adaptivity; recorded per tick, so that a replay sheds as the session did),
// then the picture's (half, then a quarter of the frames). A scene without adaptivity has only
// the picture's two levels.
inline constexpr int kRenderShedLevels = 2;
struct ShedPlan {
  int physics_levels = 0;  // 0, or sim::surgery::kMaxAdaptivityShedLevel with adaptivity

  int max_level() const { return physics_levels + kRenderShedLevels; }
  // The physics' level at shedding level `level` (SimEngine::set_shed_level).
  int physics_level(int level) const;
  // How many times fewer snapshots (and so rendered frames) a level publishes: 1, 2 or 4.
  int render_divisor(int level) const;
  // What a level leaves out, for people: "" for 0, e.g. "refinement paused, refined tissue
  // coarsened, render rate halved".
  std::string text(int level) const;
};

class PaceMonitor {
 public:
  // tick_s: simulated time per tick [s], > 0; max_level: the most shedding levels (ShedPlan::
  // max_level).
  explicit PaceMonitor(double tick_s, int max_level = kRenderShedLevels,
                       PaceSettings settings = {});

  // The schedule (re)starts at now_s [s]: the first tick of a session, after a pause, or while
  // it waits for its first device state. Keeps the shed level.
  void restart(double now_s);
  // A tick ended at now_s; it started schedule_lag_s [s] (>= 0) after its scheduled time.
  void on_tick(double now_s, double schedule_lag_s);
  // The state at wall time now_s (>= the last on_tick's).
  PaceState state_at(double now_s) const;

 private:
  void close_window(double now_s);

  double tick_s_;
  int max_level_;
  PaceSettings settings_;
  PaceState state_;
  double last_tick_s_ = 0;  // wall time of the last tick's end (or of restart)
  double window_start_s_ = 0;
  std::int64_t window_ticks_ = 0;
  double window_lag_s_ = 0;      // the largest schedule lag in the window
  double kept_up_since_s_ = -1;  // < 0: not keeping up
};

}  // namespace incise::server::live
