#pragma once
// What a surgical scene's tools did during a session, as the review's markers: the scene's events
// (sim/surgery/surgical_scene.h: grab, release, cut, collision, never event) with the session
// time and the hand whose tool it was. A scalpel commits a cut every few steps while it moves
// through tissue; the commits of one stroke (same kind and hand, each within kStrokeGapS of the
// last) make one event, whose label sums the stroke's cut area from the damage tracker.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "curriculum/run_events.h"
#include "sim/surgery/surgical_scene.h"
#include "sim/tools/damage_metrics.h"

namespace incise::server::live {

struct SceneEventRecord {
  double t_s = 0;     // [s] session time of the first occurrence
  std::string kind;   // "grasp", "release", "cut", "collision", "never_event"
  int hand = -1;      // the device of the tool (0 right, 1 left), -1 for none (a bone)
  std::string label;  // one line, e.g. "cut 42.0 mm^2, 0.0 mm^2 off target"
};

class SceneEventLog {
 public:
  static constexpr double kStrokeGapS = 0.5;
  // A session that runs for hours keeps its first events and counts the rest (dropped()).
  static constexpr std::size_t kMaxEvents = 5000;

  // Adds the scene's events of a tick that ended at t_s. tools: the scene's tool specs (for the
  // devices); damage: the scene's damage metrics after the tick (for the cut labels).
  void add(std::span<const sim::surgery::SceneEvent> events, double t_s,
           std::span<const sim::surgery::ToolSpec> tools, const sim::tools::DamageMetrics& damage);
  void clear();

  const std::vector<SceneEventRecord>& events() const { return events_; }
  std::size_t dropped() const { return dropped_; }

 private:
  struct Open {
    std::size_t index = 0;  // into events_
    double last_t_s = 0;
    double area_before = 0;     // the damage tracker's cut area before the stroke [m^2]
    double outside_before = 0;  // and its area off target [m^2]
  };
  std::vector<SceneEventRecord> events_;
  std::vector<Open> open_;  // the last event of each (kind, hand), for merging strokes
  std::size_t dropped_ = 0;
  double cut_area_seen_ = 0;  // the damage tracker's cut area after the last tick [m^2]
  double outside_seen_ = 0;   // and its area off target [m^2]
};

// A scene event's kind in the platform's one vocabulary of event kinds (curriculum/run_events.h),
// and its name there.
curriculum::EventKind scene_event_kind(sim::surgery::EventKind kind);
std::string_view scene_event_name(sim::surgery::EventKind kind);

}  // namespace incise::server::live
