#pragma once

// The session's damage metrics as one snapshot of plain numbers, and the same as
// a stable list of {name, unit, value} rows for the live metrics stream and the scoring side. The
// rows' names, units and order are a contract: scoring rules and recorded sessions refer to them,
// so a metric is only ever appended, never renamed or reordered. The tracker that fills the
// snapshot is damage_tracker.h; docs/damage.md defines every metric.

#include <array>
#include <cstddef>
#include <string_view>

#include "sim/core/types.h"

namespace incise::sim::tools {

struct DamageMetrics {
  // Tissue strain (max principal Green strain against each label's threshold).
  Real peak_strain = 0;              // [-] largest strain any tracked element reached
  Real peak_strain_ratio = 0;        // [-] largest (element peak / its label's threshold)
  int overstrained_elements = 0;     // [count] elements over their threshold at the last step
  int damaged_elements = 0;          // [count] alive elements that ever exceeded their threshold
  Real damaged_volume = 0;           // [m^3] rest volume of those elements
  Real tracked_volume = 0;           // [m^3] rest volume of all alive elements of tracked labels
  Real damage_index = 0;             // [-] damaged_volume / tracked_volume
  Real max_label_damage_index = 0;   // [-] the worst label's damaged / label volume
  Real max_time_over_threshold = 0;  // [s] longest time one element spent over its threshold

  // Cuts against the marked target (areas are rest areas of the cut surface, one side).
  int cut_events = 0;                // [count] record_cut calls with at least one crack face
  Real cut_area = 0;                 // [m^2] all cuts
  Real cut_area_outside_target = 0;  // [m^2] crack faces whose centroid is off the band
  Real cut_mean_distance = 0;        // [m] area-weighted mean distance of crack faces to target
  Real cut_max_distance = 0;         // [m] largest crack face centroid distance to target
  Real protected_cut_area = 0;       // [m^2] cut area inside tets of protected labels
  bool never_event = false;          // a protected label was cut: the attempt fails outright

  // Tool contacts with protected structures (rigid bodies or tissue labels).
  int protected_collisions = 0;         // [count] rising edges of contact, over all structures
  Real protected_contact_time = 0;      // [s] time touching at least one protected structure
  Real protected_peak_penetration = 0;  // [m] deepest contact with a protected structure
};

// One metric for the scoring side: name (snake_case, stable), unit ("1" for a ratio, "count",
// "flag" for 0/1, else SI) and value.
struct MetricRow {
  std::string_view name;
  std::string_view unit;
  Real value = 0;
};

inline constexpr std::size_t kDamageMetricCount = 19;

// Every field of metrics, in declaration order, as rows (counts and the flag as numbers).
// Allocates nothing.
std::array<MetricRow, kDamageMetricCount> metric_rows(const DamageMetrics& metrics);

}  // namespace incise::sim::tools
