#include "curriculum/curriculum_json.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "curriculum/curriculum_validation.h"

namespace incise::curriculum {
namespace {

using nlohmann::json;

std::string member(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string element(const std::string& path, std::size_t index) {
  return path + "[" + std::to_string(index) + "]";
}

enum class Presence { required, optional };
constexpr Presence required = Presence::required;
constexpr Presence optional = Presence::optional;

// One JSON object being read: checks that it is an object with no members outside `allowed`,
// and reads typed members, reporting problems at their paths.
class ObjectReader {
 public:
  ObjectReader(const json& object, std::string path,
               std::initializer_list<std::string_view> allowed)
      : object_(object), path_(std::move(path)) {
    if (!object_.is_object()) throw CurriculumError(path_, "must be an object");
    for (const auto& item : object_.items()) {
      if (std::find(allowed.begin(), allowed.end(), item.key()) != allowed.end()) continue;
      std::string expected;
      for (const std::string_view name : allowed) {
        expected += (expected.empty() ? "" : ", ") + std::string(name);
      }
      throw CurriculumError(member(path_, item.key()),
                            "unknown key (expected one of: " + expected + ")");
    }
  }

  std::string path(std::string_view key) const { return member(path_, key); }

  // The member's value, or nullptr if it is absent and optional.
  const json* find(std::string_view key, Presence presence) const {
    const auto it = object_.find(key);
    if (it != object_.end()) return &*it;
    if (presence == required) throw CurriculumError(path(key), "is required");
    return nullptr;
  }

  std::string string(std::string_view key, Presence presence) const {
    const json* value = find(key, presence);
    if (value == nullptr) return {};
    if (!value->is_string()) throw CurriculumError(path(key), "must be a string");
    return value->get<std::string>();
  }

  // The member's elements; empty if it is absent and optional.
  const json::array_t& array(std::string_view key, Presence presence) const {
    static const json::array_t none;
    const json* value = find(key, presence);
    if (value == nullptr) return none;
    if (!value->is_array()) throw CurriculumError(path(key), "must be an array");
    return value->get_ref<const json::array_t&>();
  }

  // The member's number, or #fallback if it is absent and optional.
  double number(std::string_view key, Presence presence, double fallback = 0) const {
    const json* value = find(key, presence);
    if (value == nullptr) return fallback;
    if (!value->is_number()) throw CurriculumError(path(key), "must be a number");
    return value->get<double>();
  }

  // The member's truth value; false if it is absent and optional.
  bool boolean(std::string_view key, Presence presence) const {
    const json* value = find(key, presence);
    if (value == nullptr) return false;
    if (!value->is_boolean()) throw CurriculumError(path(key), "must be true or false");
    return value->get<bool>();
  }

  std::vector<std::string> strings(std::string_view key, Presence presence) const {
    const json::array_t& values = array(key, presence);
    std::vector<std::string> result;
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (!values[i].is_string()) throw CurriculumError(element(path(key), i), "must be a string");
      result.push_back(values[i].get<std::string>());
    }
    return result;
  }

 private:
  const json& object_;
  std::string path_;
};

Threshold parse_threshold(const json& value, const std::string& path) {
  const ObjectReader reader(value, path, {"op", "value"});
  Threshold threshold;
  const json& op = *reader.find("op", required);
  if (op == "<=") {
    threshold.op = ThresholdOp::at_most;
  } else if (op == ">=") {
    threshold.op = ThresholdOp::at_least;
  } else {
    throw CurriculumError(reader.path("op"), "must be \"<=\" or \">=\"");
  }
  const json& number = *reader.find("value", required);
  if (!number.is_number()) throw CurriculumError(reader.path("value"), "must be a number");
  threshold.value = number.get<double>();
  return threshold;
}

MetricRequirement parse_metric(const json& value, const std::string& path) {
  const ObjectReader reader(value, path, {"key", "threshold", "unit"});
  MetricRequirement metric;
  metric.key = reader.string("key", required);
  metric.threshold = parse_threshold(*reader.find("threshold", required), reader.path("threshold"));
  metric.unit = reader.string("unit", optional);
  return metric;
}

// A point in scene coordinates: exactly three numbers (finiteness is validate()'s).
std::array<double, 3> parse_point(const json& value, const std::string& path) {
  if (!value.is_array() || value.size() != 3)
    throw CurriculumError(path, "must be an array of 3 numbers");
  std::array<double, 3> point{};
  for (std::size_t i = 0; i < 3; ++i) {
    if (!value[i].is_number()) throw CurriculumError(element(path, i), "must be a number");
    point[i] = value[i].get<double>();
  }
  return point;
}

// The members a protected zone shares with a target.
Zone parse_zone(const ObjectReader& reader) {
  Zone zone;
  zone.name = reader.string("name", required);
  zone.center_m = parse_point(*reader.find("center_m", required), reader.path("center_m"));
  zone.radius_m = reader.number("radius_m", required);
  zone.visible = reader.boolean("visible", optional);
  return zone;
}

ProtectedZone parse_protected_zone(const json& value, const std::string& path) {
  const ObjectReader reader(value, path, {"name", "center_m", "radius_m", "visible", "never"});
  ProtectedZone zone;
  zone.zone = parse_zone(reader);
  zone.never = reader.boolean("never", optional);
  return zone;
}

Zone parse_target(const json& value, const std::string& path) {
  return parse_zone(ObjectReader(value, path, {"name", "center_m", "radius_m", "visible"}));
}

json zone_json(const Zone& zone) {
  json item = {{"name", zone.name}, {"center_m", zone.center_m}, {"radius_m", zone.radius_m}};
  if (zone.visible) item["visible"] = true;  // absent: hidden (curricula written before it)
  return item;
}

Completion parse_completion(const json& value, const std::string& path) {
  const ObjectReader reader(value, path, {"min_contact_s", "all_targets", "min_cut_on_line_m2"});
  Completion completion;
  completion.min_contact_s = reader.number("min_contact_s", optional);
  completion.all_targets = reader.boolean("all_targets", optional);
  completion.min_cut_on_line_m2 = reader.number("min_cut_on_line_m2", optional);
  return completion;
}

int parse_consecutive_passes(const json& value, const std::string& path) {
  const std::string message =
      "must be an integer from 1 to " + std::to_string(max_consecutive_passes);
  if (!value.is_number_integer()) throw CurriculumError(path, message);
  // Compared before narrowing to int, so that huge values cannot wrap into range.
  const bool in_range = value.is_number_unsigned()
                            ? value.get<std::uint64_t>() <= max_consecutive_passes
                            : value.get<std::int64_t>() <= max_consecutive_passes;
  if (!in_range || value.get<std::int64_t>() < 1) throw CurriculumError(path, message);
  return value.get<int>();
}

Task parse_task(const json& value, const std::string& path) {
  const ObjectReader reader(
      value, path,
      {"key", "name", "scene", "station_kind", "instructions", "tools", "metrics", "completion",
       "consecutive_passes_required", "prerequisites", "protected_zones", "targets", "safe_force_n",
       "never_force_n", "portal_m", "material"});
  Task task;
  task.key = reader.string("key", required);
  task.name = reader.string("name", required);
  task.scene = reader.string("scene", required);
  task.station_kind = reader.string("station_kind", optional);
  task.material = reader.string("material", optional);
  task.instructions = reader.string("instructions", optional);
  task.tools = reader.strings("tools", optional);
  const json::array_t& metrics = reader.array("metrics", required);
  for (std::size_t i = 0; i < metrics.size(); ++i) {
    task.metrics.push_back(parse_metric(metrics[i], element(reader.path("metrics"), i)));
  }
  if (const json* completion = reader.find("completion", optional))
    task.completion = parse_completion(*completion, reader.path("completion"));
  task.consecutive_passes_required =
      parse_consecutive_passes(*reader.find("consecutive_passes_required", required),
                               reader.path("consecutive_passes_required"));
  task.prerequisites = reader.strings("prerequisites", optional);
  const json::array_t& zones = reader.array("protected_zones", optional);
  for (std::size_t i = 0; i < zones.size(); ++i) {
    task.protected_zones.push_back(
        parse_protected_zone(zones[i], element(reader.path("protected_zones"), i)));
  }
  const json::array_t& targets = reader.array("targets", optional);
  for (std::size_t i = 0; i < targets.size(); ++i) {
    task.targets.push_back(parse_target(targets[i], element(reader.path("targets"), i)));
  }
  task.safe_force_n = reader.number("safe_force_n", optional, Task{}.safe_force_n);
  task.never_force_n = reader.number("never_force_n", optional, Task{}.never_force_n);
  if (const json* portal = reader.find("portal_m", optional))
    task.portal_m = parse_point(*portal, reader.path("portal_m"));
  return task;
}

Module parse_module(const json& value, const std::string& path) {
  const ObjectReader reader(value, path, {"key", "name", "tasks"});
  Module module;
  module.key = reader.string("key", required);
  module.name = reader.string("name", required);
  const json::array_t& tasks = reader.array("tasks", required);
  for (std::size_t i = 0; i < tasks.size(); ++i) {
    module.tasks.push_back(parse_task(tasks[i], element(reader.path("tasks"), i)));
  }
  return module;
}

}  // namespace

Curriculum parse_curriculum(const json& value) {
  const ObjectReader reader(value, "", {"name", "description", "modules"});
  Curriculum curriculum;
  curriculum.name = reader.string("name", required);
  curriculum.description = reader.string("description", optional);
  const json::array_t& modules = reader.array("modules", required);
  for (std::size_t i = 0; i < modules.size(); ++i) {
    curriculum.modules.push_back(parse_module(modules[i], element("modules", i)));
  }
  validate(curriculum);
  return curriculum;
}

Curriculum parse_curriculum_text(std::string_view text) {
  json value;
  try {
    value = json::parse(text);
  } catch (const json::exception& error) {
    // A syntax error, or a number beyond a double's range (out_of_range 406).
    throw CurriculumError("", std::string("invalid JSON: ") + error.what());
  }
  return parse_curriculum(value);
}

json to_json(const Curriculum& curriculum) {
  json modules = json::array();
  for (const Module& module : curriculum.modules) {
    json tasks = json::array();
    for (const Task& task : module.tasks) {
      json metrics = json::array();
      for (const MetricRequirement& metric : task.metrics) {
        metrics.push_back({{"key", metric.key},
                           {"threshold",
                            {{"op", std::string(threshold_op_symbol(metric.threshold.op))},
                             {"value", metric.threshold.value}}},
                           {"unit", metric.unit}});
      }
      json zones = json::array();
      for (const ProtectedZone& zone : task.protected_zones) {
        json item = zone_json(zone.zone);
        item["never"] = zone.never;
        zones.push_back(std::move(item));
      }
      json targets = json::array();
      for (const Zone& target : task.targets)
        targets.push_back(zone_json(target));
      tasks.push_back({{"key", task.key},
                       {"name", task.name},
                       {"scene", task.scene},
                       {"instructions", task.instructions},
                       {"tools", task.tools},
                       {"metrics", metrics},
                       {"consecutive_passes_required", task.consecutive_passes_required},
                       {"prerequisites", task.prerequisites},
                       {"protected_zones", zones},
                       {"targets", targets},
                       {"safe_force_n", task.safe_force_n},
                       {"never_force_n", task.never_force_n}});
      if (task.portal_m) tasks.back()["portal_m"] = *task.portal_m;
      // Absent when unset, as curricula written before them leave them out.
      if (!task.station_kind.empty()) tasks.back()["station_kind"] = task.station_kind;
      if (!task.material.empty()) tasks.back()["material"] = task.material;
      const Completion& c = task.completion;
      if (c != Completion{}) {
        json completion = json::object();
        if (c.min_contact_s > 0) completion["min_contact_s"] = c.min_contact_s;
        if (c.all_targets) completion["all_targets"] = true;
        if (c.min_cut_on_line_m2 > 0) completion["min_cut_on_line_m2"] = c.min_cut_on_line_m2;
        tasks.back()["completion"] = std::move(completion);
      }
    }
    modules.push_back({{"key", module.key}, {"name", module.name}, {"tasks", tasks}});
  }
  return {{"name", curriculum.name}, {"description", curriculum.description}, {"modules", modules}};
}

}  // namespace incise::curriculum
