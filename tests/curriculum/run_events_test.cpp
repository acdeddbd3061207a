// Tests for curriculum/run_events.h: each event against a trajectory whose crossing times are
// computed here (a straight line through a sphere, force ramps), the hysteresis that turns a
// hovering signal into one event, tissue damage against closed-form areas, the timeline's bins
// against constant signals, and the exact errors for bad input.
#include "curriculum/run_events.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "curriculum/metric_catalogue.h"
#include "metric_test_helpers.h"

namespace incise::curriculum {
namespace {

using testing::error_of;
using testing::metric;

// Samples i = 0 .. n at t = i dt, each filled in by #fill(i, t, sample); orientation identity,
// jaw closed, no force, no buttons unless #fill sets them.
std::vector<HandSample> sampled(int n, double dt,
                                const std::function<void(int, double, HandSample&)>& fill) {
  std::vector<HandSample> samples(n + 1);
  for (int i = 0; i <= n; ++i) {
    samples[i].t_s = i * dt;
    fill(i, samples[i].t_s, samples[i]);
  }
  return samples;
}

// Samples of one value per entry of #values, dt apart, set by #set.
template <typename T>
std::vector<HandSample> stepped(const std::vector<T>& values, double dt,
                                const std::function<void(T, HandSample&)>& set) {
  return sampled(static_cast<int>(values.size()) - 1, dt,
                 [&](int i, double, HandSample& s) { set(values[i], s); });
}

std::vector<HandSample> forces(const std::vector<double>& newtons, double dt = 0.01) {
  return stepped<double>(newtons, dt, [](double f, HandSample& s) { s.force_n = {0, 0, f}; });
}

std::vector<RunEvent> of_kind(const std::vector<RunEvent>& events, EventKind kind) {
  std::vector<RunEvent> result;
  for (const RunEvent& e : events)
    if (e.kind == kind) result.push_back(e);
  return result;
}

ProtectedZone zone(const std::string& name, std::array<double, 3> center, double radius,
                   bool never = false) {
  return {{name, center, radius}, never};
}

// A shaft tilted by theta about x points along d = (0, -sin theta, cos theta). The right hand's
// tip slides along it from the portal at v, sideways offsets (perpendicular to d) changing
// nothing: depth v t, deepest v T, mean v T / 2. The left hand holds its tip 2 cm short of the
// portal (negative depth).
TEST(RunEvents, DepthAlongTheShaftIsMeasuredFromThePortalAlongTheToolAxis) {
  Task task;
  task.portal_m = std::array<double, 3>{0.04, 0.04, 0.1};
  const double theta = 0.3;
  const double v = 0.02;
  const std::array<double, 3> d = {0, -std::sin(theta), std::cos(theta)};
  const std::array<double, 3> side = {1, 0, 0};  // perpendicular to d
  const auto tilted = [&](HandSample& s) {
    s.orientation = {std::cos(theta / 2), std::sin(theta / 2), 0, 0};
  };
  const auto right = sampled(400, 0.005, [&](int i, double t, HandSample& s) {
    tilted(s);
    const double wobble = 0.003 * std::sin(7 * t) * (i % 2 == 0 ? 1 : -1);
    for (int k = 0; k < 3; ++k)
      s.tip_m[k] = (*task.portal_m)[k] + v * t * d[k] + wobble * side[k];
  });
  const auto left = sampled(400, 0.005, [&](int, double, HandSample& s) {
    tilted(s);
    for (int k = 0; k < 3; ++k)
      s.tip_m[k] = (*task.portal_m)[k] - 0.02 * d[k];
  });
  const auto values = event_metrics(task, right, left, run_events(task, right, left));
  const double T = 2.0;
  EXPECT_NEAR(metric(values, "max_depth_m"), v * T, 1e-12);
  EXPECT_NEAR(metric(values, "mean_depth_m"), v * T / 2, 1e-12);  // trapezoid exact for a line
  EXPECT_NEAR(metric(values, "max_depth_m_left"), -0.02, 1e-12);
  EXPECT_NEAR(metric(values, "mean_depth_m_left"), -0.02, 1e-12);

  // Without a portal there is no depth; with one hand, no left-hand depth.
  task.portal_m.reset();
  const auto without = event_metrics(task, right, left, {});
  EXPECT_EQ(
      std::count_if(without.begin(), without.end(),
                    [](const MetricValue& m) { return m.key.find("depth") != std::string::npos; }),
      0);
  task.portal_m = std::array<double, 3>{0.04, 0.04, 0.1};
  const auto one_hand = event_metrics(task, right, {}, {});
  EXPECT_EQ(std::count_if(one_hand.begin(), one_hand.end(),
                          [](const MetricValue& m) { return m.key.ends_with("_left"); }),
            0);
  EXPECT_NEAR(metric(one_hand, "max_depth_m"), v * T, 1e-12);
}

TEST(RunEvents, KindNamesAndCuttingTools) {
  EXPECT_EQ(event_kind_name(EventKind::contact), "contact");
  EXPECT_EQ(event_kind_name(EventKind::grasp), "grasp");
  EXPECT_EQ(event_kind_name(EventKind::release), "release");
  EXPECT_EQ(event_kind_name(EventKind::cut), "cut");
  EXPECT_EQ(event_kind_name(EventKind::collision), "collision");
  EXPECT_EQ(event_kind_name(EventKind::never_event), "never_event");
  EXPECT_EQ(event_kind_name(EventKind::target), "target");
  EXPECT_TRUE(is_cutting_tool("scalpel"));
  EXPECT_TRUE(is_cutting_tool("scissors"));
  EXPECT_FALSE(is_cutting_tool("probe"));
  EXPECT_FALSE(is_cutting_tool("grasper"));
  EXPECT_FALSE(is_cutting_tool(""));
}

TEST(RunEvents, StraightLineEntersASphereAtTheComputedTime) {
  // Along x at v from x = -0.05 m, at y = 0.002 m, past a sphere of radius r centred at x = 0.01:
  // the distance to the centre drops below r when (x - 0.01)^2 + 0.002^2 = r^2.
  const double v = 0.07;
  const double r = 0.005;
  const double dt = 1e-3;
  const double x_enter = 0.01 - std::sqrt(r * r - 0.002 * 0.002);
  const double t_enter = (x_enter + 0.05) / v;
  Task task;
  task.protected_zones = {zone("vessel", {0.01, 0, 0}, r)};
  const auto hand = sampled(1500, dt, [&](int, double t, HandSample& s) {
    s.tip_m = {-0.05 + v * t, 0.002, 0};
  });
  const auto events = run_events(task, hand, {});
  ASSERT_EQ(events.size(), 1u) << "through and out again: one entry";
  EXPECT_EQ(events[0].kind, EventKind::collision);
  EXPECT_EQ(events[0].hand, 0);
  EXPECT_EQ(events[0].label, "entered protected zone \"vessel\"");
  EXPECT_GT(events[0].t_s, t_enter);
  EXPECT_LE(events[0].t_s, t_enter + dt);
  const auto values = event_metrics(task, hand, {}, events);
  EXPECT_EQ(metric(values, "protected_collisions"), 1.0);
  EXPECT_EQ(metric(values, "never_events"), 0.0);
}

TEST(RunEvents, HoveringOnAZoneBoundaryGivesOneEventUntilTheTipLeavesByTheMargin) {
  // Radius 10 mm; the tip sits on the boundary with +-0.2 mm noise (below the 0.5 mm margin),
  // alternately inside and outside, then goes 1 mm out and comes back to hover again.
  const double r = 0.01;
  std::vector<double> distances = {0.05, 0.03};
  for (int i = 0; i < 40; ++i)
    distances.push_back(r + (i % 2 == 0 ? -2e-4 : 2e-4));
  distances.push_back(r + 1e-3);
  for (int i = 0; i < 40; ++i)
    distances.push_back(r + (i % 2 == 0 ? -2e-4 : 2e-4));
  const auto hand = stepped<double>(distances, 0.01, [](double d, HandSample& s) {
    s.tip_m = {0, d, 0};
  });
  Task task;
  task.protected_zones = {zone("nerve", {0, 0, 0}, r, true)};
  const auto events = run_events(task, hand, {});
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].t_s, hand[2].t_s);
  EXPECT_EQ(events[1].t_s, hand[43].t_s);
  for (const RunEvent& e : events) {
    EXPECT_EQ(e.kind, EventKind::never_event);
    EXPECT_EQ(e.label, "entered never zone \"nerve\"");
  }
  const auto values = event_metrics(task, hand, {}, events);
  EXPECT_EQ(metric(values, "protected_collisions"), 2.0) << "never zones are protected zones";
  EXPECT_EQ(metric(values, "never_events"), 2.0);

  // Without a margin every inward step of the noise is a new entry: 20 per hover.
  EventThresholds no_margin;
  no_margin.zone_margin_m = 0;
  EXPECT_EQ(run_events(task, hand, {}, no_margin).size(), 40u);
}

TEST(RunEvents, ARunStartingInsideAZoneCountsTheEntry) {
  Task task;
  task.protected_zones = {zone("vessel", {0, 0, 0}, 0.01)};
  const auto hand = stepped<double>({0.0, 0.005, 0.02}, 0.01, [](double x, HandSample& s) {
    s.tip_m = {x, 0, 0};
  });
  const auto events = run_events(task, hand, {});
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].t_s, 0.0);
}

TEST(RunEvents, ContactStartsWhenARampCrossesTheOnThresholdAndReArmsBelowOff) {
  // Rises at k N/s from 0, so |force| > 0.05 N first at the sample after t = 0.05 / k; falls to
  // 0.02 N (above off) and rises again: the same contact; then to 0 and up again: a second one.
  const double k = 0.7;
  const double dt = 1e-3;
  const double t_on = 0.05 / k;
  const auto hand = sampled(1000, dt, [&](int i, double t, HandSample& s) {
    double f = k * t;
    if (i >= 200 && i < 300) f = 0.02;
    if (i >= 500 && i < 600) f = 0.0;
    s.force_n = {0.6 * f, 0.0, 0.8 * f};  // |force| = f along a slanted direction
  });
  const auto events = run_events(Task{}, hand, {});
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, EventKind::contact);
  EXPECT_GT(events[0].t_s, t_on);
  EXPECT_LE(events[0].t_s, t_on + dt);
  EXPECT_EQ(events[1].kind, EventKind::contact);
  EXPECT_EQ(events[1].t_s, hand[600].t_s);
  EXPECT_EQ(events[0].label, "touched tissue");

  // Armed at the start: a run that begins in contact counts it.
  const auto pressed = forces({1.0, 1.0, 0.0});
  ASSERT_EQ(run_events(Task{}, pressed, {}).size(), 1u);
  EXPECT_EQ(run_events(Task{}, pressed, {})[0].t_s, 0.0);
}

TEST(RunEvents, TissueDamageOfAConstantOverloadIsExcessTimesDuration) {
  // dt = 2^-9 s makes every trapezoid exact: (F - safe) T to the last bit.
  const double dt = 1.0 / 512;
  const int n = 1024;  // T = 2 s
  const auto hand = sampled(n, dt, [](int, double, HandSample& s) { s.force_n = {0, 0, 5}; });
  Task task;
  task.safe_force_n = 3;
  const auto events = run_events(task, hand, {});
  EXPECT_EQ(metric(event_metrics(task, hand, {}, events), "tissue_damage_ns"), (5.0 - 3.0) * 2.0);
  // Under the safe force: no damage at all.
  task.safe_force_n = 5;
  EXPECT_EQ(metric(event_metrics(task, hand, {}, events), "tissue_damage_ns"), 0.0);
}

TEST(RunEvents, TissueDamageOfARampIsTheTriangleAboveTheSafeForce) {
  // F = 4 t over T = 2 s, safe 3 N (reached at t = 0.75, a sample): the excess is a triangle of
  // base 1.25 s and height 5 N, area 25/8 N s. The left hand adds a constant 1 N excess for 2 s.
  const double dt = 1.0 / 512;
  const auto right = sampled(1024, dt, [](int, double t, HandSample& s) {
    s.force_n = {4 * t, 0, 0};
  });
  const auto left = sampled(1024, dt, [](int, double, HandSample& s) { s.force_n = {0, 4, 0}; });
  Task task;
  task.safe_force_n = 3;
  EXPECT_NEAR(
      metric(event_metrics(task, right, {}, run_events(task, right, {})), "tissue_damage_ns"),
      25.0 / 8, 1e-12);
  EXPECT_NEAR(
      metric(event_metrics(task, right, left, run_events(task, right, left)), "tissue_damage_ns"),
      25.0 / 8 + 2.0, 1e-12);
}

TEST(RunEvents, NeverForceFiresAboveTheLimitAndReArmsBelowItsFraction) {
  // Limit 5 N, re-arm below 0.9 x 5 = 4.5 N: 4.7 N does not re-arm, 4 N does.
  Task task;
  task.never_force_n = 5;
  const auto hand = forces({0, 6, 4.7, 6, 4, 6, 5});
  const auto events = of_kind(run_events(task, hand, {}), EventKind::never_event);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].t_s, hand[1].t_s);
  EXPECT_EQ(events[1].t_s, hand[5].t_s);
  EXPECT_EQ(events[0].label, "force above the never-event limit of 5 N");
  const auto values = event_metrics(task, hand, {}, run_events(task, hand, {}));
  EXPECT_EQ(metric(values, "never_events"), 2.0);
  EXPECT_EQ(metric(values, "protected_collisions"), 0.0) << "a force is not a zone entry";
  // No limit: no never events however hard the tool presses.
  task.never_force_n = 0;
  EXPECT_TRUE(of_kind(run_events(task, hand, {}), EventKind::never_event).empty());
}

TEST(RunEvents, GraspOnEachJawClosure) {
  // Closed means jaw <= 0.5; starting closed is not a grasp.
  const auto hand = stepped<double>({0.0, 1.0, 0.8, 0.5, 0.4, 0.6, 0.51, 0.2, 0.2}, 0.01,
                                    [](double jaw, HandSample& s) { s.jaw = jaw; });
  const auto events = run_events(Task{}, hand, {});
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, EventKind::grasp);
  EXPECT_EQ(events[0].t_s, hand[3].t_s);
  EXPECT_EQ(events[1].t_s, hand[7].t_s);
}

TEST(RunEvents, CutOnlyForCuttingToolsOnEachPressOfButtonZero) {
  // Pressed in the first sample (counts), released, pressed and held, bit 1 alone (not a cut),
  // pressed with bit 1 as well: 3 cuts for the scalpel, none for the probe's same presses.
  const std::vector<int> buttons = {1, 0, 1, 1, 2, 3};
  const auto hand =
      stepped<int>(buttons, 0.01, [](int b, HandSample& s) { s.buttons = std::uint8_t(b); });
  Task task;
  task.tools = {"scalpel", "probe"};
  const auto events = run_events(task, hand, hand);
  ASSERT_EQ(events.size(), 3u);
  for (const RunEvent& e : events) {
    EXPECT_EQ(e.kind, EventKind::cut);
    EXPECT_EQ(e.hand, 0);
    EXPECT_EQ(e.label, "cut with the scalpel");
  }
  EXPECT_EQ(events[0].t_s, hand[0].t_s);
  EXPECT_EQ(events[1].t_s, hand[2].t_s);
  EXPECT_EQ(events[2].t_s, hand[5].t_s);
  task.tools = {"probe"};
  EXPECT_TRUE(run_events(task, hand, {}).empty());
  task.tools = {};
  EXPECT_TRUE(run_events(task, hand, {}).empty()) << "no tool listed: nothing cuts";
}

TEST(RunEvents, TargetsAreReachedOncePerRunByWhicheverHandComesFirst) {
  // Targets a, b, c 10 mm apart along x, radius 2 mm. The right hand visits a, leaves, visits a
  // again, then b; the left hand reaches b earlier; nobody reaches c.
  Task task;
  task.targets = {{"a", {0, 0, 0}, 0.002}, {"b", {0.01, 0, 0}, 0.002}, {"c", {0.02, 0, 0}, 0.002}};
  const std::vector<double> right_x = {-0.01, 0, -0.01, 0.0005, 0.005, 0.01};
  const std::vector<double> left_x = {0.03, 0.03, 0.011, 0.03, 0.03, 0.03};
  const auto set_x = [](double x, HandSample& s) { s.tip_m = {x, 0, 0}; };
  const auto right = stepped<double>(right_x, 0.01, set_x);
  const auto left = stepped<double>(left_x, 0.01, set_x);
  const auto events = run_events(task, right, left);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0], (RunEvent{right[1].t_s, EventKind::target, 0, "reached target \"a\"", 0}));
  EXPECT_EQ(events[1], (RunEvent{left[2].t_s, EventKind::target, 1, "reached target \"b\"", 1}));
  const auto values = event_metrics(task, right, left, events);
  EXPECT_EQ(metric(values, "targets_visited"), 2.0);
  EXPECT_EQ(metric(values, "targets_fraction"), 2.0 / 3.0);
  // The right hand alone reaches b itself, later.
  const auto alone = run_events(task, right, {});
  ASSERT_EQ(alone.size(), 2u);
  EXPECT_EQ(alone[1].t_s, right[5].t_s);
  // A task without targets has reached all of them.
  EXPECT_EQ(metric(event_metrics(Task{}, right, {}, {}), "targets_fraction"), 1.0);
}

TEST(RunEvents, TwoHandsEventsCarryTheirHandAndAreSortedByTimeHandKind) {
  // Left touches at sample 1, right at 2; at sample 3 both close their jaws, and the right hand
  // also enters a zone and reaches a target (found after both hands' other events, so the sort
  // must move it before the left hand's grasp).
  Task task;
  task.protected_zones = {zone("duct", {0.1, 0, 0}, 0.01)};
  task.targets = {{"papilla", {0.1, 0, 0}, 0.005}};
  const auto right = stepped<int>({0, 0, 1, 3}, 0.01, [](int code, HandSample& s) {
    s.jaw = code == 3 ? 0.0 : 1.0;
    s.force_n = {0, 0, code == 1 || code == 3 ? 1.0 : 0.0};
    s.tip_m = {code == 3 ? 0.1 : 0.0, 0, 0};
  });
  const auto left = stepped<int>({0, 1, 1, 2}, 0.01, [](int code, HandSample& s) {
    s.jaw = code == 2 ? 0.0 : 1.0;
    s.force_n = {0, 0, code >= 1 ? 1.0 : 0.0};
  });
  const auto events = run_events(task, right, left);
  const std::vector<std::tuple<double, int, EventKind>> expected = {
      {left[1].t_s, 1, EventKind::contact}, {right[2].t_s, 0, EventKind::contact},
      {right[3].t_s, 0, EventKind::grasp},  {right[3].t_s, 0, EventKind::collision},
      {right[3].t_s, 0, EventKind::target}, {left[3].t_s, 1, EventKind::grasp},
  };
  ASSERT_EQ(events.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i)
    EXPECT_EQ(std::tie(events[i].t_s, events[i].hand, events[i].kind), expected[i]) << i;
}

TEST(RunEvents, EventMetricsAreTheFiveInOrderWithUnitsAndDefinitions) {
  const auto values = event_metrics(Task{}, {}, {}, {});
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"protected_collisions", "count"}, {"never_events", "count"},    {"tissue_damage_ns", "N s"},
      {"tissue_contact_s", "s"},         {"targets_visited", "count"}, {"targets_fraction", ""}};
  ASSERT_EQ(values.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(values[i].key, expected[i].first);
    EXPECT_EQ(values[i].unit, expected[i].second);
    // Named and defined in the catalogue, in the unit it is computed in.
    const auto info = find_metric(values[i].key);
    ASSERT_TRUE(info) << values[i].key;
    EXPECT_EQ(info->unit, values[i].unit) << values[i].key;
  }
}

TEST(RunTimeline, ConstantSpeedFillsEveryBinWithThatSpeed) {
  // dt = 2^-10 s and bins of 2^-4 s: 64 samples per bin, bin edges on samples exactly.
  const double dt = 1.0 / 1024;
  const double interval = 1.0 / 16;
  const double v = 0.125;
  const int n = 64 * 10 + 20;  // ten full bins and a partial one
  const auto right = sampled(n, dt, [&](int, double t, HandSample& s) {
    s.tip_m = {v * t, 0.01, 0};
  });
  const auto left = sampled(n, dt, [&](int, double t, HandSample& s) {
    s.tip_m = {0, -2 * v * t, 0};
  });
  const Timeline timeline = run_timeline(Task{}, right, left, interval);
  EXPECT_EQ(timeline.interval_s, interval);
  ASSERT_EQ(timeline.t_s.size(), 11u);
  for (std::size_t k = 0; k < timeline.t_s.size(); ++k) {
    EXPECT_EQ(timeline.t_s[k], k * interval);
    EXPECT_NEAR(timeline.speed_m_s[0][k], v, 1e-12) << k;
    EXPECT_NEAR(timeline.speed_m_s[1][k], 2 * v, 1e-12) << k;
  }
  // One-handed: the left vectors stay empty.
  const Timeline one = run_timeline(Task{}, right, {}, interval);
  EXPECT_TRUE(one.speed_m_s[1].empty());
  EXPECT_TRUE(one.peak_force_n[1].empty());
  EXPECT_EQ(one.speed_m_s[0].size(), 11u);

  // Sparse samples, one per bin: each bin still has the speed of the step into it (bin 0 has no
  // step). The speed doubles halfway.
  const auto sparse = sampled(8, interval, [&](int i, double t, HandSample& s) {
    s.tip_m = {i <= 4 ? v * t : v * 4 * interval + 2 * v * (t - 4 * interval), 0, 0};
  });
  const Timeline coarse = run_timeline(Task{}, sparse, {}, interval);
  ASSERT_EQ(coarse.speed_m_s[0].size(), 9u);
  EXPECT_EQ(coarse.speed_m_s[0][0], 0.0);
  for (std::size_t k = 1; k < 9; ++k)
    EXPECT_NEAR(coarse.speed_m_s[0][k], k <= 4 ? v : 2 * v, 1e-12) << k;
}

TEST(RunTimeline, KeepsForceSpikesAndAccumulatesDamageToTheMetric) {
  // 1 N everywhere, one 10 N sample in bin 3; safe force 0.5 N. The interval ending at a sample
  // counts in that sample's bin, so the damage at the end of bin k is the integral up to its last
  // sample, t = (64 (k + 1) - 1) dt, except around the spike.
  const double dt = 1.0 / 1024;
  const double interval = 1.0 / 16;
  const int spike = 64 * 3 + 10;
  const auto hand = sampled(64 * 6 - 1, dt, [&](int i, double, HandSample& s) {
    s.force_n = {i == spike ? 10.0 : 1.0, 0, 0};
  });
  Task task;
  task.safe_force_n = 0.5;
  const Timeline timeline = run_timeline(task, hand, {}, interval);
  ASSERT_EQ(timeline.t_s.size(), 6u);
  ASSERT_EQ(timeline.damage_ns.size(), 6u);
  const double spike_extra = (10.0 - 1.0) * dt;  // two half-intervals of 9 N more excess
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(timeline.peak_force_n[0][k], k == 3 ? 10.0 : 1.0) << k;
    const double expected = 0.5 * (64.0 * (k + 1) - 1) * dt + (k >= 3 ? spike_extra : 0.0);
    EXPECT_NEAR(timeline.damage_ns[k], expected, 1e-12) << k;
    if (k > 0) {
      EXPECT_GE(timeline.damage_ns[k], timeline.damage_ns[k - 1]);
    }
  }
  EXPECT_EQ(timeline.damage_ns.back(),
            metric(event_metrics(task, hand, {}, {}), "tissue_damage_ns"));
}

TEST(RunTimeline, ABinWithoutSamplesIsZeroAndKeepsTheDamage) {
  // Samples at 0, 0.1 and 0.35 s with bins of 0.1 s: bin 2 holds none.
  const auto hand = stepped<double>({0.0, 0.1, 0.35}, 1.0, [](double t, HandSample& s) {
    s.t_s = t;
    s.force_n = {2, 0, 0};
    s.tip_m = {t, 0, 0};
  });
  Task task;
  task.safe_force_n = 1;
  const Timeline timeline = run_timeline(task, hand, {}, 0.1);
  ASSERT_EQ(timeline.t_s.size(), 4u);
  EXPECT_EQ(timeline.peak_force_n[0][2], 0.0);
  EXPECT_EQ(timeline.speed_m_s[0][2], 0.0);
  // The tip moves at 1 m/s: the steps into bins 1 and 3 (from 0 to 0.1 s, from 0.1 to 0.35 s).
  EXPECT_NEAR(timeline.speed_m_s[0][1], 1.0, 1e-12);
  EXPECT_NEAR(timeline.speed_m_s[0][3], 1.0, 1e-12);
  EXPECT_EQ(timeline.speed_m_s[0][0], 0.0) << "no step ends in the first bin";
  EXPECT_NEAR(timeline.damage_ns[1], 0.1, 1e-15);
  EXPECT_EQ(timeline.damage_ns[2], timeline.damage_ns[1]);
  EXPECT_NEAR(timeline.damage_ns[3], 0.35, 1e-15);
  EXPECT_TRUE(run_timeline(task, {}, {}, 0.1).t_s.empty());
}

TEST(RunEvents, BadInputIsRejectedWithTheSampleNamed) {
  const auto good = forces({0, 1, 2});
  auto nan_force = good;
  nan_force[1].force_n[2] = std::numeric_limits<double>::quiet_NaN();
  auto inf_tip = good;
  inf_tip[2].tip_m[0] = std::numeric_limits<double>::infinity();
  auto backwards = good;
  backwards[2].t_s = 0.005;
  auto bad_jaw = good;
  bad_jaw[0].jaw = 1.5;
  auto shifted = good;
  shifted[1].t_s = 0.011;
  const Task task;
  EXPECT_EQ(error_of([&] { run_events(task, nan_force, {}); }), "sample 1: force_n is not finite");
  EXPECT_EQ(error_of([&] { run_events(task, good, inf_tip); }),
            "left sample 2: tip_m is not finite");
  EXPECT_EQ(error_of([&] { run_events(task, backwards, {}); }),
            "sample 2: t_s 0.005 is before the previous sample's 0.01");
  EXPECT_EQ(error_of([&] { run_events(task, bad_jaw, good); }),
            "right sample 0: jaw 1.5 is outside [0, 1]");
  EXPECT_EQ(error_of([&] {
              run_events(task, good, forces({0, 1}));
            }),
            "right has 3 samples but left has 2");
  EXPECT_EQ(error_of([&] { run_events(task, good, shifted); }),
            "sample 1: left t_s 0.011 differs from right t_s 0.01");
  EXPECT_EQ(error_of([&] { event_metrics(task, nan_force, {}, {}); }),
            "sample 1: force_n is not finite");
  EXPECT_EQ(error_of([&] { run_timeline(task, good, shifted, 0.1); }),
            "sample 1: left t_s 0.011 differs from right t_s 0.01");
  EventThresholds inverted;
  inverted.contact_off_n = 0.1;
  EXPECT_EQ(error_of([&] { run_events(task, good, {}, inverted); }),
            "thresholds: contact_off_n 0.1 is above contact_on_n 0.05");
}

TEST(RunTimeline, IntervalMustBeFiniteAndPositive) {
  const auto good = forces({0, 1, 2});
  EXPECT_EQ(error_of([&] { run_timeline(Task{}, good, {}, 0); }),
            "interval_s 0 is not a finite number > 0");
  EXPECT_EQ(error_of([&] { run_timeline(Task{}, good, {}, -0.1); }),
            "interval_s -0.1 is not a finite number > 0");
  EXPECT_EQ(error_of([&] { run_timeline(Task{}, good, {}, std::nan("")); }),
            "interval_s nan is not a finite number > 0");
  EXPECT_EQ(error_of([&] { run_timeline(Task{}, good, {}, 1e-12); }),
            "interval_s 1e-12 gives more than 1e+07 bins");
}

}  // namespace
}  // namespace incise::curriculum
