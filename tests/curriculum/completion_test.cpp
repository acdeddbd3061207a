// Completion criteria (Task::completion): what an attempt must have done to count, scored as
// requirements before the thresholds, and the composition of an attempt's metrics
// (curriculum/attempt_metrics.h) they are read from.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "curriculum/attempt_metrics.h"
#include "curriculum/curriculum_json.h"
#include "curriculum/curriculum_validation.h"
#include "curriculum/metrics.h"
#include "curriculum/run_events.h"
#include "metric_test_helpers.h"

namespace incise::curriculum {
namespace {

using testing::metric;

// A hand at 100 Hz for #n samples, the tip moving along x at 1 cm/s; #force(i) is its force.
std::vector<HandSample> hand(int n, const std::function<double(int)>& force, double y = 0) {
  std::vector<HandSample> samples(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    auto& s = samples[static_cast<std::size_t>(i)];
    s.t_s = 0.01 * i;
    s.tip_m = {0.0001 * i, y, 0};
    s.force_n = {0, 0, force(i)};
  }
  return samples;
}

Task task_with_completion() {
  Task task;
  task.key = "t";
  task.name = "T";
  task.scene = "s.json";
  task.metrics = {{"completion_time_s", {ThresholdOp::at_most, 100.0}, "s"}};
  task.targets = {{"a", {0.005, 0, 0}, 0.001, false}, {"b", {0.5, 0, 0}, 0.001, false}};
  task.completion.min_contact_s = 0.2;
  task.completion.all_targets = true;
  task.completion.min_cut_on_line_m2 = 1e-5;
  return task;
}

TEST(Completion, EachCriterionIsARequirementBeforeTheThresholds) {
  const Task task = task_with_completion();
  const std::vector<MetricRequirement> criteria = {
      {"tissue_contact_s", {ThresholdOp::at_least, 0.2}, "s"},
      {"targets_fraction", {ThresholdOp::at_least, 1.0}, ""},
      {"cut_on_line_m2", {ThresholdOp::at_least, 1e-5}, "m^2"}};
  EXPECT_EQ(completion_requirements(task), criteria);
  const auto scored = scored_requirements(task);
  ASSERT_EQ(scored.size(), 4u);
  EXPECT_EQ(scored[3].key, "completion_time_s");
  // A criterion left at zero is not asked for.
  Task none = task;
  none.completion = {};
  EXPECT_TRUE(completion_requirements(none).empty());
}

TEST(Completion, AnAttemptThatMeetsEveryThresholdButNotTheCriteriaFails) {
  const Task task = task_with_completion();
  // Quick and gentle (every threshold met), but the tool never touched anything.
  const std::vector<MetricValue> idle = {{"completion_time_s", 10, "s"},
                                         {"tissue_contact_s", 0, "s"},
                                         {"targets_fraction", 0.5, ""},
                                         {"cut_on_line_m2", 0, "m^2"}};
  const auto results = score_attempt(task, idle);
  ASSERT_EQ(results.size(), 4u);
  EXPECT_TRUE(results[0].criterion);
  EXPECT_TRUE(results[2].criterion);
  EXPECT_FALSE(results[3].criterion);
  EXPECT_TRUE(results[3].passed);  // the threshold
  EXPECT_FALSE(results[0].passed);
  EXPECT_FALSE(attempt_passed(results));

  const std::vector<MetricValue> done = {{"completion_time_s", 10, "s"},
                                         {"tissue_contact_s", 0.2, "s"},  // the boundary
                                         {"targets_fraction", 1, ""},
                                         {"cut_on_line_m2", 2e-5, "m^2"}};
  EXPECT_TRUE(attempt_passed(score_attempt(task, done)));
}

TEST(Completion, TissueContactAddsUpEveryHandsTimeOnTheTissue) {
  Task task;
  // The right hand presses for samples 10..29 (0.2 s), the left for 50..59 (0.1 s), both above
  // kContactForceN; a force at the threshold itself is not contact.
  const auto right = hand(100, [](int i) { return i >= 10 && i < 30 ? 0.5 : 0.0; });
  const auto left = hand(
      100, [](int i) { return i >= 50 && i < 60 ? 2.0 : kContactForceN; }, 0.1);
  const auto values = event_metrics(task, right, left, run_events(task, right, left));
  EXPECT_NEAR(metric(values, "tissue_contact_s"), 0.3, 1e-12);
  const auto one_hand = event_metrics(task, right, {}, run_events(task, right, {}));
  EXPECT_NEAR(metric(one_hand, "tissue_contact_s"), 0.2, 1e-12);
}

TEST(Completion, AttemptMetricsComposeTheHandsAndAddTheCutStructuresToTheNeverEvents) {
  Task task;
  task.tools = {"probe", "grasper"};
  const auto right = hand(50, [](int) { return 0.1; });
  const auto left = hand(
      50, [](int) { return 0.0; }, 0.05);
  const std::vector<MetricValue> simulation = {{"cut_on_line_m2", 3e-5, "m^2"},
                                               {std::string(kSimNeverEventsKey), 2, "count"}};
  const auto values = attempt_metrics(task, right, left, simulation);
  EXPECT_EQ(values.front().key, "completion_time_s");
  EXPECT_NEAR(metric(values, "completion_time_s"), 0.49, 1e-12);
  EXPECT_NEAR(metric(values, "path_length_m_left"), 0.0049, 1e-12);
  EXPECT_EQ(metric(values, "never_events"), 2);  // none entered, two cut
  EXPECT_EQ(metric(values, "cut_on_line_m2"), 3e-5);
  // One-handed: no left-hand or bimanual keys.
  const auto one = attempt_metrics(task, right, {});
  for (const auto& v : one)
    EXPECT_EQ(v.key.find("_left"), std::string::npos) << v.key;
  EXPECT_EQ(metric(one, "never_events"), 0);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The evidence: a tool that never touches the tissue fails every task of the demo
// curriculum, however quick, short and gentle the attempt, and the reason is a criterion.
TEST(Completion, AnAttemptWithoutContactFailsEveryDemoTask) {
  const Curriculum demo = parse_curriculum_text(read_file(INCISE_DEMO_CURRICULUM));
  int tasks = 0;
  for (const Module& module : demo.modules) {
    for (const Task& task : module.tasks) {
      ++tasks;
      EXPECT_GT(task.completion.min_contact_s, 0) << task.key;
      EXPECT_FALSE(task.station_kind.empty()) << task.key;
      // The tool tours every target without touching anything: only the contact is missing.
      std::vector<HandSample> right;
      double t = 0;
      for (const Zone& target : task.targets) {
        right.push_back({t, target.center_m, {1, 0, 0, 0}, 0, {0, 0, 0}, 0});
        t += 0.5;
      }
      right.push_back({t, {0, 0, 0}, {1, 0, 0, 0}, 0, {0, 0, 0}, 0});
      std::vector<HandSample> left;
      if (task.tools.size() > 1) {
        left = right;
        for (auto& s : left)
          s.tip_m[1] += 0.2;  // far from everything
      }
      // The simulation saw a perfect cut: the criteria, not the cut, must fail it.
      const std::vector<MetricValue> simulation = {{"cut_area_m2", 1e-4, "m^2"},
                                                   {"cut_on_target_fraction", 1, ""},
                                                   {"cut_on_line_m2", 1e-4, "m^2"},
                                                   {"sim_damage_index", 0, ""},
                                                   {std::string(kSimNeverEventsKey), 0, "count"}};
      const auto results = score_attempt(task, attempt_metrics(task, right, left, simulation));
      EXPECT_FALSE(attempt_passed(results)) << task.key;
      ASSERT_FALSE(results.empty());
      EXPECT_EQ(results.front().key, "tissue_contact_s") << task.key;
      EXPECT_TRUE(results.front().criterion);
      EXPECT_FALSE(results.front().passed) << task.key;
    }
  }
  EXPECT_EQ(tasks, 5);
}

// The criteria round-trip through JSON, and what cannot be met or repeats a metric is refused.
TEST(Completion, JsonRoundTripAndValidation) {
  Curriculum c;
  c.name = "c";
  Task task = task_with_completion();
  task.station_kind = "laparoscopy";
  c.modules = {{"m", "M", {task}}};
  validate(c);
  EXPECT_EQ(parse_curriculum(to_json(c)), c);

  const auto error = [&](const std::function<void(Task&)>& change) {
    Curriculum bad = c;
    change(bad.modules[0].tasks[0]);
    try {
      validate(bad);
    } catch (const CurriculumError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(error([](Task& t) { t.completion.min_contact_s = -1; }),
            "modules[0].tasks[0].completion.min_contact_s: must be a finite number, 0 or more");
  EXPECT_EQ(error([](Task& t) { t.completion.min_cut_on_line_m2 = std::nan(""); }),
            "modules[0].tasks[0].completion.min_cut_on_line_m2: must be a finite number, 0 or "
            "more");
  EXPECT_EQ(error([](Task& t) { t.targets.clear(); }),
            "modules[0].tasks[0].completion.all_targets: needs targets: the task has none to "
            "reach");
  EXPECT_EQ(error([](Task& t) {
              t.metrics.push_back({"targets_fraction", {ThresholdOp::at_least, 1}, ""});
            }),
            "modules[0].tasks[0].metrics[1].key: \"targets_fraction\" is already a completion "
            "criterion");
  EXPECT_EQ(error([](Task& t) {
              t.station_kind = "Laparoscopy";
            }).rfind("modules[0].tasks[0].station_kind: ", 0),
            0u);
  // Unknown members of completion are refused with their path.
  auto text = to_json(c);
  text["modules"][0]["tasks"][0]["completion"]["min_contact"] = 1;
  try {
    parse_curriculum(text);
    ADD_FAILURE() << "accepted";
  } catch (const CurriculumError& e) {
    EXPECT_EQ(
        std::string(e.what()).rfind("modules[0].tasks[0].completion.min_contact: unknown key", 0),
        0u)
        << e.what();
  }
}

}  // namespace
}  // namespace incise::curriculum
