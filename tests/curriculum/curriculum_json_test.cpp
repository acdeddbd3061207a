#include "curriculum/curriculum_json.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "sample_curriculum.h"

namespace incise::curriculum {
namespace {

using nlohmann::json;

std::string read_file(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

// Parses json expecting a CurriculumError whose what() is exactly `expected`.
void expect_error(const json& value, const std::string& expected) {
  try {
    parse_curriculum(value);
    ADD_FAILURE() << "accepted, expected \"" << expected << "\"";
  } catch (const CurriculumError& error) {
    EXPECT_EQ(std::string(error.what()), expected);
  }
}

// The sample with one change applied.
json changed(const std::function<void(json&)>& change) {
  json value = sample_curriculum_json();
  change(value);
  return value;
}

TEST(CurriculumJson, DemoFileParses) {
  const std::string text = read_file(INCISE_DEMO_CURRICULUM);
  ASSERT_FALSE(text.empty()) << INCISE_DEMO_CURRICULUM;
  const Curriculum curriculum = parse_curriculum_text(text);
  EXPECT_EQ(curriculum.name, "Basic laparoscopic skills");
  ASSERT_EQ(curriculum.modules.size(), 3u);
  ASSERT_EQ(curriculum.modules[0].tasks.size(), 2u);
  // The second task is two-handed: its tools are held by devices 0 and 1.
  const Task& bimanual = curriculum.modules[0].tasks[1];
  EXPECT_EQ(bimanual.key, "bimanual_palpation");
  EXPECT_EQ(bimanual.tools, (std::vector<std::string>{"probe", "retractor"}));
  EXPECT_EQ(bimanual.prerequisites, std::vector<std::string>{"palpation"});
  const Task& task = curriculum.modules[0].tasks[0];
  EXPECT_EQ(task.key, "palpation");
  EXPECT_EQ(task.scene, "scenes/palpation.json");
  EXPECT_EQ(task.consecutive_passes_required, 3);
  EXPECT_TRUE(task.prerequisites.empty());
  const std::vector<MetricRequirement> metrics = {
      {"completion_time_s", {ThresholdOp::at_most, 120.0}, "s"},
      {"path_length_m", {ThresholdOp::at_most, 1.5}, "m"},
      {"peak_force_n", {ThresholdOp::at_most, 4.0}, "N"},
      {"contact_time_s", {ThresholdOp::at_least, 5.0}, "s"},
      {"protected_collisions", {ThresholdOp::at_most, 2.0}, "count"},
      {"sim_damage_index", {ThresholdOp::at_most, 0.02}, ""}};
  EXPECT_EQ(task.metrics, metrics);
  // Palpation keeps off a nerve and must never touch the artery or press above 12 N.
  ASSERT_EQ(task.protected_zones.size(), 2u);
  EXPECT_EQ(task.protected_zones[0].zone.name, "nerve");
  EXPECT_FALSE(task.protected_zones[0].never);
  EXPECT_EQ(task.protected_zones[1].zone.name, "artery");
  EXPECT_TRUE(task.protected_zones[1].never);
  EXPECT_EQ(task.targets.size(), 3u);
  EXPECT_EQ(task.safe_force_n, 3.0);
  EXPECT_EQ(task.never_force_n, 12.0);
  EXPECT_TRUE(bimanual.protected_zones.empty());
  EXPECT_EQ(bimanual.never_force_n, 0.0);
  // The liver task cuts in a surgical scene, scalpel right and grasper left, after the two-handed
  // palpation; scored on the cut and never events.
  ASSERT_EQ(curriculum.modules[1].tasks.size(), 1u);
  const Task& cut = curriculum.modules[1].tasks[0];
  EXPECT_EQ(cut.key, "liver_cut");
  EXPECT_EQ(cut.scene, "scenes/surgery/liver_station.json");
  EXPECT_EQ(cut.tools, (std::vector<std::string>{"scalpel", "grasper"}));
  EXPECT_EQ(cut.prerequisites, std::vector<std::string>{"bimanual_palpation"});
  const auto scored = [&](const std::string& key) {
    return std::any_of(cut.metrics.begin(), cut.metrics.end(),
                       [&](const MetricRequirement& m) { return m.key == key; });
  };
  for (const char* key : {"cut_area_m2", "cut_on_target_fraction", "never_events"})
    EXPECT_TRUE(scored(key)) << key;
  // The knee at the arthroscopy station: a tour of four landmarks (all to be reached), then a
  // meniscectomy with the punch, the scope on device 0 in both.
  ASSERT_EQ(curriculum.modules[2].tasks.size(), 2u);
  const Task& tour = curriculum.modules[2].tasks[0];
  EXPECT_EQ(tour.scene, "scenes/surgery/knee_station.json");
  EXPECT_EQ(tour.tools, (std::vector<std::string>{"scope", "probe"}));
  EXPECT_EQ(tour.targets.size(), 4u);
  const Task& trim = curriculum.modules[2].tasks[1];
  EXPECT_EQ(trim.scene, "scenes/surgery/knee_meniscectomy.json");
  EXPECT_EQ(trim.tools, (std::vector<std::string>{"scope", "scalpel"}));
  EXPECT_EQ(trim.prerequisites, std::vector<std::string>{"knee_tour"});
  EXPECT_EQ(parse_curriculum(to_json(curriculum)), curriculum);
}

TEST(CurriculumJson, RoundTripIsExact) {
  const Curriculum curriculum = parse_curriculum(sample_curriculum_json());
  EXPECT_EQ(parse_curriculum(to_json(curriculum)), curriculum);
  EXPECT_EQ(parse_curriculum_text(to_json(curriculum).dump()), curriculum);
  // Every member is written out, so the sample comes back unchanged apart from the members it
  // leaves to their defaults.
  json full = sample_curriculum_json();
  for (json& module : full["modules"]) {
    for (json& task : module["tasks"]) {
      task["protected_zones"] = json::array();
      task["targets"] = json::array();
      task["safe_force_n"] = 3.0;
      task["never_force_n"] = 0.0;
    }
  }
  EXPECT_EQ(to_json(curriculum), full);
}

// The sample's first task with two protected zones (one never, shown), a shown target and both
// forces.
json with_zones() {
  return changed([](json& value) {
    json& task = value["modules"][0]["tasks"][0];
    task["protected_zones"] = json::parse(R"([
      {"name": "vessel", "center_m": [0.01, -0.02, 0.1], "radius_m": 0.004},
      {"name": "nerve", "center_m": [0, 0, 0.05], "radius_m": 0.002, "visible": true,
       "never": true}])");
    task["targets"] = json::parse(R"([{"name": "polyp", "center_m": [0.02, 0, 0.08],
                                       "radius_m": 0.005, "visible": true}])");
    task["safe_force_n"] = 2.5;
    task["never_force_n"] = 6;
  });
}

TEST(CurriculumJson, ZonesTargetsAndForcesAreRead) {
  const Curriculum curriculum = parse_curriculum(with_zones());
  const Task& task = curriculum.modules[0].tasks[0];
  const std::vector<ProtectedZone> zones = {{{"vessel", {0.01, -0.02, 0.1}, 0.004, false}, false},
                                            {{"nerve", {0, 0, 0.05}, 0.002, true}, true}};
  EXPECT_EQ(task.protected_zones, zones);
  EXPECT_EQ(task.targets, (std::vector<Zone>{{"polyp", {0.02, 0, 0.08}, 0.005, true}}));
  EXPECT_EQ(task.safe_force_n, 2.5);
  EXPECT_EQ(task.never_force_n, 6.0);
  EXPECT_TRUE(task.has_never_events());
  // Left out: no zones or targets, the default safe force, no never force.
  const Task& plain = curriculum.modules[0].tasks[1];
  EXPECT_TRUE(plain.protected_zones.empty());
  EXPECT_TRUE(plain.targets.empty());
  EXPECT_EQ(plain.safe_force_n, 3.0);
  EXPECT_EQ(plain.never_force_n, 0.0);
  EXPECT_FALSE(plain.has_never_events());
}

TEST(CurriculumJson, RoundTripKeepsZonesTargetsAndForces) {
  Curriculum curriculum = parse_curriculum(with_zones());
  curriculum.modules[0].tasks[0].protected_zones[0].zone.center_m[1] = 0.1 + 0.2;
  curriculum.modules[0].tasks[0].targets[0].radius_m = 1e-300;
  curriculum.modules[1].tasks[0].safe_force_n = 1.0 / 3;
  EXPECT_EQ(parse_curriculum(to_json(curriculum)), curriculum);
  EXPECT_EQ(parse_curriculum_text(to_json(curriculum).dump()), curriculum);
  // never is written out even when false; visible only when true (hidden is the default).
  const json zones = to_json(curriculum)["modules"][0]["tasks"][0]["protected_zones"];
  EXPECT_EQ(zones[0]["never"], false);
  EXPECT_FALSE(zones[0].contains("visible"));
  EXPECT_EQ(zones[1]["visible"], true);
}

// The portal is left out when a task has none, and read back exactly when it has one.
TEST(CurriculumJson, RoundTripKeepsThePortal) {
  Curriculum curriculum = parse_curriculum(with_zones());
  EXPECT_FALSE(curriculum.modules[0].tasks[0].portal_m.has_value());
  EXPECT_FALSE(to_json(curriculum)["modules"][0]["tasks"][0].contains("portal_m"));
  curriculum.modules[0].tasks[0].portal_m = std::array<double, 3>{0.04, 0.1 + 0.2, -1e-300};
  EXPECT_EQ(parse_curriculum_text(to_json(curriculum).dump()), curriculum);
}

TEST(CurriculumJson, RoundTripKeepsAwkwardValues) {
  Curriculum curriculum = parse_curriculum(sample_curriculum_json());
  curriculum.modules[0].tasks[1].metrics[0].threshold.value = 0.1 + 0.2;  // not a short decimal
  curriculum.modules[0].tasks[0].metrics[0].threshold.value = 1e-300;     // a force: not negative
  curriculum.modules[1].tasks[0].instructions = "Quote \" and unicode \u00b5m";
  EXPECT_EQ(parse_curriculum_text(to_json(curriculum).dump()), curriculum);
}

TEST(CurriculumJson, OptionalMembersMayBeLeftOut) {
  const Curriculum curriculum = parse_curriculum(changed([](json& value) {
    value.erase("description");
    json& task = value["modules"][0]["tasks"][0];
    task.erase("instructions");
    task.erase("tools");
    task.erase("prerequisites");
    task["metrics"][0].erase("unit");
  }));
  EXPECT_EQ(curriculum.description, "");
  const Task& task = curriculum.modules[0].tasks[0];
  EXPECT_EQ(task.instructions, "");
  EXPECT_TRUE(task.tools.empty());
  EXPECT_TRUE(task.prerequisites.empty());
  EXPECT_EQ(task.metrics[0].unit, "");
}

TEST(CurriculumJson, ShapeErrorsNameTheirPath) {
  const std::string metric = "modules[0].tasks[1].metrics[0]";
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases = {
      {[](json& v) { v = json::array(); }, "(root): must be an object"},
      {[](json& v) { v["colour"] = "red"; },
       "colour: unknown key (expected one of: name, description, modules)"},
      {[](json& v) { v.erase("name"); }, "name: is required"},
      {[](json& v) { v["name"] = 7; }, "name: must be a string"},
      {[](json& v) { v["modules"] = json::object(); }, "modules: must be an array"},
      {[](json& v) { v["modules"][1] = "cutting"; }, "modules[1]: must be an object"},
      {[](json& v) { v["modules"][0].erase("tasks"); }, "modules[0].tasks: is required"},
      {[](json& v) { v["modules"][0]["tasks"][1]["scenery"] = "x"; },
       "modules[0].tasks[1].scenery: unknown key (expected one of: key, name, scene, "
       "station_kind, instructions, tools, metrics, completion, consecutive_passes_required, "
       "prerequisites, protected_zones, targets, safe_force_n, never_force_n, portal_m, material)"},
      {[](json& v) { v["modules"][0]["tasks"][1]["tools"][1] = nullptr; },
       "modules[0].tasks[1].tools[1]: must be a string"},
      {[](json& v) { v["modules"][0]["tasks"][1]["prerequisites"] = "palpation"; },
       "modules[0].tasks[1].prerequisites: must be an array"},
      {[](json& v) { v["modules"][0]["tasks"][1]["metrics"][0]["threshold"]["op"] = "<"; },
       metric + ".threshold.op: must be \"<=\" or \">=\""},
      {[](json& v) { v["modules"][0]["tasks"][1]["metrics"][0]["threshold"]["op"] = 1; },
       metric + ".threshold.op: must be \"<=\" or \">=\""},
      {[](json& v) { v["modules"][0]["tasks"][1]["metrics"][0]["threshold"].erase("op"); },
       metric + ".threshold.op: is required"},
      {[](json& v) { v["modules"][0]["tasks"][1]["metrics"][0]["threshold"]["value"] = "0.9"; },
       metric + ".threshold.value: must be a number"},
      {[](json& v) { v["modules"][0]["tasks"][1]["metrics"][0]["threshold"] = 0.9; },
       metric + ".threshold: must be an object"},
      {[](json& v) { v["modules"][0]["tasks"][1]["metrics"][0]["weight"] = 2; },
       metric + ".weight: unknown key (expected one of: key, threshold, unit)"},
      {[](json& v) { v["modules"][0]["tasks"][1]["consecutive_passes_required"] = 2.5; },
       "modules[0].tasks[1].consecutive_passes_required: must be an integer from 1 to 1000"},
      {[](json& v) { v["modules"][0]["tasks"][1]["consecutive_passes_required"] = 0; },
       "modules[0].tasks[1].consecutive_passes_required: must be an integer from 1 to 1000"},
      {[](json& v) { v["modules"][0]["tasks"][1]["consecutive_passes_required"] = -3; },
       "modules[0].tasks[1].consecutive_passes_required: must be an integer from 1 to 1000"},
      {[](json& v) {
         v["modules"][0]["tasks"][1]["consecutive_passes_required"] = 18446744073709551615u;
       },
       "modules[0].tasks[1].consecutive_passes_required: must be an integer from 1 to 1000"},
  };
  for (const auto& [change, expected] : cases)
    expect_error(changed(change), expected);
}

TEST(CurriculumJson, ZoneShapeErrorsNameTheirPath) {
  const std::string task = "modules[0].tasks[0]";
  const std::string zone = task + ".protected_zones[1]";
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases = {
      {[](json& t) { t["protected_zones"] = json::object(); },
       task + ".protected_zones: must be an array"},
      {[](json& t) { t["protected_zones"][1] = "nerve"; }, zone + ": must be an object"},
      {[](json& t) { t["protected_zones"][1]["colour"] = "red"; },
       zone + ".colour: unknown key (expected one of: name, center_m, radius_m, visible, never)"},
      {[](json& t) { t["protected_zones"][1]["visible"] = "yes"; },
       zone + ".visible: must be true or false"},
      {[](json& t) { t["protected_zones"][1].erase("name"); }, zone + ".name: is required"},
      {[](json& t) { t["protected_zones"][1].erase("center_m"); }, zone + ".center_m: is required"},
      {[](json& t) {
         t["protected_zones"][1]["center_m"] = {0, 0};
       },
       zone + ".center_m: must be an array of 3 numbers"},
      {[](json& t) {
         t["protected_zones"][1]["center_m"] = {0, 0, 0, 0};
       },
       zone + ".center_m: must be an array of 3 numbers"},
      {[](json& t) { t["protected_zones"][1]["center_m"] = 0.1; },
       zone + ".center_m: must be an array of 3 numbers"},
      {[](json& t) { t["protected_zones"][1]["center_m"][2] = "0.05"; },
       zone + ".center_m[2]: must be a number"},
      {[](json& t) { t["protected_zones"][1]["radius_m"] = "2 mm"; },
       zone + ".radius_m: must be a number"},
      {[](json& t) { t["protected_zones"][1]["never"] = 1; },
       zone + ".never: must be true or false"},
      {[](json& t) { t["targets"][0]["never"] = true; },
       task +
           ".targets[0].never: unknown key (expected one of: name, center_m, radius_m, visible)"},
      {[](json& t) { t["targets"][0].erase("radius_m"); },
       task + ".targets[0].radius_m: is required"},
      {[](json& t) { t["safe_force_n"] = "3"; }, task + ".safe_force_n: must be a number"},
      {[](json& t) { t["never_force_n"] = nullptr; }, task + ".never_force_n: must be a number"},
      {[](json& t) {
         t["portal_m"] = {0, 0};
       },
       task + ".portal_m: must be an array of 3 numbers"},
      {[](json& t) {
         t["portal_m"] = {0, "0", 0};
       },
       task + ".portal_m[1]: must be a number"},
  };
  for (const auto& [change, expected] : cases) {
    json value = with_zones();
    change(value["modules"][0]["tasks"][0]);
    expect_error(value, expected);
  }
}

TEST(CurriculumJson, ZoneValidationErrorsNameTheirPath) {
  const std::string task = "modules[0].tasks[0]";
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases = {
      {[](json& t) { t["protected_zones"][0]["name"] = ""; },
       task + ".protected_zones[0].name: must not be empty"},
      {[](json& t) { t["protected_zones"][1]["name"] = "vessel"; },
       task + ".protected_zones[1].name: duplicate zone or target name \"vessel\" (first at " +
           task + ".protected_zones[0])"},
      {[](json& t) { t["targets"][0]["name"] = "nerve"; },
       task + ".targets[0].name: duplicate zone or target name \"nerve\" (first at " + task +
           ".protected_zones[1])"},
      {[](json& t) { t["protected_zones"][1]["radius_m"] = 0; },
       task + ".protected_zones[1].radius_m: must be a finite number above 0"},
      {[](json& t) { t["targets"][0]["radius_m"] = -0.005; },
       task + ".targets[0].radius_m: must be a finite number above 0"},
      {[](json& t) { t["safe_force_n"] = 0; },
       task + ".safe_force_n: must be a finite number above 0"},
      {[](json& t) { t["never_force_n"] = -1; },
       task + ".never_force_n: must be a finite number, 0 (no limit) or more"},
      {[](json& t) { t["never_force_n"] = 2.5; },
       task + ".never_force_n: must be 0 (no limit) or above safe_force_n 2.5"},
      {[](json& t) { t["never_force_n"] = 2; },
       task + ".never_force_n: must be 0 (no limit) or above safe_force_n 2.5"},
  };
  for (const auto& [change, expected] : cases) {
    json value = with_zones();
    change(value["modules"][0]["tasks"][0]);
    expect_error(value, expected);
  }
  // The same name in two tasks is fine: names are per task.
  json value = with_zones();
  value["modules"][0]["tasks"][1]["targets"] = value["modules"][0]["tasks"][0]["targets"];
  EXPECT_NO_THROW(parse_curriculum(value));
}

TEST(CurriculumJson, ValidationErrorsNameTheirPath) {
  const std::vector<std::pair<std::function<void(json&)>, std::string>> cases = {
      {[](json& v) { v["modules"] = json::array(); }, "modules: must list at least one module"},
      {[](json& v) { v["modules"][1]["key"] = "basics"; },
       "modules[1].key: duplicate module key \"basics\""},
      {[](json& v) { v["modules"][1]["tasks"][0]["key"] = "grasping"; },
       "modules[1].tasks[0].key: duplicate task key \"grasping\" (first at modules[0].tasks[1])"},
      {[](json& v) { v["modules"][0]["tasks"][1]["metrics"][1]["key"] = "targets_reached"; },
       "modules[0].tasks[1].metrics[1].key: duplicate metric key \"targets_reached\""},
      {[](json& v) { v["modules"][0]["tasks"][0]["key"] = "Palpation"; },
       "modules[0].tasks[0].key: must be a key: a lowercase letter, then lowercase letters, "
       "digits or '_' (got \"Palpation\")"},
      {[](json& v) { v["modules"][0]["tasks"][0]["metrics"] = json::array(); },
       "modules[0].tasks[0].metrics: must list at least one metric"},
      {[](json& v) { v["modules"][0]["tasks"][0]["scene"] = ""; },
       "modules[0].tasks[0].scene: must not be empty"},
      {[](json& v) { v["modules"][0]["tasks"][1]["tools"][1] = "grasper"; },
       "modules[0].tasks[1].tools[1]: duplicate entry \"grasper\""},
      {[](json& v) { v["modules"][1]["tasks"][0]["prerequisites"][1] = "suturing"; },
       "modules[1].tasks[0].prerequisites[1]: unknown task \"suturing\""},
  };
  for (const auto& [change, expected] : cases)
    expect_error(changed(change), expected);
}

TEST(CurriculumJson, ErrorCarriesPathAndReasonApart) {
  try {
    parse_curriculum(changed(
        [](json& v) { v["modules"][0]["tasks"][1]["metrics"][0]["threshold"]["op"] = "=="; }));
    FAIL() << "accepted";
  } catch (const CurriculumError& error) {
    EXPECT_EQ(error.path(), "modules[0].tasks[1].metrics[0].threshold.op");
    EXPECT_EQ(error.reason(), "must be \"<=\" or \">=\"");
  }
}

TEST(CurriculumJson, PrerequisiteCyclesAreRejected) {
  // A task that requires itself.
  expect_error(
      changed([](json& v) { v["modules"][0]["tasks"][0]["prerequisites"] = {"palpation"}; }),
      "modules[0].tasks[0].prerequisites[0]: prerequisite cycle: palpation -> palpation");
  // Two tasks requiring each other.
  expect_error(
      changed([](json& v) { v["modules"][0]["tasks"][0]["prerequisites"] = {"grasping"}; }),
      "modules[0].tasks[1].prerequisites[0]: prerequisite cycle: palpation -> grasping "
      "-> palpation");
  // Three tasks across modules.
  expect_error(
      changed([](json& v) { v["modules"][0]["tasks"][0]["prerequisites"] = {"incision"}; }),
      "modules[0].tasks[1].prerequisites[0]: prerequisite cycle: palpation -> incision "
      "-> grasping -> palpation");
}

TEST(CurriculumJson, SharedPrerequisitesAreNotACycle) {
  // incision needs grasping and palpation; grasping needs palpation too: a diamond, no loop.
  const Curriculum curriculum = parse_curriculum(sample_curriculum_json());
  EXPECT_EQ(curriculum.modules[1].tasks[0].prerequisites,
            (std::vector<std::string>{"grasping", "palpation"}));
}

TEST(CurriculumJson, SyntaxErrorIsReportedAtTheRoot) {
  try {
    parse_curriculum_text("{\"name\": ");
    FAIL() << "accepted";
  } catch (const CurriculumError& error) {
    EXPECT_EQ(error.path(), "");
    EXPECT_EQ(std::string(error.what()).rfind("(root): invalid JSON: ", 0), 0u) << error.what();
  }
}

}  // namespace
}  // namespace incise::curriculum
