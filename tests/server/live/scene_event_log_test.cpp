// The session's log of a surgical scene's events: server/live/scene_event_log.h.
#include "server/live/scene_event_log.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace incise::server::live {
namespace {

using sim::surgery::EventKind;
using sim::surgery::SceneEvent;

// The scene's tools: 0 a scalpel on device 0, 1 a grasper on device 1, 2 a probe on device 3
// (a device no hand of a session has).
const std::vector<sim::surgery::ToolSpec> kTools = {
    sim::surgery::make_tool(sim::surgery::ToolKind::scalpel, 0),
    sim::surgery::make_tool(sim::surgery::ToolKind::grasper, 1),
    sim::surgery::make_tool(sim::surgery::ToolKind::probe, 3)};

sim::tools::DamageMetrics cut_so_far(double area_mm2, double outside_mm2) {
  sim::tools::DamageMetrics m;
  m.cut_area = area_mm2 * 1e-6;
  m.cut_area_outside_target = outside_mm2 * 1e-6;
  return m;
}

// One vocabulary: each scene kind lands on the platform kind of the same name, and the scene's own
// spelling (which the incise CLI prints) is the platform's.
TEST(SceneEventLog, SceneKindsAreThePlatformsKindsOfTheSameName) {
  for (const EventKind kind : {EventKind::grasp, EventKind::release, EventKind::cut,
                               EventKind::collision, EventKind::never_event}) {
    EXPECT_EQ(curriculum::event_kind_name(scene_event_kind(kind)), sim::surgery::to_string(kind));
    EXPECT_EQ(scene_event_name(kind), sim::surgery::to_string(kind));
  }
  EXPECT_EQ(scene_event_kind(EventKind::grasp), curriculum::EventKind::grasp);
  EXPECT_EQ(scene_event_kind(EventKind::release), curriculum::EventKind::release);
}

TEST(SceneEventLog, TheCommitsOfOneStrokeAreOneCutLabelledWithTheStrokesArea) {
  SceneEventLog log;
  // A first stroke commits 10, 15 and 5 mm^2 (2 off the line) 0.2 s apart; 2 s later a second
  // stroke commits 7 mm^2.
  log.add(std::vector<SceneEvent>{{EventKind::cut, 0, 0, "10 mm^2"}}, 1.0, kTools,
          cut_so_far(10, 0));
  log.add(std::vector<SceneEvent>{{EventKind::cut, 0, 0, "15 mm^2"}}, 1.2, kTools,
          cut_so_far(25, 0));
  log.add(std::vector<SceneEvent>{{EventKind::cut, 0, 0, "5 mm^2"}}, 1.4, kTools,
          cut_so_far(30, 2));
  log.add(std::vector<SceneEvent>{{EventKind::cut, 0, 0, "7 mm^2"}}, 3.4, kTools,
          cut_so_far(37, 2));
  const auto& events = log.events();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, "cut");
  EXPECT_EQ(events[0].hand, 0);
  EXPECT_EQ(events[0].t_s, 1.0);
  EXPECT_EQ(events[0].label, "cut 30.0 mm^2, 2.0 mm^2 off the marked line");
  EXPECT_EQ(events[1].t_s, 3.4);
  EXPECT_EQ(events[1].label, "cut 7.0 mm^2, 0.0 mm^2 off the marked line");
}

TEST(SceneEventLog, GraspsReleasesAndCollisionsAreEachAnEventWithTheirToolsHand) {
  SceneEventLog log;
  const auto none = cut_so_far(0, 0);
  log.add(std::vector<SceneEvent>{{EventKind::grasp, 1, 0, "3 vertices"},
                                  {EventKind::collision, -1, 0, "femur"},
                                  {EventKind::collision, 2, 0, "tibia"}},
          0.5, kTools, none);
  log.add(std::vector<SceneEvent>{{EventKind::release, 1, 0, "opened, 3 vertices"},
                                  {EventKind::grasp, 1, 0, "2 vertices"}},
          0.7, kTools, none);
  const auto& events = log.events();
  ASSERT_EQ(events.size(), 5u);
  EXPECT_EQ(events[0].kind, "grasp");  // the recording's name for a grab
  EXPECT_EQ(events[0].hand, 1);
  EXPECT_EQ(events[0].label, "3 vertices");
  EXPECT_EQ(events[1].kind, "collision");
  EXPECT_EQ(events[1].hand, -1);  // a bone's
  EXPECT_EQ(events[2].hand, -1);  // the probe's device 3 is no hand of a session
  EXPECT_EQ(events[3].kind, "release");
  EXPECT_EQ(events[3].t_s, 0.7);
  EXPECT_EQ(events[4].kind, "grasp");
  EXPECT_EQ(events[4].label, "2 vertices");
}

TEST(SceneEventLog, NeverEventsOfOneStrokeAreOne) {
  SceneEventLog log;
  for (const double t : {1.0, 1.1, 1.3, 2.5}) {
    log.add(std::vector<SceneEvent>{{EventKind::never_event, 0, 0, "a protected tissue was cut"}},
            t, kTools, cut_so_far(0, 0));
  }
  ASSERT_EQ(log.events().size(), 2u);
  EXPECT_EQ(log.events()[0].t_s, 1.0);
  EXPECT_EQ(log.events()[1].t_s, 2.5);
}

TEST(SceneEventLog, ALongSessionKeepsItsFirstEventsAndCountsTheRest) {
  SceneEventLog log;
  for (std::size_t i = 0; i < SceneEventLog::kMaxEvents + 10; ++i) {
    log.add(std::vector<SceneEvent>{{EventKind::collision, -1, 0, "femur"}}, static_cast<double>(i),
            kTools, cut_so_far(0, 0));
  }
  EXPECT_EQ(log.events().size(), SceneEventLog::kMaxEvents);
  EXPECT_EQ(log.dropped(), 10u);
  EXPECT_EQ(log.events().back().t_s, static_cast<double>(SceneEventLog::kMaxEvents - 1));
  log.clear();
  EXPECT_TRUE(log.events().empty());
  EXPECT_EQ(log.dropped(), 0u);
}

}  // namespace
}  // namespace incise::server::live
