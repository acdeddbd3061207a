#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace incise::curriculum {

// How a measured value must compare with its pass threshold. The boundary value passes.
enum class ThresholdOp {
  at_most,   // "<=": e.g. completion time, path length, peak force
  at_least,  // ">=": e.g. fraction of targets reached
};

// "<=" for at_most, ">=" for at_least: the spelling curricula use in JSON.
std::string_view threshold_op_symbol(ThresholdOp op);

struct Threshold {
  ThresholdOp op = ThresholdOp::at_most;
  double value = 0.0;  // in the metric's unit

  bool operator==(const Threshold&) const = default;
};

// One metric a task is scored on, e.g. {"peak_force_n", {at_most, 4.0}, "N"}. The key names a
// value the metrics computation reports for every attempt.
struct MetricRequirement {
  std::string key;
  Threshold threshold;
  std::string unit;  // for display only: "s", "m", "N"; empty for counts and ratios

  bool operator==(const MetricRequirement&) const = default;
};

// A sphere of the scene a task cares about, in scene coordinates: a structure the tool tip must
// keep out of (a protected zone, e.g. a vessel beside the target) or a landmark it must visit (a
// target, e.g. a spot to inspect in an arthroscopy).
struct Zone {
  std::string name;  // shown in events and results, e.g. "vessel"
  std::array<double, 3> center_m{};
  double radius_m = 0;  // > 0
  // Drawn in the trainee's picture (a translucent ball: a target green, a protected structure
  // amber, a never-zone red); hidden by default, when finding it is part of the skill.
  bool visible = false;

  bool operator==(const Zone&) const = default;
};

// A protected zone: entering it is a collision; entering a zone marked never is a never event,
// which fails the attempt outright whatever its metrics.
struct ProtectedZone {
  Zone zone;
  bool never = false;

  bool operator==(const ProtectedZone&) const = default;
};

// What an attempt must have done to count, whatever its metrics: a task that can be passed without
// doing it proves nothing. Each criterion set here is scored as one more requirement on a metric
// every attempt reports (completion_requirements, metrics.h), and the result shows it apart from
// the thresholds. Zero (false) leaves a criterion out.
struct Completion {
  // The tools on the tissue at least this long, all tools together (tissue_contact_s) [s].
  double min_contact_s = 0;
  // Every one of the task's targets reached (targets_fraction = 1).
  bool all_targets = false;
  // At least this area cut inside the marked line's band (cut_on_line_m2) [m^2].
  double min_cut_on_line_m2 = 0;

  bool operator==(const Completion&) const = default;
};

// One exercise: a scene to run, the tools it needs, and the metric thresholds an attempt must
// meet. A task is mastered after consecutive_passes_required passing attempts in a row.
struct Task {
  std::string key;                 // unique within the curriculum; prerequisites refer to it
  std::string name;                // shown to trainees
  std::string scene;               // scene file id, e.g. "scenes/palpation.json"
  std::string instructions;        // shown before and during the attempt
  std::vector<std::string> tools;  // tool ids the station must provide, e.g. "probe"
  std::vector<MetricRequirement> metrics;
  Completion completion;
  // The kind of station the task needs ("bench", "laparoscopy", "arthroscopy": what its devices
  // and scenes are); empty: any station.
  std::string station_kind;
  int consecutive_passes_required = 1;
  std::vector<std::string> prerequisites;  // keys of tasks to master first
  std::vector<ProtectedZone> protected_zones;
  std::vector<Zone> targets;  // landmarks to visit (targets_visited, target events)
  // Force on tissue above which it is overloaded (tissue_damage_ns accumulates the excess) [N].
  double safe_force_n = 3.0;
  // A force above this is a never event (tearing); 0: no such limit [N].
  double never_force_n = 0.0;
  // Where the tools enter the body (the trocar, the fulcrum of a laparoscopic shaft), in scene
  // coordinates; when set, each hand's depth along its shaft is measured from it (run_events.h).
  std::optional<std::array<double, 3>> portal_m;
  // A named material (docs/calibration.md: saved from a tissue calibration) the scene runs with in
  // place of its own constants; empty: the scene's. The server checks that it exists and fits.
  std::string material;

  // True if something in this task can be a never event (a never zone or a never force).
  bool has_never_events() const;

  bool operator==(const Task&) const = default;
};

// A group of related tasks, shown together.
struct Module {
  std::string key;  // unique within the curriculum
  std::string name;
  std::vector<Task> tasks;

  bool operator==(const Module&) const = default;
};

struct Curriculum {
  std::string name;
  std::string description;
  std::vector<Module> modules;

  bool operator==(const Curriculum&) const = default;
};

// The task with this key in any module, or nullptr.
const Task* find_task(const Curriculum& curriculum, std::string_view key);

}  // namespace incise::curriculum
