#pragma once
// Every metric an attempt can be scored on, as a table: its key, the name and unit people read,
// the unit thresholds are entered in, and what it measures. The whole dashboard shows metrics
// through it (GET /api/metrics), so a value reads the same on every page; the metric computations
// (attempt_metrics.h) report exactly these keys, in the units given here (a test holds them equal).
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace incise::curriculum {

struct MetricInfo {
  std::string key;   // "peak_force_n"; a second hand's twin ends in "_left"
  std::string name;  // "Peak force"; "(left hand)" added for the twin
  std::string unit;  // the unit the value is computed and stored in: "N", "m^2", "count", ""
  // How people read it, and enter its thresholds: shown = value * display_scale, in display_unit
  // ("mm²", "%", "s"), rounded to decimals digits after the point.
  std::string display_unit;
  double display_scale = 1;
  int decimals = 0;
  std::string definition;  // one line: what it measures
  // Which way is better: "lower" (a time, a force), "higher" (a share reached), or "" (no
  // direction by itself, e.g. the number of movements).
  std::string better;
  bool per_hand = false;  // has a "_left" twin for the second hand (device 1)
  // The values it can take, in its unit: a threshold outside them is a typing error (a time of
  // -5 s, a share of 1.5).
  double min = 0;
  double max = std::numeric_limits<double>::infinity();
};

// The table, in the order the dashboard lists it (the twins not included).
std::span<const MetricInfo> metric_table();

// The metric with this key, a "_left" twin included (its name says so), or nullopt.
std::optional<MetricInfo> find_metric(std::string_view key);

// Every metric, each per-hand one followed by its "_left" twin.
std::vector<MetricInfo> metric_catalogue();

}  // namespace incise::curriculum
