#include "server/live/pace_monitor.h"

#include <algorithm>

namespace incise::server::live {

int ShedPlan::physics_level(int level) const {
  return std::clamp(level, 0, physics_levels);
}

int ShedPlan::render_divisor(int level) const {
  return 1 << std::clamp(level - physics_levels, 0, kRenderShedLevels);
}

std::string ShedPlan::text(int level) const {
  std::string text;
  switch (physics_level(level)) {
    case 0:
      break;
    case 1:
      text = "refinement paused";
      break;
    default:
      text = "refinement paused, refined tissue coarsened";
  }
  const int divisor = render_divisor(level);
  if (divisor > 1) {
    if (!text.empty()) text += ", ";
    text += divisor == 2 ? "render rate halved" : "render rate quartered";
  }
  return text;
}

PaceMonitor::PaceMonitor(double tick_s, int max_level, PaceSettings settings)
    : tick_s_(tick_s), max_level_(std::max(0, max_level)), settings_(settings) {}

void PaceMonitor::restart(double now_s) {
  last_tick_s_ = window_start_s_ = now_s;
  window_ticks_ = 0;
  window_lag_s_ = 0;
  state_.lag_s = 0;
}

void PaceMonitor::on_tick(double now_s, double schedule_lag_s) {
  last_tick_s_ = now_s;
  state_.lag_s = std::max(0.0, schedule_lag_s);
  window_lag_s_ = std::max(window_lag_s_, state_.lag_s);
  ++window_ticks_;
  if (now_s - window_start_s_ >= settings_.window_s) close_window(now_s);
}

void PaceMonitor::close_window(double now_s) {
  const double wall = now_s - window_start_s_;
  state_.real_time_factor = static_cast<double>(window_ticks_) * tick_s_ / wall;
  const bool behind =
      state_.real_time_factor < settings_.behind_factor || window_lag_s_ > settings_.behind_lag_s;
  if (behind) {
    state_.behind = true;
    state_.shed_level = std::min(state_.shed_level + 1, max_level_);
    kept_up_since_s_ = -1;
  } else if (state_.real_time_factor >= settings_.recover_factor &&
             window_lag_s_ < settings_.behind_lag_s / 2) {
    if (kept_up_since_s_ < 0) kept_up_since_s_ = window_start_s_;
    if (now_s - kept_up_since_s_ >= settings_.recover_s) {
      state_.behind = false;
      state_.shed_level = std::max(state_.shed_level - 1, 0);
      kept_up_since_s_ = now_s;
    }
  } else {
    kept_up_since_s_ = -1;  // neither: hold what is shed
  }
  window_start_s_ = now_s;
  window_ticks_ = 0;
  window_lag_s_ = 0;
}

PaceState PaceMonitor::state_at(double now_s) const {
  PaceState state = state_;
  // No tick has ended for a while: the one running is that late, and the window that far short.
  const double stalled = now_s - last_tick_s_ - tick_s_;
  if (stalled > settings_.behind_lag_s) {
    state.behind = true;
    state.lag_s = std::max(state.lag_s, stalled);
    const double wall = now_s - window_start_s_;
    if (wall > 0) {
      state.real_time_factor =
          std::min(state.real_time_factor, static_cast<double>(window_ticks_) * tick_s_ / wall);
    }
  }
  return state;
}

}  // namespace incise::server::live
