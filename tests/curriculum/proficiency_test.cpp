#include "curriculum/proficiency.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <string>

namespace incise::curriculum {
namespace {

Task palpation() {
  Task task;
  task.key = "palpation";
  task.metrics = {{"completion_time_s", {ThresholdOp::at_most, 120.0}, "s"},
                  {"path_length_m", {ThresholdOp::at_most, 1.5}, "m"},
                  {"targets_reached", {ThresholdOp::at_least, 0.8}, ""}};
  task.consecutive_passes_required = 3;
  return task;
}

const std::map<std::string, double> good_attempt = {
    {"completion_time_s", 80.0}, {"path_length_m", 1.0}, {"targets_reached", 1.0}};

TEST(Proficiency, ThresholdBoundaryPassesAndNanFails) {
  EXPECT_TRUE(meets_threshold({ThresholdOp::at_most, 4.0}, 4.0));
  EXPECT_TRUE(meets_threshold({ThresholdOp::at_most, 4.0}, -1.0));
  EXPECT_FALSE(meets_threshold({ThresholdOp::at_most, 4.0}, std::nextafter(4.0, 5.0)));
  EXPECT_TRUE(meets_threshold({ThresholdOp::at_least, 0.8}, 0.8));
  EXPECT_FALSE(meets_threshold({ThresholdOp::at_least, 0.8}, std::nextafter(0.8, 0.0)));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(meets_threshold({ThresholdOp::at_most, 4.0}, nan));
  EXPECT_FALSE(meets_threshold({ThresholdOp::at_least, 4.0}, nan));
}

TEST(Proficiency, AttemptPassesWhenEveryMetricMeetsItsThreshold) {
  EXPECT_TRUE(attempt_passes(palpation(), good_attempt));
  // Exactly at every threshold still passes.
  EXPECT_TRUE(attempt_passes(
      palpation(),
      {{"completion_time_s", 120.0}, {"path_length_m", 1.5}, {"targets_reached", 0.8}}));
  // Values the task does not score are ignored.
  std::map<std::string, double> extra = good_attempt;
  extra["peak_force_n"] = 100.0;
  EXPECT_TRUE(attempt_passes(palpation(), extra));
}

TEST(Proficiency, OneFailingMetricFailsTheAttempt) {
  for (const auto& [key, bad_value] : std::map<std::string, double>{
           {"completion_time_s", 120.5}, {"path_length_m", 1.6}, {"targets_reached", 0.7}}) {
    std::map<std::string, double> values = good_attempt;
    values[key] = bad_value;
    EXPECT_FALSE(attempt_passes(palpation(), values)) << key;
  }
}

TEST(Proficiency, MissingMetricFailsTheAttempt) {
  for (const auto& [key, value] : good_attempt) {
    std::map<std::string, double> values = good_attempt;
    values.erase(key);
    EXPECT_FALSE(attempt_passes(palpation(), values)) << key;
  }
  EXPECT_FALSE(attempt_passes(palpation(), {}));
}

TEST(Proficiency, MasteredOnExactlyNConsecutivePasses) {
  const Task task = palpation();  // N = 3
  EXPECT_FALSE(task_mastered(task, {}));
  EXPECT_FALSE(task_mastered(task, {true}));
  EXPECT_FALSE(task_mastered(task, {true, true}));  // N - 1
  EXPECT_TRUE(task_mastered(task, {true, true, true}));
  EXPECT_TRUE(task_mastered(task, {false, true, true, true}));
  EXPECT_TRUE(task_mastered(task, {true, true, true, true, true}));
}

TEST(Proficiency, FailureResetsTheRunButNotMastery) {
  const Task task = palpation();
  EXPECT_FALSE(task_mastered(task, {true, true, false}));
  EXPECT_FALSE(task_mastered(task, {true, true, false, true, true}));
  // Once N in a row passed, the task stays mastered: a later failure only restarts the run.
  EXPECT_TRUE(task_mastered(task, {true, true, true, false}));
  EXPECT_TRUE(task_mastered(task, {false, true, true, true, false, false}));
  EXPECT_EQ(consecutive_passes({true, true, true, false}), 0);
  EXPECT_EQ(consecutive_passes({true, true, false, true, true}), 2);
  EXPECT_EQ(consecutive_passes({true, false}), 0);
  EXPECT_EQ(consecutive_passes({}), 0);
}

TEST(Proficiency, SinglePassMastersWhenNIsOne) {
  Task task = palpation();
  task.consecutive_passes_required = 1;
  EXPECT_TRUE(task_mastered(task, {false, true}));
  EXPECT_TRUE(task_mastered(task, {true, false}));  // mastered at the first pass, and kept
  EXPECT_FALSE(task_mastered(task, {false, false}));
}

}  // namespace
}  // namespace incise::curriculum
