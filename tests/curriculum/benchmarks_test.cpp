#include "curriculum/benchmarks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace incise::curriculum {
namespace {

// 2, 4, 4, 4, 5, 5, 7, 9: mean 5, sum of squared deviations 32, so the sample SD is sqrt(32 / 7).
TEST(Benchmarks, MeanAndSampleStandardDeviationMatchTheTextbookExample) {
  const std::vector<double> values = {9, 4, 2, 4, 5, 5, 7, 4};
  const auto stats = summarize(values);
  EXPECT_EQ(stats.n, 8);
  EXPECT_DOUBLE_EQ(stats.mean, 5.0);
  EXPECT_DOUBLE_EQ(stats.sd, std::sqrt(32.0 / 7.0));
  // Sorted 2 4 4 4 5 5 7 9: the median halfway between ranks 3 and 4; p10 at rank 0.7 between 2
  // and 4; p90 at rank 6.3 between 7 and 9.
  EXPECT_DOUBLE_EQ(stats.median, 4.5);
  EXPECT_DOUBLE_EQ(stats.p10, 2 + 0.7 * 2);
  EXPECT_DOUBLE_EQ(stats.p90, 7 + 0.3 * 2);
}

TEST(Benchmarks, TheSpreadStaysAccurateFarFromZero) {
  const std::vector<double> values = {1e9 + 1, 1e9 + 2, 1e9 + 3};
  EXPECT_NEAR(summarize(values).sd, 1.0, 1e-9);
}

TEST(Benchmarks, RelativeScoreCountsExpertStandardDeviations) {
  const std::vector<double> values = {2, 4};  // mean 3, sd sqrt(2)
  const auto stats = summarize(values);
  EXPECT_DOUBLE_EQ(relative_score(3 + 2 * std::sqrt(2.0), stats), 2.0);
  EXPECT_DOUBLE_EQ(relative_score(3, stats), 0.0);
  EXPECT_DOUBLE_EQ(relative_score(3 - std::sqrt(2.0), stats), -1.0);
}

TEST(Benchmarks, ASingleRunOrRunsThatDoNotVaryHaveNoRelativeScore) {
  const std::vector<double> one = {3};
  const auto single = summarize(one);
  EXPECT_EQ(single.sd, 0.0);
  EXPECT_EQ(single.median, 3.0);
  EXPECT_TRUE(std::isnan(relative_score(4, single)));
  const std::vector<double> same = {3, 3, 3};
  EXPECT_TRUE(std::isnan(relative_score(4, summarize(same))));
}

TEST(Benchmarks, BadInputIsRefused) {
  EXPECT_THROW(summarize({}), std::invalid_argument);
  const std::vector<double> nan = {1, std::nan("")};
  EXPECT_THROW(summarize(nan), std::invalid_argument);
  const std::vector<double> sorted = {1, 2};
  EXPECT_THROW(percentile(sorted, 1.5), std::invalid_argument);
  EXPECT_THROW(percentile(sorted, -0.1), std::invalid_argument);
  EXPECT_DOUBLE_EQ(percentile(sorted, 1.0), 2.0);
}

TEST(Benchmarks, ExpertScoresAreGroupedByTaskAndMetricAndSummarised) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<ExpertScore> scores = {{"palpation", "peak_force_n", 2.0, "N"},
                                           {"cut", "cut_area_m2", 1e-4, "m^2"},
                                           {"palpation", "peak_force_n", 4.0, "N"},
                                           {"palpation", "log_dimensionless_jerk", nan, ""},
                                           {"palpation", "peak_force_n", 3.0, "N"}};
  const auto groups = group_benchmarks(scores);
  ASSERT_EQ(groups.size(), 2u);  // the unmeasurable jerk is left out, and its empty group
  const auto& peak = groups.at({"palpation", "peak_force_n"});
  EXPECT_EQ(peak.unit, "N");
  EXPECT_EQ(peak.stats.n, 3);
  EXPECT_DOUBLE_EQ(peak.stats.mean, 3.0);
  EXPECT_DOUBLE_EQ(peak.stats.sd, 1.0);
  EXPECT_DOUBLE_EQ(peak.stats.median, 3.0);
  EXPECT_EQ(groups.at({"cut", "cut_area_m2"}).stats.n, 1);
  EXPECT_EQ(groups.begin()->first.first, "cut");  // in key order
  EXPECT_TRUE(group_benchmarks({}).empty());
}

}  // namespace
}  // namespace incise::curriculum
