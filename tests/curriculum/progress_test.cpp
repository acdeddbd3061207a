// Where a trainee stands: attempts passed or adjusted, mastery by consecutive passes, and locks
// by prerequisites (curriculum/progress.h).
#include "curriculum/progress.h"

#include <gtest/gtest.h>

namespace incise::curriculum {
namespace {

// Palpation (2 in a row) unlocks the cut (1), which with the two-handed task (1) unlocks the tour.
Curriculum three_steps() {
  Curriculum c;
  c.name = "steps";
  Module basics{"basics", "Basics", {}};
  Task palpation;
  palpation.key = "palpation";
  palpation.name = "Palpation";
  palpation.consecutive_passes_required = 2;
  Task two_hands;
  two_hands.key = "two_hands";
  two_hands.name = "Two-handed palpation";
  Task cut;
  cut.key = "cut";
  cut.name = "Cut along the line";
  cut.prerequisites = {"palpation"};
  Task tour;
  tour.key = "tour";
  tour.name = "Tour";
  tour.prerequisites = {"cut", "two_hands"};
  basics.tasks = {palpation, two_hands, cut};
  Module advanced{"advanced", "Advanced", {tour}};
  c.modules = {basics, advanced};
  return c;
}

AttemptRecord passed(const std::string& task) {
  return {task, true, {true, true}, std::nullopt};
}
AttemptRecord failed(const std::string& task) {
  return {task, true, {true, false}, std::nullopt};
}

TEST(Progress, AnAttemptPassesWhenScoredAndAllPassedUnlessAnInstructorAdjustedIt) {
  EXPECT_TRUE(attempt_passed({"t", true, {true, true}, std::nullopt}));
  EXPECT_FALSE(attempt_passed({"t", true, {true, false}, std::nullopt}));
  EXPECT_FALSE(attempt_passed({"t", true, {}, std::nullopt}));  // never scored
  EXPECT_TRUE(attempt_passed({"t", true, {false}, true}));
  EXPECT_FALSE(attempt_passed({"t", true, {true}, false}));
}

TEST(Progress, LockedUntilEveryPrerequisiteIsMasteredInARow) {
  const Curriculum c = three_steps();
  // Nothing done: only the tasks without prerequisites are open.
  std::vector<TaskProgress> p = curriculum_progress(c, {});
  ASSERT_EQ(p.size(), 4u);
  EXPECT_TRUE(find_progress(p, "palpation")->unlocked());
  EXPECT_EQ(find_progress(p, "cut")->missing_prerequisites, std::vector<std::string>{"palpation"});
  EXPECT_EQ(find_progress(p, "tour")->missing_prerequisites,
            (std::vector<std::string>{"cut", "two_hands"}));
  EXPECT_EQ(locked_reason(c, *find_progress(p, "tour")),
            "task \"Tour\" is locked: master \"Cut along the line\" and \"Two-handed palpation\" "
            "first");
  EXPECT_EQ(locked_reason(c, *find_progress(p, "palpation")), "");

  // Pass, fail, pass: one in a row of two, still locked; a second pass masters it.
  std::vector<AttemptRecord> s = {passed("palpation"), failed("palpation"), passed("palpation")};
  p = curriculum_progress(c, s);
  EXPECT_EQ(find_progress(p, "palpation")->attempts, 3);
  EXPECT_EQ(find_progress(p, "palpation")->passed_attempts, 2);
  EXPECT_EQ(find_progress(p, "palpation")->consecutive_passes, 1);
  EXPECT_FALSE(find_progress(p, "cut")->unlocked());
  s.push_back(passed("palpation"));
  p = curriculum_progress(c, s);
  EXPECT_TRUE(find_progress(p, "palpation")->mastered);
  EXPECT_TRUE(find_progress(p, "cut")->unlocked());
  EXPECT_EQ(locked_reason(c, *find_progress(p, "tour")),
            "task \"Tour\" is locked: master \"Cut along the line\" and \"Two-handed palpation\" "
            "first");

  // Sessions that did not finish are not attempts; an adjustment makes a failed one pass.
  s.push_back({"cut", false, {true}, std::nullopt});
  s.push_back({"two_hands", true, {false}, true});
  s.push_back(passed("cut"));
  p = curriculum_progress(c, s);
  EXPECT_EQ(find_progress(p, "cut")->attempts, 1);
  EXPECT_TRUE(find_progress(p, "two_hands")->mastered);
  EXPECT_TRUE(find_progress(p, "tour")->unlocked());
  EXPECT_EQ(find_progress(p, "tour")->module, "Advanced");

  // A failure after mastery restarts the run but keeps the mastery, and what it unlocked stays
  // open (proficiency.h): practice after moving on does not lock anything again.
  s.push_back(failed("palpation"));
  p = curriculum_progress(c, s);
  EXPECT_TRUE(find_progress(p, "palpation")->mastered);
  EXPECT_EQ(find_progress(p, "palpation")->consecutive_passes, 0);
  EXPECT_TRUE(find_progress(p, "cut")->unlocked());
  EXPECT_EQ(find_progress(p, "nothing"), nullptr);
}

TEST(Progress, TheNextTaskIsTheFirstUnlockedOneNotYetMastered) {
  const Curriculum c = three_steps();
  EXPECT_EQ(next_task(curriculum_progress(c, {})), "palpation");
  // Palpation mastered (2 in a row): the two-handed task comes next, before the cut it unlocked.
  const auto after = curriculum_progress(c, {passed("palpation"), passed("palpation")});
  EXPECT_EQ(next_task(after), "two_hands");
  const auto most = curriculum_progress(
      c, {passed("palpation"), passed("palpation"), passed("two_hands"), passed("cut")});
  EXPECT_EQ(next_task(most), "tour");
  const auto all = curriculum_progress(c, {passed("palpation"), passed("palpation"),
                                           passed("two_hands"), passed("cut"), passed("tour")});
  EXPECT_EQ(next_task(all), "");
}

}  // namespace
}  // namespace incise::curriculum
