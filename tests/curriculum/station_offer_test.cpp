// Which tasks a station offers and why one may not start (curriculum/station_offer.h).
#include "curriculum/station_offer.h"

#include <gtest/gtest.h>

namespace incise::curriculum {
namespace {

Task task(const std::string& key, const std::string& name, const std::string& kind,
          std::vector<std::string> prerequisites = {}) {
  Task t;
  t.key = key;
  t.name = name;
  t.station_kind = kind;
  t.prerequisites = std::move(prerequisites);
  return t;
}

Curriculum plan() {
  Curriculum c;
  c.name = "plan";
  c.modules = {{"basics",
                "Basics",
                {task("palpation", "Palpation", "bench"), task("anywhere", "Knot tying", "")}},
               {"liver", "Liver", {task("cut", "Cut", "laparoscopy", {"palpation"})}}};
  return c;
}

TEST(StationOffer, ATaskFitsAStationOfItsKindOrAnyWhenItNamesNone) {
  const Curriculum c = plan();
  EXPECT_TRUE(station_fits(c.modules[0].tasks[0], "bench"));
  EXPECT_FALSE(station_fits(c.modules[0].tasks[0], "laparoscopy"));
  EXPECT_FALSE(station_fits(c.modules[0].tasks[0], ""));
  EXPECT_TRUE(station_fits(c.modules[0].tasks[1], ""));
  EXPECT_TRUE(station_fits(c.modules[0].tasks[1], "arthroscopy"));
}

TEST(StationOffer, TheMisfitNamesTheTaskTheKindItNeedsAndWhatTheStationIs) {
  const Curriculum c = plan();
  EXPECT_EQ(station_misfit(c.modules[0].tasks[0], "Surgical station", "laparoscopy"),
            "task \"Palpation\" needs a bench station; Surgical station is a laparoscopy station");
  EXPECT_EQ(station_misfit(c.modules[0].tasks[0], "Station 9", ""),
            "task \"Palpation\" needs a bench station; Station 9 declares no kind");
  EXPECT_EQ(station_misfit(c.modules[1].tasks[0], "Station 1", "arthroscopy"),
            "task \"Cut\" needs a laparoscopy station; Station 1 is an arthroscopy station");
  EXPECT_EQ(station_misfit(c.modules[0].tasks[0], "Scope room", "endoscopy"),
            "task \"Palpation\" needs a bench station; Scope room is an endoscopy station");
  EXPECT_EQ(station_misfit(c.modules[0].tasks[0], "Station 1", "bench"), "");
}

TEST(StationOffer, OnlyFittingTasksInOrderWithTheTraineesLocks) {
  const Curriculum c = plan();
  // An instructor: nothing locked.
  const auto bench = station_offer(c, "bench", nullptr);
  ASSERT_EQ(bench.size(), 2u);
  EXPECT_EQ(bench[0].task->key, "palpation");
  EXPECT_EQ(bench[0].module, "Basics");
  EXPECT_EQ(bench[1].task->key, "anywhere");
  const auto lap = station_offer(c, "laparoscopy", nullptr);
  ASSERT_EQ(lap.size(), 2u);
  EXPECT_EQ(lap[0].task->key, "anywhere");
  EXPECT_EQ(lap[1].task->key, "cut");
  EXPECT_EQ(lap[1].locked_reason, "");
  // A trainee who has not mastered palpation: the cut is offered, locked, with the reason.
  const auto progress = curriculum_progress(c, {});
  const auto trainee = station_offer(c, "laparoscopy", &progress);
  ASSERT_EQ(trainee.size(), 2u);
  EXPECT_EQ(trainee[0].locked_reason, "");
  EXPECT_EQ(trainee[1].locked_reason, locked_reason(c, *find_progress(progress, "cut")));
  EXPECT_NE(trainee[1].locked_reason.find("Palpation"), std::string::npos);
  EXPECT_TRUE(station_offer(c, "", nullptr).size() == 1u);
}

}  // namespace
}  // namespace incise::curriculum
