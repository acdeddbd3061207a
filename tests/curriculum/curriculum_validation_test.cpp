#include "curriculum/curriculum_validation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "curriculum/curriculum_json.h"
#include "sample_curriculum.h"

namespace incise::curriculum {
namespace {

// Curricula built in code (e.g. edited by an admin and stored by the database) get the same
// checks and paths as parsed ones.
void expect_error(const Curriculum& curriculum, const std::string& expected) {
  try {
    validate(curriculum);
    ADD_FAILURE() << "accepted, expected \"" << expected << "\"";
  } catch (const CurriculumError& error) {
    EXPECT_EQ(std::string(error.what()), expected);
  }
}

Curriculum sample() {
  return parse_curriculum(sample_curriculum_json());
}

TEST(CurriculumValidation, SampleIsValid) {
  EXPECT_NO_THROW(validate(sample()));
}

TEST(CurriculumValidation, ConsecutivePassesMustBeAtLeastOne) {
  Curriculum curriculum = sample();
  curriculum.modules[1].tasks[0].consecutive_passes_required = 0;
  expect_error(
      curriculum,
      "modules[1].tasks[0].consecutive_passes_required: must be an integer from 1 to 1000");
  curriculum.modules[1].tasks[0].consecutive_passes_required = max_consecutive_passes + 1;
  expect_error(
      curriculum,
      "modules[1].tasks[0].consecutive_passes_required: must be an integer from 1 to 1000");
  curriculum.modules[1].tasks[0].consecutive_passes_required = max_consecutive_passes;
  EXPECT_NO_THROW(validate(curriculum));
}

TEST(CurriculumValidation, ThresholdMustBeFinite) {
  Curriculum curriculum = sample();
  curriculum.modules[0].tasks[1].metrics[1].threshold.value =
      std::numeric_limits<double>::infinity();
  expect_error(curriculum,
               "modules[0].tasks[1].metrics[1].threshold.value: must be a finite number");
  curriculum.modules[0].tasks[1].metrics[1].threshold.value =
      std::numeric_limits<double>::quiet_NaN();
  expect_error(curriculum,
               "modules[0].tasks[1].metrics[1].threshold.value: must be a finite number");
}

TEST(CurriculumValidation, NamesMustNotBeEmpty) {
  Curriculum curriculum = sample();
  curriculum.name.clear();
  expect_error(curriculum, "name: must not be empty");
  curriculum = sample();
  curriculum.modules[1].name.clear();
  expect_error(curriculum, "modules[1].name: must not be empty");
  curriculum = sample();
  curriculum.modules[1].tasks.clear();
  expect_error(curriculum, "modules[1].tasks: must list at least one task");
  curriculum = sample();
  curriculum.modules[1].tasks[0].prerequisites.push_back("");
  expect_error(curriculum, "modules[1].tasks[0].prerequisites[2]: must not be empty");
}

TEST(CurriculumValidation, ReferencesAreCheckedAfterEveryTaskIsKnown) {
  // A prerequisite may name a task defined later in the document.
  Curriculum curriculum = sample();
  curriculum.modules[0].tasks[0].prerequisites = {};
  curriculum.modules[0].tasks[1].prerequisites = {"incision"};
  curriculum.modules[1].tasks[0].prerequisites = {"palpation"};
  EXPECT_NO_THROW(validate(curriculum));
}

TEST(CurriculumValidation, ZonesAndTargetsMustBeFiniteSpheres) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  Curriculum curriculum = sample();
  Task& task = curriculum.modules[1].tasks[0];
  task.protected_zones = {{{"artery", {0, 0, 0.1}, 0.003}, true}};
  task.targets = {{"mark_a", {0.01, 0, 0.1}, 0.002}, {"mark_b", {0.02, 0, 0.1}, 0.002}};
  EXPECT_NO_THROW(validate(curriculum));
  task.targets[1].center_m[1] = nan;
  expect_error(curriculum, "modules[1].tasks[0].targets[1].center_m[1]: must be a finite number");
  task.targets[1].center_m[1] = 0;
  task.protected_zones[0].zone.center_m[0] = -inf;
  expect_error(curriculum,
               "modules[1].tasks[0].protected_zones[0].center_m[0]: must be a finite number");
  task.protected_zones[0].zone.center_m[0] = 0;
  task.protected_zones[0].zone.radius_m = inf;
  expect_error(curriculum,
               "modules[1].tasks[0].protected_zones[0].radius_m: must be a finite number above 0");
  task.protected_zones[0].zone.radius_m = nan;
  expect_error(curriculum,
               "modules[1].tasks[0].protected_zones[0].radius_m: must be a finite number above 0");
  task.protected_zones[0].zone.radius_m = 0.003;
  task.targets[1].name = "mark_a";
  expect_error(curriculum,
               "modules[1].tasks[0].targets[1].name: duplicate zone or target name \"mark_a\" "
               "(first at modules[1].tasks[0].targets[0])");
  task.targets[1].name = "";
  expect_error(curriculum, "modules[1].tasks[0].targets[1].name: must not be empty");
}

TEST(CurriculumValidation, ForcesMustBeFiniteAndTheNeverForceAboveTheSafeOne) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Curriculum curriculum = sample();
  Task& task = curriculum.modules[0].tasks[1];
  task.safe_force_n = nan;
  expect_error(curriculum, "modules[0].tasks[1].safe_force_n: must be a finite number above 0");
  task.safe_force_n = -3;
  expect_error(curriculum, "modules[0].tasks[1].safe_force_n: must be a finite number above 0");
  task.safe_force_n = 3;
  task.never_force_n = nan;
  expect_error(curriculum,
               "modules[0].tasks[1].never_force_n: must be a finite number, 0 (no limit) or more");
  task.never_force_n = std::numeric_limits<double>::infinity();
  expect_error(curriculum,
               "modules[0].tasks[1].never_force_n: must be a finite number, 0 (no limit) or more");
  task.never_force_n = 3;
  expect_error(curriculum,
               "modules[0].tasks[1].never_force_n: must be 0 (no limit) or above safe_force_n 3");
  task.never_force_n = std::nextafter(3.0, 4.0);  // just above the safe force: allowed
  EXPECT_NO_THROW(validate(curriculum));
  task.never_force_n = 0;
  EXPECT_NO_THROW(validate(curriculum));
}

// A never event fails the attempt outright: a task naming never_events may only ask for none.
TEST(CurriculumValidation, NeverEventsMayOnlyBeRequiredToBeNone) {
  Curriculum curriculum = sample();
  Task& task = curriculum.modules[0].tasks[0];
  const std::string where = "modules[0].tasks[0].metrics[" + std::to_string(task.metrics.size()) +
                            "].threshold: never_events must be \"<=\" 0: a never event fails "
                            "the attempt";
  task.metrics.push_back({"never_events", {ThresholdOp::at_most, 2.0}, "count"});
  expect_error(curriculum, where);
  task.metrics.back().threshold = {ThresholdOp::at_least, 0.0};
  expect_error(curriculum, where);
  task.metrics.back().threshold = {ThresholdOp::at_most, 0.0};
  EXPECT_NO_THROW(validate(curriculum));
}

TEST(CurriculumValidation, KeySyntax) {
  EXPECT_TRUE(is_valid_key("palpation"));
  EXPECT_TRUE(is_valid_key("peak_force_n"));
  EXPECT_TRUE(is_valid_key("task2"));
  EXPECT_FALSE(is_valid_key(""));
  EXPECT_FALSE(is_valid_key("2task"));
  EXPECT_FALSE(is_valid_key("_task"));
  EXPECT_FALSE(is_valid_key("Task"));
  EXPECT_FALSE(is_valid_key("peak force"));
  EXPECT_FALSE(is_valid_key("peak-force"));
}

// A threshold outside the values its metric can take (metric_catalogue.h) is a typing error: a
// time of -5 s would fail every attempt, a share above 1 too.
TEST(CurriculumValidation, ThresholdsStayWithinTheirMetricsRange) {
  Curriculum curriculum = sample();
  Task& task = curriculum.modules[0].tasks[0];
  task.metrics = {{"completion_time_s", {ThresholdOp::at_most, -5}, "s"}};
  expect_error(curriculum,
               "modules[0].tasks[0].metrics[0].threshold.value: must be 0 s or more for "
               "completion_time_s");
  task.metrics = {{"economy_of_motion", {ThresholdOp::at_least, 1.5}, ""}};
  expect_error(curriculum,
               "modules[0].tasks[0].metrics[0].threshold.value: must be from 0 to 1 for "
               "economy_of_motion");
  task.metrics = {{"path_length_m_left", {ThresholdOp::at_most, -0.1}, "m"}};
  expect_error(curriculum,
               "modules[0].tasks[0].metrics[0].threshold.value: must be 0 m or more for "
               "path_length_m_left");
  // The boundaries are values; smoothness has no bound; unknown keys are not judged here.
  task.metrics = {{"economy_of_motion", {ThresholdOp::at_least, 1}, ""},
                  {"completion_time_s", {ThresholdOp::at_most, 0}, "s"},
                  {"log_dimensionless_jerk", {ThresholdOp::at_least, -12}, ""},
                  {"some_new_metric", {ThresholdOp::at_least, -3}, ""}};
  EXPECT_NO_THROW(validate(curriculum));
}

}  // namespace
}  // namespace incise::curriculum
