// Tests for curriculum/metrics.h: each basic metric against a closed form, the degenerate runs,
// precise errors for bad samples, and scoring at the threshold boundaries.
#include "curriculum/metrics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "curriculum/metric_catalogue.h"
#include "metric_test_helpers.h"

namespace incise::curriculum {
namespace {

using Vec = std::array<double, 3>;

const double pi = std::numbers::pi;

using testing::metric;

// The error message basic_metrics throws for these samples ("" if it does not throw).
std::string error_of(const std::vector<ToolSample>& samples) {
  try {
    basic_metrics(samples);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(BasicMetrics, ReportsTheFiveMetricsInOrderWithUnitsAndDefinitions) {
  const auto values = basic_metrics({});
  ASSERT_EQ(values.size(), 5u);
  const std::vector<std::pair<std::string, std::string>> expected = {{"completion_time_s", "s"},
                                                                     {"path_length_m", "m"},
                                                                     {"peak_force_n", "N"},
                                                                     {"rms_force_n", "N"},
                                                                     {"contact_time_s", "s"}};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(values[i].key, expected[i].first);
    EXPECT_EQ(values[i].unit, expected[i].second);
    // Named and defined in the catalogue, in the unit it is computed in.
    const auto info = find_metric(values[i].key);
    ASSERT_TRUE(info) << values[i].key;
    EXPECT_EQ(info->unit, values[i].unit) << values[i].key;
    EXPECT_EQ(values[i].value, 0.0) << "an empty run measures nothing: " << values[i].key;
  }
}

TEST(BasicMetrics, OneSampleHasAPeakButNoDurationPathOrRms) {
  const std::vector<ToolSample> one = {{2.5, {0.1, 0.2, 0.3}, {3.0, 0.0, 4.0}}};
  const auto values = basic_metrics(one);
  EXPECT_EQ(metric(values, "completion_time_s"), 0.0);
  EXPECT_EQ(metric(values, "path_length_m"), 0.0);
  EXPECT_DOUBLE_EQ(metric(values, "peak_force_n"), 5.0);
  EXPECT_EQ(metric(values, "rms_force_n"), 0.0) << "no duration to average over";
}

TEST(BasicMetrics, CompletionTimeIsLastMinusFirstTime) {
  std::vector<ToolSample> samples;
  for (double t : {5.0, 5.002, 5.5, 6.0, 7.5})
    samples.push_back({t, {}, {}});
  EXPECT_DOUBLE_EQ(metric(basic_metrics(samples), "completion_time_s"), 2.5);
}

TEST(BasicMetrics, StraightLinePathIsTheDistanceWhateverTheSteps) {
  const Vec from = {0.01, -0.02, 0.03};
  const Vec to = {0.07, 0.05, -0.01};
  const double length = std::hypot(to[0] - from[0], to[1] - from[1], to[2] - from[2]);
  // Uneven steps along the segment, including a pause (two equal positions).
  const std::vector<double> fractions = {0.0, 0.001, 0.1, 0.1, 0.35, 0.9, 0.95, 1.0};
  std::vector<ToolSample> samples;
  for (std::size_t i = 0; i < fractions.size(); ++i) {
    Vec p;
    for (int k = 0; k < 3; ++k)
      p[k] = from[k] + fractions[i] * (to[k] - from[k]);
    samples.push_back({0.002 * static_cast<double>(i), p, {}});
  }
  EXPECT_NEAR(metric(basic_metrics(samples), "path_length_m"), length, 1e-15);

  // There and back again travels twice the distance, though the tip ends where it began.
  auto back = samples;
  for (auto it = samples.rbegin() + 1; it != samples.rend(); ++it)
    back.push_back({back.back().t_s + 0.002, it->tip_m, {}});
  EXPECT_NEAR(metric(basic_metrics(back), "path_length_m"), 2 * length, 1e-15);
}

TEST(BasicMetrics, ClosedPolygonOnACircleHasPerimeterTwoNRSinPiOverN) {
  const double r = 0.04;
  const Vec centre = {0.1, 0.2, -0.05};
  for (int n : {3, 4, 7, 100, 5000}) {
    std::vector<ToolSample> samples;
    for (int i = 0; i <= n; ++i) {  // the last vertex closes the loop at the first
      const double a = 2 * pi * i / n;
      // A circle in a tilted plane, so that every coordinate moves.
      const double c = r * std::cos(a), s = r * std::sin(a);
      samples.push_back({0.002 * i, {centre[0] + c, centre[1] + s * 0.6, centre[2] + s * 0.8}, {}});
    }
    const double perimeter = 2 * n * r * std::sin(pi / n);
    EXPECT_NEAR(metric(basic_metrics(samples), "path_length_m"), perimeter, 1e-13) << n;
  }
}

TEST(BasicMetrics, ConstantForceMagnitudeHasRmsAndPeakEqualToIt) {
  // The direction turns and the ticks are uneven; only the magnitude matters.
  const double magnitude = 2.75;
  std::vector<ToolSample> samples;
  double t = 0.3;
  for (int i = 0; i < 200; ++i) {
    const double a = 0.05 * i;
    samples.push_back({t, {}, {magnitude * std::cos(a), magnitude * std::sin(a), 0.0}});
    t += (i % 3 == 0) ? 0.001 : 0.0035;
  }
  const auto values = basic_metrics(samples);
  EXPECT_NEAR(metric(values, "rms_force_n"), magnitude, 1e-12);
  EXPECT_NEAR(metric(values, "peak_force_n"), magnitude, 1e-12);
}

// A triangle wave of `ramps` ramps, each rising from 0 to A (or falling back) in n equal ticks,
// sampled at the ticks. The trapezoid rule over one ramp gives dt A^2 (2n^2 + 1) / (6n), so
//   rms = A sqrt((2n^2 + 1) / (6n^2)),
// which is A / sqrt(2) for n = 1 and tends to the continuous A / sqrt(3) as n grows. An odd number
// of ramps is not a whole period, so a one-sided (rectangle) rule would give another value.
std::vector<ToolSample> triangle_wave(double amplitude, int n, int ramps, double dt) {
  std::vector<ToolSample> samples;
  for (int i = 0; i <= n * ramps; ++i) {
    const int phase = i % (2 * n);
    const double f = amplitude * (phase <= n ? phase : 2 * n - phase) / n;
    samples.push_back({dt * i, {}, {0.0, -f, 0.0}});
  }
  return samples;
}

TEST(BasicMetrics, TriangleWaveRmsMatchesTheTrapezoidClosedForm) {
  const double amplitude = 6.0;
  for (int n : {1, 2, 5, 50}) {
    for (int ramps : {1, 2, 3, 6}) {
      const auto values = basic_metrics(triangle_wave(amplitude, n, ramps, 0.002));
      const double expected = amplitude * std::sqrt((2.0 * n * n + 1) / (6.0 * n * n));
      EXPECT_NEAR(metric(values, "rms_force_n"), expected, 1e-12) << n << " " << ramps;
      EXPECT_DOUBLE_EQ(metric(values, "peak_force_n"), amplitude);
    }
  }
  EXPECT_NEAR(metric(basic_metrics(triangle_wave(amplitude, 1000, 4, 0.0005)), "rms_force_n"),
              amplitude / std::sqrt(3.0), 1e-6);
}

TEST(BasicMetrics, RmsIsWeightedByTimeNotBySampleCount) {
  // 1 N for 1 s (two samples), then 3 N for 1 s sampled a hundred times. Per-sample averaging
  // would be dominated by the dense part; the time-weighted mean is the same as with 2 samples.
  std::vector<ToolSample> sparse = {
      {0.0, {}, {1, 0, 0}}, {1.0, {}, {1, 0, 0}}, {1.0, {}, {3, 0, 0}}, {2.0, {}, {3, 0, 0}}};
  std::vector<ToolSample> dense = {{0.0, {}, {1, 0, 0}}, {1.0, {}, {1, 0, 0}}};
  for (int i = 0; i <= 100; ++i)
    dense.push_back({1.0 + i / 100.0, {}, {0, 0, 3}});
  const double expected = std::sqrt((1.0 + 9.0) / 2);
  EXPECT_NEAR(metric(basic_metrics(sparse), "rms_force_n"), expected, 1e-12);
  EXPECT_NEAR(metric(basic_metrics(dense), "rms_force_n"), expected, 1e-12);
}

TEST(BasicMetrics, SamplesAtOneInstantHaveNoDuration) {
  const std::vector<ToolSample> same_time = {{1.0, {0, 0, 0}, {1, 0, 0}},
                                             {1.0, {0.03, 0.04, 0}, {2, 0, 0}}};
  const auto values = basic_metrics(same_time);
  EXPECT_EQ(metric(values, "completion_time_s"), 0.0);
  EXPECT_DOUBLE_EQ(metric(values, "path_length_m"), 0.05);
  EXPECT_DOUBLE_EQ(metric(values, "peak_force_n"), 2.0);
  EXPECT_EQ(metric(values, "rms_force_n"), 0.0);
}

TEST(BasicMetrics, NonFiniteValuesAreRejectedNamingTheSample) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<ToolSample> good;
  for (int i = 0; i < 5; ++i)
    good.push_back({0.002 * i, {0.01 * i, 0, 0}, {0, 0, 1}});
  ASSERT_EQ(error_of(good), "");

  auto bad_t = good;
  bad_t[3].t_s = nan;
  EXPECT_EQ(error_of(bad_t), "sample 3: t_s is not finite");
  auto bad_tip = good;
  bad_tip[0].tip_m[1] = inf;
  EXPECT_EQ(error_of(bad_tip), "sample 0: tip_m is not finite");
  auto bad_force = good;
  bad_force[4].force_n[2] = -inf;
  EXPECT_EQ(error_of(bad_force), "sample 4: force_n is not finite");
  auto bad_first = good;
  bad_first[1].force_n[0] = nan;
  bad_first[2].t_s = nan;
  EXPECT_EQ(error_of(bad_first), "sample 1: force_n is not finite") << "the first bad sample";
}

TEST(BasicMetrics, DecreasingTimeIsRejectedNamingTheSample) {
  std::vector<ToolSample> samples;
  for (int i = 0; i < 6; ++i)
    samples.push_back({0.5 * i, {}, {}});
  samples[4].t_s = 1.25;  // after sample 2 (1.0) but before sample 3 (1.5)
  const std::string message = error_of(samples);
  EXPECT_EQ(message.rfind("sample 4: ", 0), 0u) << message;
  EXPECT_NE(message.find("1.25"), std::string::npos) << message;
  EXPECT_NE(message.find("1.5"), std::string::npos) << message;
}

Task probing_task() {
  Task task;
  task.key = "probing";
  task.metrics = {{"completion_time_s", {ThresholdOp::at_most, 60.0}, "s"},
                  {"peak_force_n", {ThresholdOp::at_most, 4.0}, "N"},
                  {"targets_reached", {ThresholdOp::at_least, 0.8}, ""}};
  return task;
}

TEST(ScoreAttempt, OneResultPerRequiredMetricInTheTasksOrder) {
  // Values in another order, plus one the task does not score.
  const std::vector<MetricValue> values = {{"targets_reached", 0.9, ""},
                                           {"path_length_m", 9.0, "m"},
                                           {"peak_force_n", 3.0, "N"},
                                           {"completion_time_s", 75.0, "s"}};
  const auto results = score_attempt(probing_task(), values);
  ASSERT_EQ(results.size(), 3u);
  EXPECT_EQ(results[0].key, "completion_time_s");
  EXPECT_EQ(results[0].value, 75.0);
  EXPECT_EQ(results[0].unit, "s");
  EXPECT_EQ(results[0].threshold, (Threshold{ThresholdOp::at_most, 60.0}));
  EXPECT_FALSE(results[0].passed);
  EXPECT_TRUE(results[0].measured);
  EXPECT_EQ(results[1].key, "peak_force_n");
  EXPECT_TRUE(results[1].passed);
  EXPECT_EQ(results[2].key, "targets_reached");
  EXPECT_TRUE(results[2].passed);
  EXPECT_FALSE(attempt_passed(results)) << "the completion time failed";
}

TEST(ScoreAttempt, ValuesExactlyAtTheThresholdsPass) {
  const std::vector<MetricValue> at_boundary = {
      {"completion_time_s", 60.0, "s"}, {"peak_force_n", 4.0, "N"}, {"targets_reached", 0.8, ""}};
  const auto results = score_attempt(probing_task(), at_boundary);
  for (const auto& r : results)
    EXPECT_TRUE(r.passed) << r.key;
  EXPECT_TRUE(attempt_passed(results));

  // One representable step beyond each boundary fails that metric alone.
  for (std::size_t i = 0; i < at_boundary.size(); ++i) {
    auto beyond = at_boundary;
    const bool at_least = i == 2;
    beyond[i].value = std::nextafter(beyond[i].value, at_least ? -1e9 : 1e9);
    const auto failed = score_attempt(probing_task(), beyond);
    for (std::size_t k = 0; k < failed.size(); ++k)
      EXPECT_EQ(failed[k].passed, k != i) << at_boundary[i].key << " / " << failed[k].key;
    EXPECT_FALSE(attempt_passed(failed));
  }
}

TEST(ScoreAttempt, MissingMetricIsUnmeasuredAndFails) {
  const std::vector<MetricValue> values = {{"completion_time_s", 10.0, "s"},
                                           {"peak_force_n", 1.0, "N"}};
  const auto results = score_attempt(probing_task(), values);
  ASSERT_EQ(results.size(), 3u);
  EXPECT_TRUE(results[0].measured && results[0].passed);
  EXPECT_TRUE(results[1].measured && results[1].passed);
  EXPECT_EQ(results[2].key, "targets_reached");
  EXPECT_FALSE(results[2].measured);
  EXPECT_FALSE(results[2].passed);
  EXPECT_EQ(results[2].threshold, (Threshold{ThresholdOp::at_least, 0.8}));
  EXPECT_FALSE(attempt_passed(results));
}

TEST(ScoreAttempt, NanValueFails) {
  const std::vector<MetricValue> values = {
      {"completion_time_s", std::numeric_limits<double>::quiet_NaN(), "s"},
      {"peak_force_n", 1.0, "N"},
      {"targets_reached", 1.0, ""}};
  const auto results = score_attempt(probing_task(), values);
  EXPECT_TRUE(results[0].measured);
  EXPECT_FALSE(results[0].passed);
  EXPECT_FALSE(attempt_passed(results));
}

// A never event fails the attempt outright: a task that can have one is scored on never_events
// <= 0 as well, whether it names that metric or not; a task that cannot have one is not.
TEST(ScoreAttempt, ANeverEventFailsAnAttemptWhoseNamedMetricsPass) {
  const std::vector<MetricValue> passing = {
      {"completion_time_s", 30.0, "s"}, {"peak_force_n", 3.0, "N"}, {"targets_reached", 1.0, ""}};
  EXPECT_TRUE(attempt_passed(score_attempt(probing_task(), passing)));

  for (const bool never_zone : {true, false}) {
    SCOPED_TRACE(never_zone ? "a never zone" : "a never force");
    Task task = probing_task();
    if (never_zone) {
      task.protected_zones = {{{"artery", {0, 0, 0}, 0.005}, true}};
    } else {
      task.never_force_n = 10;
    }
    ASSERT_TRUE(task.has_never_events());
    for (const double never_events : {0.0, 1.0}) {
      auto values = passing;
      values.push_back({"never_events", never_events, "count"});
      const auto results = score_attempt(task, values);
      ASSERT_EQ(results.size(), 4u);
      EXPECT_EQ(results[3].key, "never_events");
      EXPECT_EQ(results[3].threshold, (Threshold{ThresholdOp::at_most, 0.0}));
      EXPECT_EQ(attempt_passed(results), never_events == 0.0);
    }
    // Not measured at all: the attempt cannot prove it had none.
    EXPECT_FALSE(attempt_passed(score_attempt(task, passing)));
    // Named by the task: scored once, on the task's own threshold.
    task.metrics.push_back({"never_events", {ThresholdOp::at_most, 0.0}, "count"});
    auto values = passing;
    values.push_back({"never_events", 1.0, "count"});
    const auto named = score_attempt(task, values);
    EXPECT_EQ(named.size(), 4u);
    EXPECT_FALSE(attempt_passed(named));
  }
  // A protected zone that is not a never zone does not add the requirement.
  Task gentle = probing_task();
  gentle.protected_zones = {{{"nerve", {0, 0, 0}, 0.005}, false}};
  EXPECT_FALSE(gentle.has_never_events());
  EXPECT_EQ(score_attempt(gentle, passing).size(), 3u);
}

TEST(ScoreAttempt, AnAttemptScoredOnNothingDoesNotPass) {
  Task no_metrics;
  no_metrics.key = "empty";
  const std::vector<MetricValue> values = {{"completion_time_s", 1.0, "s"}};
  const auto results = score_attempt(no_metrics, values);
  EXPECT_TRUE(results.empty());
  EXPECT_FALSE(attempt_passed(results));
}

TEST(ScoreAttempt, ScoresTheBasicMetricsOfARecordedRun) {
  // 2 s along a 0.1 m line at 500 Hz, pressing 1.5 N.
  std::vector<ToolSample> samples;
  for (int i = 0; i <= 1000; ++i)
    samples.push_back({i / 500.0, {0.1 * i / 1000.0, 0, 0}, {0, 0, -1.5}});
  Task task;
  task.key = "line";
  task.metrics = {{"path_length_m", {ThresholdOp::at_most, 0.1 + 1e-12}, "m"},
                  {"rms_force_n", {ThresholdOp::at_most, 1.5 + 1e-12}, "N"},
                  {"completion_time_s", {ThresholdOp::at_most, 1.9}, "s"}};
  const auto results = score_attempt(task, basic_metrics(samples));
  ASSERT_EQ(results.size(), 3u);
  EXPECT_TRUE(results[0].passed);
  EXPECT_TRUE(results[1].passed);
  EXPECT_FALSE(results[2].passed) << "2 s is over 1.9 s";
  EXPECT_NEAR(results[2].value, 2.0, 1e-12);
  EXPECT_FALSE(attempt_passed(results));
}

}  // namespace
}  // namespace incise::curriculum

namespace incise::curriculum {
namespace {

// Contact time counts the intervals that start in contact, whatever the sample spacing: here
// forces of 0, 2, 2, 0, 1e-4 (below the threshold), 3 N at uneven times.
TEST(BasicMetrics, ContactTimeSumsTheIntervalsThatStartInContact) {
  const std::vector<ToolSample> samples = {{0.0, {}, {0, 0, 0}},    {0.5, {}, {0, 0, 2}},
                                           {0.75, {}, {2, 0, 0}},   {1.5, {}, {0, 0, 0}},
                                           {2.0, {}, {0, 1e-4, 0}}, {3.0, {}, {0, 3, 0}}};
  const auto values = basic_metrics(samples);
  const auto it = std::find_if(values.begin(), values.end(),
                               [](const MetricValue& v) { return v.key == "contact_time_s"; });
  ASSERT_NE(it, values.end());
  EXPECT_DOUBLE_EQ(it->value, (0.75 - 0.5) + (1.5 - 0.75));
}

}  // namespace
}  // namespace incise::curriculum
