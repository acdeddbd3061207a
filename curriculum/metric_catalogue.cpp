#include "curriculum/metric_catalogue.h"

#include <vector>

namespace incise::curriculum {
namespace {

constexpr std::string_view kLeft = "_left";
constexpr double kInf = std::numeric_limits<double>::infinity();

// key, name, unit, display unit, scale, decimals, definition, better, per hand[, min, max]
const std::vector<MetricInfo>& table() {
  static const std::vector<MetricInfo> rows = {
      {"completion_time_s", "Completion time", "s", "s", 1, 1,
       "Time from the first to the last recorded sample.", "lower", false},
      {"path_length_m", "Path length", "m", "cm", 100, 1,
       "Total distance travelled by the tool tip.", "lower", true},
      {"angular_path_rad", "Angular path", "rad", "°", 57.29577951308232, 0,
       "Total angle through which the tool turned.", "lower", true},
      {"economy_of_motion", "Economy of motion", "", "%", 100, 0,
       "Straight distance from start to end divided by the path length (100 % = a straight line).",
       "higher", true, 0, 1},
      {"movements", "Movements", "count", "", 1, 0,
       "Number of separate movements: the tip sped up after having come to rest.", "", true},
      {"idle_time_s", "Idle time", "s", "s", 1, 1,
       "Time the tip stood still in pauses of at least 0.2 s.", "lower", true},
      {"mean_speed_m_s", "Mean speed", "m/s", "cm/s", 100, 1,
       "Path length divided by the duration of the run.", "", true},
      {"log_dimensionless_jerk", "Smoothness", "", "", 1, 1,
       "Smoothness of the tip's motion (log dimensionless jerk; higher is smoother).", "higher",
       true, -kInf},
      {"peak_force_n", "Peak force", "N", "N", 1, 2, "Largest force on the tool at any sample.",
       "lower", true},
      {"rms_force_n", "RMS force", "N", "N", 1, 2,
       "Root mean square of the force on the tool over time.", "lower", true},
      {"integrated_force_ns", "Force impulse", "N s", "N s", 1, 1,
       "Force on the tool summed over time (impulse of its magnitude).", "lower", true},
      {"contact_time_s", "Contact time", "s", "s", 1, 1,
       "Time the tool touched tissue (force on the tool above 1 mN).", "", false},
      {"jaw_closures", "Jaw closures", "count", "", 1, 0, "Number of times the jaws closed.", "",
       true},
      {"bimanual_dexterity", "Bimanual dexterity", "", "%", 100, 0,
       "Share of the time either hand moved during which both hands moved.", "higher", false, 0, 1},
      {"path_length_ratio", "Path length ratio", "", "", 1, 2,
       "Path length of the left (non-dominant) hand divided by that of the right hand.", "", false},
      {"protected_collisions", "Protected structure entries", "count", "", 1, 0,
       "Number of times the tool tip entered a protected structure (never zones included).",
       "lower", false},
      {"never_events", "Never events", "count", "", 1, 0,
       "Number of never events: a never zone entered, the never-event force exceeded or a "
       "protected structure cut.",
       "lower", false},
      {"tissue_damage_ns", "Tissue overload", "N s", "N s", 1, 2,
       "Force above the task's safe force summed over time: how long and how far the tissue was "
       "overloaded.",
       "lower", false},
      {"tissue_contact_s", "Tools on the tissue", "s", "s", 1, 1,
       "Time the tools touched the tissue, each tool's time added up: proof the task was done.",
       "higher", false},
      {"targets_visited", "Targets reached", "count", "", 1, 0,
       "Number of distinct targets the tool tip reached.", "higher", false},
      {"targets_fraction", "Share of targets reached", "", "%", 100, 0,
       "Share of the task's targets reached (100 % when the task has none).", "higher", false, 0,
       1},
      {"max_depth_m", "Deepest insertion", "m", "mm", 1000, 1,
       "Deepest insertion of the tool tip along its shaft beyond the portal.", "", true},
      {"mean_depth_m", "Mean insertion", "m", "mm", 1000, 1,
       "Time-averaged insertion of the tool tip along its shaft beyond the portal.", "", true},
      {"sim_damage_index", "Tissue damaged", "", "%", 100, 1,
       "Share of the tissue's volume the simulation strained beyond its damage threshold (max "
       "principal Green strain).",
       "lower", false, 0, 1},
      {"sim_peak_strain", "Peak strain", "", "", 1, 2,
       "Largest principal Green strain of any tissue element in the simulation.", "lower", false},
      {"cut_area_m2", "Cut area", "m^2", "mm²", 1e6, 0,
       "Area the scalpel cut (rest area of the cut surface, one side); surgical scenes.", "",
       false},
      {"cut_on_line_m2", "Cut on the line", "m^2", "mm²", 1e6, 0,
       "Area cut inside the marked line's band (the completion criterion of a cutting task); "
       "surgical scenes.",
       "higher", false},
      {"cut_on_target_fraction", "Cut on target", "", "%", 100, 0,
       "Share of the cut area within the marked line's band (0 without a cut); surgical scenes.",
       "higher", false, 0, 1},
      {"cut_mean_distance_m", "Mean distance from the line", "m", "mm", 1000, 1,
       "Area-weighted mean distance of the cut surface from the marked line; surgical scenes.",
       "lower", false},
      {"cut_max_distance_m", "Largest distance from the line", "m", "mm", 1000, 1,
       "Largest distance of any cut face from the marked line; surgical scenes.", "lower", false},
      {"sim_never_events", "Protected structures cut", "count", "", 1, 0,
       "Protected structures the scalpel cut (a never event; also counted in never events).",
       "lower", false},
  };
  return rows;
}

MetricInfo left_twin(MetricInfo info) {
  info.key += kLeft;
  info.name += " (left hand)";
  info.definition += " Left hand.";
  info.per_hand = false;
  return info;
}

}  // namespace

std::span<const MetricInfo> metric_table() {
  return table();
}

std::optional<MetricInfo> find_metric(std::string_view key) {
  for (const MetricInfo& info : table()) {
    if (info.key == key) return info;
  }
  if (key.ends_with(kLeft)) {
    const auto base = find_metric(key.substr(0, key.size() - kLeft.size()));
    if (base && base->per_hand) return left_twin(*base);
  }
  return std::nullopt;
}

std::vector<MetricInfo> metric_catalogue() {
  std::vector<MetricInfo> all;
  for (const MetricInfo& info : table()) {
    all.push_back(info);
    if (info.per_hand) all.push_back(left_twin(info));
  }
  return all;
}

}  // namespace incise::curriculum
