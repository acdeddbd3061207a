#include "curriculum/curriculum.h"

#include <gtest/gtest.h>

#include "curriculum/curriculum_json.h"
#include "sample_curriculum.h"

namespace incise::curriculum {
namespace {

TEST(Curriculum, FindTaskSearchesEveryModule) {
  const Curriculum curriculum = parse_curriculum(sample_curriculum_json());
  ASSERT_NE(find_task(curriculum, "incision"), nullptr);
  EXPECT_EQ(find_task(curriculum, "incision")->name, "Straight incision");
  EXPECT_EQ(find_task(curriculum, "palpation"), &curriculum.modules[0].tasks[0]);
  EXPECT_EQ(find_task(curriculum, "suturing"), nullptr);
}

TEST(Curriculum, ThresholdOpSymbols) {
  EXPECT_EQ(threshold_op_symbol(ThresholdOp::at_most), "<=");
  EXPECT_EQ(threshold_op_symbol(ThresholdOp::at_least), ">=");
}

}  // namespace
}  // namespace incise::curriculum
