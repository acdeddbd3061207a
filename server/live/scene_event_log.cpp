#include "server/live/scene_event_log.h"

#include <cstdio>

namespace incise::server::live {

curriculum::EventKind scene_event_kind(sim::surgery::EventKind kind) {
  using curriculum::EventKind;
  switch (kind) {
    case sim::surgery::EventKind::grasp:
      return EventKind::grasp;
    case sim::surgery::EventKind::release:
      return EventKind::release;
    case sim::surgery::EventKind::cut:
      return EventKind::cut;
    case sim::surgery::EventKind::collision:
      return EventKind::collision;
    case sim::surgery::EventKind::never_event:
      return EventKind::never_event;
  }
  return EventKind::collision;  // not reached: every scene kind is mapped above
}

std::string_view scene_event_name(sim::surgery::EventKind kind) {
  return curriculum::event_kind_name(scene_event_kind(kind));
}

namespace {

std::string cut_label(double area_m2, double outside_m2) {
  char text[96];
  std::snprintf(text, sizeof text, "cut %.1f mm^2, %.1f mm^2 off the marked line", 1e6 * area_m2,
                1e6 * outside_m2);
  return text;
}

}  // namespace

void SceneEventLog::add(std::span<const sim::surgery::SceneEvent> events, double t_s,
                        std::span<const sim::surgery::ToolSpec> tools,
                        const sim::tools::DamageMetrics& damage) {
  for (const auto& e : events) {
    const std::string kind(scene_event_name(e.kind));
    int hand = -1;
    if (e.tool >= 0 && static_cast<std::size_t>(e.tool) < tools.size()) {
      const int device = tools[static_cast<std::size_t>(e.tool)].device;
      if (device == 0 || device == 1) hand = device;
    }
    const bool stroke =
        e.kind == sim::surgery::EventKind::cut || e.kind == sim::surgery::EventKind::never_event;
    Open* open = nullptr;
    for (Open& o : open_) {
      const SceneEventRecord& r = events_[o.index];
      if (r.kind == kind && r.hand == hand) open = &o;
    }
    const bool continues = stroke && open != nullptr && t_s - open->last_t_s <= kStrokeGapS;
    if (continues) {
      open->last_t_s = t_s;
    } else {
      if (events_.size() >= kMaxEvents) {
        ++dropped_;
        continue;
      }
      events_.push_back({t_s, kind, hand, e.detail});
      // A stroke's cut area counts from the end of the tick before its first commit.
      const Open fresh{events_.size() - 1, t_s, cut_area_seen_, outside_seen_};
      if (open != nullptr) {
        *open = fresh;
      } else {
        open = &open_.emplace_back(fresh);
      }
    }
    if (e.kind == sim::surgery::EventKind::cut) {
      events_[open->index].label = cut_label(damage.cut_area - open->area_before,
                                             damage.cut_area_outside_target - open->outside_before);
    }
  }
  cut_area_seen_ = damage.cut_area;
  outside_seen_ = damage.cut_area_outside_target;
}

void SceneEventLog::clear() {
  events_.clear();
  open_.clear();
  dropped_ = 0;
  cut_area_seen_ = 0;
  outside_seen_ = 0;
}

}  // namespace incise::server::live
