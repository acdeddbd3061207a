#include "curriculum/run_events.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "curriculum/number_text.h"

namespace incise::curriculum {

namespace {

using Vec3 = std::array<double, 3>;

constexpr double kJawClosedBelow = 0.5;  // as motion_metrics: jaw <= this counts as closed

double norm(const Vec3& v) {
  return std::hypot(v[0], v[1], v[2]);
}
double distance(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

void check_thresholds(const EventThresholds& th) {
  const auto check = [](const char* name, double value) {
    if (!std::isfinite(value) || value < 0)
      throw std::invalid_argument("thresholds: " + std::string(name) + " " + shortest_text(value) +
                                  " is not a finite number >= 0");
  };
  check("contact_on_n", th.contact_on_n);
  check("contact_off_n", th.contact_off_n);
  check("zone_margin_m", th.zone_margin_m);
  check("never_force_rearm", th.never_force_rearm);
  // Without these the hysteresis would re-arm while the signal is still above its trigger.
  if (th.contact_off_n > th.contact_on_n)
    throw std::invalid_argument("thresholds: contact_off_n " + shortest_text(th.contact_off_n) +
                                " is above contact_on_n " + shortest_text(th.contact_on_n));
  if (th.never_force_rearm > 1)
    throw std::invalid_argument("thresholds: never_force_rearm " +
                                shortest_text(th.never_force_rearm) + " is above 1");
}

// A rising-edge detector with hysteresis: fires when #trigger holds while armed, and re-arms when
// #rearm holds. Starts armed, so a signal already high in the first sample counts.
struct Edge {
  bool armed = true;
  bool fires(bool trigger, bool rearm) {
    if (armed && trigger) {
      armed = false;
      return true;
    }
    if (rearm) armed = true;
    return false;
  }
};

// The tissue damage [N s] over the interval from sample i - 1 to i of both hands (trapezoid rule on
// the excess over the safe force). Shared by event_metrics and run_timeline so that the timeline's
// last value is exactly the metric.
double interval_damage(std::span<const HandSample> right, std::span<const HandSample> left,
                       std::size_t i, double safe_force_n) {
  const auto excess = [&](const HandSample& s) {
    return std::max(0.0, norm(s.force_n) - safe_force_n);
  };
  const double dt = right[i].t_s - right[i - 1].t_s;
  double damage = 0.5 * dt * (excess(right[i - 1]) + excess(right[i]));
  if (!left.empty()) damage += 0.5 * dt * (excess(left[i - 1]) + excess(left[i]));
  return damage;
}

// Depth along the shaft: how far the tip is past the portal along the tool's axis, (tip - portal)
// . d with d = R(q) e_z (the orientation's +z is the shaft direction into the body, as
// devices/kinematics.h has it). Returns the largest and the time average (trapezoid rule; the
// single value of a run without duration); 0 and 0 for no samples.
std::pair<double, double> shaft_depth(const Vec3& portal, std::span<const HandSample> hand) {
  const auto depth = [&](const HandSample& s) {
    const auto& q = s.orientation;
    const double n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    // R e_z of the normalised quaternion: the third column of its rotation matrix.
    const Vec3 d = {2 * (x * z + w * y) / n2, 2 * (y * z - w * x) / n2,
                    1 - 2 * (x * x + y * y) / n2};
    return (s.tip_m[0] - portal[0]) * d[0] + (s.tip_m[1] - portal[1]) * d[1] +
           (s.tip_m[2] - portal[2]) * d[2];
  };
  if (hand.empty()) return {0.0, 0.0};
  double deepest = depth(hand[0]);
  double integral = 0;
  double previous = deepest;
  for (std::size_t i = 1; i < hand.size(); ++i) {
    const double d = depth(hand[i]);
    deepest = std::max(deepest, d);
    integral += 0.5 * (previous + d) * (hand[i].t_s - hand[i - 1].t_s);
    previous = d;
  }
  const double duration = hand.back().t_s - hand.front().t_s;
  return {deepest, duration > 0 ? integral / duration : deepest};
}

double tissue_damage(const Task& task, std::span<const HandSample> right,
                     std::span<const HandSample> left) {
  double damage = 0;
  for (std::size_t i = 1; i < right.size(); ++i)
    damage += interval_damage(right, left, i, task.safe_force_n);
  return damage;
}

// Each hand's time on the tissue (|force| above kContactForceN at an interval's start), added up.
double tissue_contact(std::span<const HandSample> right, std::span<const HandSample> left) {
  double contact = 0;
  for (const std::span<const HandSample> hand : {right, left}) {
    for (std::size_t i = 1; i < hand.size(); ++i) {
      if (norm(hand[i - 1].force_n) > kContactForceN) contact += hand[i].t_s - hand[i - 1].t_s;
    }
  }
  return contact;
}

// The events of one hand that depend on that hand alone (all but target).
void hand_events(const Task& task, std::span<const HandSample> hand, int h,
                 const EventThresholds& th, std::vector<RunEvent>& events) {
  // Device h holds tools[h]; a hand without a listed tool cuts nothing.
  const auto tool_index = static_cast<std::size_t>(h);
  const std::string tool = tool_index < task.tools.size() ? task.tools[tool_index] : "";
  const bool cutting = is_cutting_tool(tool);
  const double never_force = task.never_force_n;
  Edge contact;
  Edge never_force_edge;
  std::vector<Edge> zone_edges(task.protected_zones.size());
  bool was_pressed = false;  // released before the run, so a press in the first sample counts
  for (std::size_t i = 0; i < hand.size(); ++i) {
    const HandSample& s = hand[i];
    const double force = norm(s.force_n);
    const auto add = [&](EventKind kind, std::string label, int zone = -1) {
      events.push_back({s.t_s, kind, h, std::move(label), zone});
    };
    if (contact.fires(force > th.contact_on_n, force <= th.contact_off_n))
      add(EventKind::contact, "touched tissue");
    if (i > 0 && hand[i - 1].jaw > kJawClosedBelow && s.jaw <= kJawClosedBelow)
      add(EventKind::grasp, "closed the jaws");
    const bool pressed = (s.buttons & 1u) != 0;
    if (cutting && pressed && !was_pressed) add(EventKind::cut, "cut with the " + tool);
    was_pressed = pressed;
    for (std::size_t z = 0; z < zone_edges.size(); ++z) {
      const ProtectedZone& zone = task.protected_zones[z];
      const double d = distance(s.tip_m, zone.zone.center_m);
      if (zone_edges[z].fires(d < zone.zone.radius_m, d >= zone.zone.radius_m + th.zone_margin_m))
        add(zone.never ? EventKind::never_event : EventKind::collision,
            std::string("entered ") + (zone.never ? "never zone" : "protected zone") + " \"" +
                zone.zone.name + "\"",
            static_cast<int>(z));
    }
    if (never_force > 0 &&
        never_force_edge.fires(force > never_force, force < th.never_force_rearm * never_force))
      add(EventKind::never_event,
          "force above the never-event limit of " + shortest_text(never_force) + " N");
  }
}

}  // namespace

std::string_view event_kind_name(EventKind kind) {
  switch (kind) {
    case EventKind::contact:
      return "contact";
    case EventKind::grasp:
      return "grasp";
    case EventKind::release:
      return "release";
    case EventKind::cut:
      return "cut";
    case EventKind::collision:
      return "collision";
    case EventKind::never_event:
      return "never_event";
    case EventKind::target:
      return "target";
  }
  return "unknown";
}

bool is_cutting_tool(std::string_view tool) {
  return tool == "scalpel" || tool == "scissors";
}

std::vector<RunEvent> run_events(const Task& task, std::span<const HandSample> right,
                                 std::span<const HandSample> left,
                                 const EventThresholds& thresholds) {
  check_thresholds(thresholds);
  check_hand_samples(right, left, !left.empty());
  std::vector<RunEvent> events;
  hand_events(task, right, 0, thresholds, events);
  hand_events(task, left, 1, thresholds, events);

  // Targets are shared by the hands: sample by sample, right before left, the first to arrive
  // claims the target.
  std::vector<bool> reached(task.targets.size(), false);
  for (std::size_t i = 0; i < right.size(); ++i) {
    for (int h = 0; h < 2; ++h) {
      const std::span<const HandSample> hand = h == 0 ? right : left;
      if (hand.empty()) continue;
      for (std::size_t k = 0; k < task.targets.size(); ++k) {
        const Zone& target = task.targets[k];
        if (reached[k] || distance(hand[i].tip_m, target.center_m) >= target.radius_m) continue;
        reached[k] = true;
        events.push_back({hand[i].t_s, EventKind::target, h,
                          "reached target \"" + target.name + "\"", static_cast<int>(k)});
      }
    }
  }

  // Stable: simultaneous events of one kind (two zones entered at once) keep the task's order.
  std::stable_sort(events.begin(), events.end(), [](const RunEvent& a, const RunEvent& b) {
    return std::tie(a.t_s, a.hand, a.kind) < std::tie(b.t_s, b.hand, b.kind);
  });
  return events;
}

std::vector<MetricValue> event_metrics(const Task& task, std::span<const HandSample> right,
                                       std::span<const HandSample> left,
                                       std::span<const RunEvent> events) {
  check_hand_samples(right, left, !left.empty());
  double collisions = 0;
  double never_events = 0;
  std::set<int> targets;  // distinct even if the caller repeats an event
  for (const RunEvent& e : events) {
    if (e.kind == EventKind::collision) ++collisions;
    if (e.kind == EventKind::never_event) {
      ++never_events;
      if (e.zone >= 0) ++collisions;  // a never zone's entry, not a never force
    }
    if (e.kind == EventKind::target) targets.insert(e.zone);
  }
  const double visited = static_cast<double>(targets.size());
  const double fraction =
      task.targets.empty() ? 1.0 : visited / static_cast<double>(task.targets.size());
  std::vector<MetricValue> values = {
      {"protected_collisions", collisions, "count"},
      {"never_events", never_events, "count"},
      {"tissue_damage_ns", tissue_damage(task, right, left), "N s"},
      {"tissue_contact_s", tissue_contact(right, left), "s"},
      {"targets_visited", visited, "count"},
      {"targets_fraction", fraction, ""},
  };
  if (task.portal_m) {
    for (const auto& [hand, suffix] : {std::pair(right, ""), std::pair(left, "_left")}) {
      if (hand.empty() && suffix[0] != '\0') continue;
      const auto [deepest, mean] = shaft_depth(*task.portal_m, hand);
      values.push_back({std::string("max_depth_m") + suffix, deepest, "m"});
      values.push_back({std::string("mean_depth_m") + suffix, mean, "m"});
    }
  }
  return values;
}

Timeline run_timeline(const Task& task, std::span<const HandSample> right,
                      std::span<const HandSample> left, double interval_s) {
  if (!std::isfinite(interval_s) || interval_s <= 0)
    throw std::invalid_argument("interval_s " + shortest_text(interval_s) +
                                " is not a finite number > 0");
  check_hand_samples(right, left, !left.empty());
  Timeline timeline;
  timeline.interval_s = interval_s;
  if (right.empty()) return timeline;

  // floor is monotone in t, so bins are visited in order and the last sample is in the last bin.
  const double t0 = right.front().t_s;
  // The small allowance puts a sample on a bin edge (tick 25 x 0.002 s against 0.05 s bins) into
  // the bin it starts, whichever way the division rounds.
  const auto bin_of = [&](double t) {
    return static_cast<std::size_t>(std::floor((t - t0) / interval_s + 1e-9));
  };
  // A cap on the bins, so that a mistyped interval cannot ask for terabytes.
  constexpr double kMaxBins = 1e7;
  if ((right.back().t_s - t0) / interval_s >= kMaxBins)
    throw std::invalid_argument("interval_s " + shortest_text(interval_s) + " gives more than " +
                                shortest_text(kMaxBins) + " bins");
  const std::size_t bins = bin_of(right.back().t_s) + 1;
  timeline.t_s.resize(bins);
  for (std::size_t k = 0; k < bins; ++k)
    timeline.t_s[k] = t0 + static_cast<double>(k) * interval_s;

  const int hands = left.empty() ? 1 : 2;
  for (int h = 0; h < hands; ++h) {
    const std::span<const HandSample> hand = h == 0 ? right : left;
    std::vector<double>& peak = timeline.peak_force_n[h];
    std::vector<double>& speed = timeline.speed_m_s[h];
    peak.assign(bins, 0.0);
    speed.assign(bins, 0.0);
    // The step from sample i - 1 to sample i belongs to sample i's bin, as the damage does.
    std::vector<double> path(bins, 0.0);
    std::vector<double> time(bins, 0.0);
    for (std::size_t i = 0; i < hand.size(); ++i) {
      const std::size_t k = bin_of(hand[i].t_s);
      peak[k] = std::max(peak[k], norm(hand[i].force_n));
      if (i == 0) continue;
      path[k] += distance(hand[i].tip_m, hand[i - 1].tip_m);
      time[k] += hand[i].t_s - hand[i - 1].t_s;
    }
    for (std::size_t k = 0; k < bins; ++k)
      speed[k] = time[k] > 0 ? path[k] / time[k] : 0.0;
  }

  // The interval ending at sample i belongs to sample i's bin, as the path does.
  timeline.damage_ns.assign(bins, 0.0);
  double damage = 0;
  for (std::size_t i = 0; i < right.size(); ++i) {
    if (i > 0) damage += interval_damage(right, left, i, task.safe_force_n);
    timeline.damage_ns[bin_of(right[i].t_s)] = damage;
  }
  // A bin without samples (a gap in the recording) holds the damage reached before it.
  for (std::size_t k = 1; k < bins; ++k)
    timeline.damage_ns[k] = std::max(timeline.damage_ns[k], timeline.damage_ns[k - 1]);
  return timeline;
}

}  // namespace incise::curriculum
