#include "curriculum/curriculum_validation.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace incise::curriculum
