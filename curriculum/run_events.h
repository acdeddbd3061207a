#pragma once
// What happened during a recorded attempt, when: events (contact, grasp, cut, collision with a
// protected structure, never event, target reached), their metrics, and a downsampled timeline of
// force, speed and tissue damage for the instructor's review. Pure
// functions over the recorded hand streams, like motion_metrics.h, so that scoring, the review
// page and the tests see the same events.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "curriculum/curriculum.h"
#include "curriculum/metrics.h"
#include "curriculum/motion_metrics.h"

namespace incise::curriculum {

enum class EventKind {
  contact,      // the tool starts touching tissue
  grasp,        // the jaw closes
  release,      // a grasper lets go (surgical scenes only: the scene reports it)
  cut,          // a cutting tool's primary button is pressed
  collision,    // the tip enters a protected zone
  never_event,  // the tip enters a never zone, or the force rises above the never force
  target,       // the tip reaches a target (landmark) for the first time
};

// "contact", "grasp", "release", "cut", "collision", "never_event", "target": the one spelling of
// event kinds in the API, the database and the dashboard. The surgical scene's events
// (sim::surgery::EventKind) are mapped onto these at the server (server/live/scene_event_log.h),
// since neither sim/ nor curriculum/ may depend on the other.
std::string_view event_kind_name(EventKind kind);

struct RunEvent {
  double t_s = 0;  // the sample time at which it happened
  EventKind kind = EventKind::contact;
  int hand = 0;       // 0: device 0 (right), 1: device 1 (left)
  std::string label;  // one line for the dashboard, e.g. "entered protected zone \"vessel\""
  // The zone of a zone entry (collision, never_event): its index in task.protected_zones; of a
  // target event: its index in task.targets; -1 otherwise (e.g. a never force).
  int zone = -1;

  bool operator==(const RunEvent&) const = default;
};

// How events are told from noise: each starts on a rising edge and re-arms only after the
// signal has fallen back (hysteresis), so a signal hovering at a threshold gives one event.
struct EventThresholds {
  double contact_on_n = 0.05;      // contact starts when |force| rises above this ...
  double contact_off_n = 0.01;     // ... after having been at or below this (or at the start)
  double zone_margin_m = 0.5e-3;   // a zone is left when the tip is this far outside its radius
  double never_force_rearm = 0.9;  // a never force re-arms below this fraction of the limit
};

// True for tools that cut with their primary button (bit 0): "scalpel", "scissors".
bool is_cutting_tool(std::string_view tool);

// The events of an attempt, sorted by time (ties: hand 0 first, then in EventKind order). Per
// hand h (#left may be empty for a one-handed run; otherwise sample-aligned with #right):
//   contact      |force| > contact_on_n after |force| <= contact_off_n (the run starts armed)
//   grasp        jaw_i > 0.5 and jaw_{i+1} <= 0.5 (motion_metrics' jaw closure), at t_{i+1}
//   cut          task.tools[h] is a cutting tool and button bit 0 goes from released to pressed
//                (pressed in the first sample counts)
//   collision    the tip enters a protected zone that is not never: distance to the centre
//                < radius, after having been >= radius + zone_margin_m (or at the start);
//                label names the zone
//   never_event  the same for a never zone; and |force| > task.never_force_n (when > 0) after
//                having been below never_force_rearm x never_force_n (or at the start)
//   target       the tip is within a target's radius for the first time in the run (by any hand)
// Throws std::invalid_argument for samples as hand_metrics does and for misaligned hands as
// bimanual_metrics does.
std::vector<RunEvent> run_events(const Task& task, std::span<const HandSample> right,
                                 std::span<const HandSample> left,
                                 const EventThresholds& thresholds = {});

// The event metrics of an attempt, in this order:
//   protected_collisions  number of collision and never-zone events (entries into any protected
//                         zone) [count]
//   never_events          number of never_event events [count]
//   tissue_damage_ns      integral over the run of max(0, |force| - task.safe_force_n) dt,
//                         summed over both hands, trapezoid rule on each interval [N s]: how long
//                         and how far the tissue was overloaded
//   tissue_contact_s      sum over both hands of t_{i+1} - t_i over the samples i with |force_i|
//                         > kContactForceN [s]: the tools' time on the tissue (completion
//                         criteria, Task::completion)
//   targets_visited       number of distinct targets reached (target events) [count]
//   targets_fraction      targets_visited / number of targets; 1 when the task has none
// and, when task.portal_m is set, the depth along the shaft of each hand (the left hand's keys end
// in "_left"), depth_i = (tip_i - portal) . d_i with d_i the shaft direction, the tool
// orientation's +z axis (devices/kinematics.h):
//   max_depth_m           max over i of depth_i [m]
//   mean_depth_m          integral of depth dt / duration, trapezoid rule; depth_0 for a run
//                         without duration [m]
// #events: run_events of the same samples.
std::vector<MetricValue> event_metrics(const Task& task, std::span<const HandSample> right,
                                       std::span<const HandSample> left,
                                       std::span<const RunEvent> events);

// An attempt's signals downsampled to one value per interval, for plotting under the replay.
// Bin k covers [t_0 + k interval, t_0 + (k + 1) interval); t_s[k] is its start. Per hand (index 0
// right, 1 left; the left vectors are empty for a one-handed run):
//   peak_force_n  the largest |force| of the samples in the bin (spikes are not averaged away)
//   speed_m_s     the tip's path over the steps that end in the bin (from the sample before to
//                 one in the bin) / their duration; 0 when they take no time
// and for the run:
//   damage_ns     tissue_damage_ns accumulated up to the end of the bin (non-decreasing)
struct Timeline {
  double interval_s = 0;
  std::vector<double> t_s;
  std::vector<double> peak_force_n[2];
  std::vector<double> speed_m_s[2];
  std::vector<double> damage_ns;
};

// Throws std::invalid_argument for interval_s <= 0 or non-finite, and as run_events does.
Timeline run_timeline(const Task& task, std::span<const HandSample> right,
                      std::span<const HandSample> left, double interval_s);

}  // namespace incise::curriculum
